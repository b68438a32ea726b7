// Ground-truth occupancy maps rendered from a world slice, written in map_server format.
//
// A cell is occupied when the open square of the cell meets the slice's geometry: a segment passing
// through its interior, a circle's disc overlapping it, or the cell centre lying inside a closed
// outline (each shape's segments filled by the even-odd rule along the row through the cell
// centres). All of it is computed exactly per cell, not by sampling. A segment lying exactly on a
// grid line, with no occupied cell on either side, marks the cell on its +x / +y side so that a
// zero-thickness wall never vanishes.
#ifndef MINIBOT3D_SIM_WORLD_MAP_H_
#define MINIBOT3D_SIM_WORLD_MAP_H_

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "minibot3d_sim/world_slice.h"

namespace minibot3d_sim {

struct OccupancyImage {
  int width = 0;
  int height = 0;
  double resolution = 0.05;
  // World position of the lower-left corner of cell (0, 0).
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  // Row-major, row 0 at the lowest y (as nav_msgs/OccupancyGrid); 1 = occupied, 0 = free.
  std::vector<std::uint8_t> occupied;

  bool at(int col, int row) const {
    return occupied[static_cast<std::size_t>(row) * width + col] != 0;
  }
};

// Rasterises `slice` over the bounds of its geometry grown by `margin`, with the origin snapped to
// a multiple of `resolution`. Throws std::invalid_argument for a non-positive resolution, a negative
// margin, an empty slice, or a map of more than 10^8 cells.
OccupancyImage RenderSlice(const WorldSlice& slice, double resolution, double margin);

// Writes OUT_BASENAME.pgm (binary P5, 0 = occupied, 254 = free, top row = highest y) and
// OUT_BASENAME.yaml (map_server format, image path relative to the yaml) with minibot3d_map_io's
// SaveMap: each file through a temporary file renamed into place. Throws std::runtime_error
// (minibot3d_map_io::MapIoError) naming the file on any I/O failure.
void WriteMapServerFiles(const OccupancyImage& image, const std::string& out_basename);

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_WORLD_MAP_H_
