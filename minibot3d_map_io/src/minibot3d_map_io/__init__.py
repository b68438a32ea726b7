"""Maps on disk in ROS map_server's format (YAML + image): the workspace's one Python reader and
writer, the twin of the C++ library of this package. See map_io.py."""
from minibot3d_map_io.map_io import (MapIoError, OccupancyGrid, format_double, load_map,  # noqa: F401
                                     read_image, save_map, write_atomically)
