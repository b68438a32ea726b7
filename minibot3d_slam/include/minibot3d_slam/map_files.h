// minibot3d_slam's maps on disk: minibot3d_map_io's reader and writer, with the PGM comment
// map_saver and slam_offline write ("CREATOR: minibot3d_slam map_io RESOLUTION m/pix"), part of
// the file: saved maps are compared byte for byte.
#ifndef MINIBOT3D_SLAM_MAP_FILES_H_
#define MINIBOT3D_SLAM_MAP_FILES_H_

#include <string>

#include "minibot3d_map_io/file_util.h"
#include "minibot3d_map_io/map_io.h"
#include "minibot3d_slam/types.h"

namespace minibot3d_slam {

// map_saver's --occ / --free in percent.
inline minibot3d_map_io::SaveOptions SlamMapSaveOptions(const GridMap& map,
                                                        int occupied_percent = 65,
                                                        int free_percent = 25) {
  minibot3d_map_io::SaveOptions options;
  options.occupied_percent = occupied_percent;
  options.free_percent = free_percent;
  options.pgm_comment =
      "CREATOR: minibot3d_slam map_io " + minibot3d_map_io::FormatDouble(map.resolution) + " m/pix";
  return options;
}

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_MAP_FILES_H_
