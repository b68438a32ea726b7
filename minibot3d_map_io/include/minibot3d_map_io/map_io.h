// Maps on disk in ROS map_server's format: NAME.yaml (image, resolution, origin, negate,
// occupied_thresh, free_thresh, optional mode) and an image (PGM written; PGM/PNG/... read).
//
// The one reader and writer of the workspace, so a map file means the same to every tool: the
// simulator's ground-truth renderer, map_server, map_saver, slam_offline and the world loader's
// floor plans all go through it; its Python twin is the module minibot3d_map_io (same semantics,
// same tests).
// ROS-free: yaml-cpp and OpenCV's image codecs only.
//
// Loading follows map_server's image_loader.cpp: a pixel's channels are averaged (alpha too, in
// trinary mode only), negate flips the mean, and p = (255 - mean) / 255 is classified:
//   trinary (default): p > occupied_thresh -> 100, p < free_thresh -> 0, else -1;
//   scale: the same, but in between 99 * (p - free) / (occ - free), and a transparent pixel -1;
//   raw:   the (negated) mean itself, 0..255, stored as int8 (so 255 reads as -1).
// Saving follows map_saver: cells >= occupied_percent are black (0), 0..free_percent white (254),
// everything else grey (205); the YAML's thresholds (0.65, 0.196) read exactly those back.
#ifndef MINIBOT3D_MAP_IO_MAP_IO_H_
#define MINIBOT3D_MAP_IO_MAP_IO_H_

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace minibot3d_map_io {

class MapIoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An occupancy grid as map_server and nav_msgs/OccupancyGrid see it: row-major from the origin
// (the outer corner of cell (0, 0)), x to the right, y up, so row 0 is the image's bottom row;
// values -1 unknown, 0 free .. 100 occupied.
struct OccupancyGrid {
  double resolution = 0.05;  // m per cell
  double origin_x = 0.0, origin_y = 0.0, origin_theta = 0.0;
  int width = 0, height = 0;
  std::vector<std::int8_t> data;
};

// Loads NAME.yaml and its image (a relative image path is relative to the YAML's folder) with
// map_server's semantics (above). Throws MapIoError naming the file and the key or value at
// fault.
OccupancyGrid LoadMap(const std::string& yaml_path);

struct SaveOptions {
  // map_saver's --occ / --free, in percent: 1 <= occupied_percent <= 100,
  // 0 <= free_percent < occupied_percent.
  int occupied_percent = 65;
  int free_percent = 25;
  // The PGM header's comment line, without the '#'; empty writes
  // "CREATOR: minibot3d_map_io <resolution> m/pix".
  std::string pgm_comment;
  // Ends the YAML with a comment line saying which grey levels were written for what.
  bool explain_grey_levels = true;
};

// Writes BASE.pgm (binary P5) and BASE.yaml (the image named relative, so the pair can move
// together), each through a temporary file renamed into place, the image first so that a YAML on
// disk always points at a complete image. Numbers are written as the shortest text that reads
// back as the same double, with a decimal point (0.0, not 0). Throws MapIoError naming the file
// on failure, and for an empty or inconsistent grid or options out of range.
void SaveMap(const OccupancyGrid& map, const std::string& base,
             const SaveOptions& options = SaveOptions());

}  // namespace minibot3d_map_io

#endif  // MINIBOT3D_MAP_IO_MAP_IO_H_
