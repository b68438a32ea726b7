// Maps on disk in map_server's format: NAME.yaml (image, resolution, origin, negate,
// occupied_thresh, free_thresh, optional mode) and an image (PGM written; PGM/PNG read).
#ifndef MINIBOT3D_SLAM_MAP_IO_H_
#define MINIBOT3D_SLAM_MAP_IO_H_

#include <stdexcept>
#include <string>

#include "minibot3d_slam/types.h"

namespace minibot3d_slam {

class MapIoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Loads NAME.yaml and its image (a relative image path is relative to the YAML's folder) with
// map_server's semantics for mode trinary (default) / scale / raw and negate. Throws MapIoError
// naming the file and the key or value at fault.
GridMap LoadMap(const std::string& yaml_path);

// Writes BASE.pgm (0 occupied, 254 free, 205 unknown, as map_saver does) and BASE.yaml, each
// through a temporary file renamed into place. occupied_thresh/free_thresh are the percentages
// map_saver takes (--occ 65 --free 25). Throws MapIoError naming the file on failure.
void SaveMap(const GridMap& map, const std::string& base, int occupied_percent = 65,
             int free_percent = 25);

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_MAP_IO_H_
