// Exact rasterisation of a WorldSlice into an occupancy image, and map_server output.
//
// Everything is done in cell units (u, v) = (p − origin) / resolution, where cell (i, j) is the
// open square (i, i+1) × (j, j+1). Coordinates within 1e-7 cells of an integer are snapped to it so
// that walls built on the resolution's multiples do not bleed into the neighbouring cell through
// rounding.
#include "minibot3d_sim/world_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <stdexcept>

#include "minibot3d_map_io/map_io.h"

namespace minibot3d_sim {
namespace {

constexpr double kSnap = 1e-7;
constexpr double kMaxCells = 1e8;

double RoundToSignificant(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*g", digits, x);
  return std::strtod(buf, nullptr);
}

double Snap(double x) {
  const double r = std::round(x);
  return std::abs(x - r) < kSnap ? r : x;
}

bool IsInteger(double x) { return x == std::floor(x); }

struct Raster {
  int w, h;
  std::vector<std::uint8_t>* occ;
  void Mark(int i, int j) {
    if (i >= 0 && i < w && j >= 0 && j < h) (*occ)[static_cast<std::size_t>(j) * w + i] = 1;
  }
  bool Get(int i, int j) const {
    return i >= 0 && i < w && j >= 0 && j < h && (*occ)[static_cast<std::size_t>(j) * w + i];
  }
};

// A segment in cell units.
struct Seg {
  double ua, va, ub, vb;
};

// Fills, row by row, the cells whose centre lies inside the closed outline(s) formed by one shape's
// segments (even-odd rule). Rows with an odd number of crossings belong to an open outline (a lone
// wall, a mesh with holes) and are left to the segment pass.
void FillShape(const std::vector<Seg>& segs, Raster* raster) {
  double vmin = std::numeric_limits<double>::infinity(), vmax = -vmin;
  for (const Seg& s : segs) {
    vmin = std::min({vmin, s.va, s.vb});
    vmax = std::max({vmax, s.va, s.vb});
  }
  const int j0 = std::max(0, static_cast<int>(std::floor(vmin - 0.5)));
  const int j1 = std::min(raster->h - 1, static_cast<int>(std::ceil(vmax - 0.5)));
  std::vector<double> xs;
  for (int j = j0; j <= j1; ++j) {
    const double v = j + 0.5;
    xs.clear();
    for (const Seg& s : segs) {
      // Half-open in v, so a vertex on the row is counted once.
      if ((s.va <= v) != (s.vb <= v)) {
        xs.push_back(s.ua + (v - s.va) / (s.vb - s.va) * (s.ub - s.ua));
      }
    }
    if (xs.empty() || xs.size() % 2 != 0) continue;
    std::sort(xs.begin(), xs.end());
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
      const int i0 = static_cast<int>(std::ceil(xs[k] - 0.5));
      const int i1 = static_cast<int>(std::floor(xs[k + 1] - 0.5));
      for (int i = std::max(0, i0); i <= std::min(raster->w - 1, i1); ++i) raster->Mark(i, j);
    }
  }
}

// Marks the cells whose open interior the segment passes through. A segment lying on a grid line
// passes through none; it is returned in *on_grid_line for the last pass.
void MarkSegment(const Seg& s, Raster* raster, std::vector<Seg>* on_grid_line) {
  if (s.ua == s.ub && s.va == s.vb) return;  // a point has no extent to mark
  if (s.va == s.vb) {
    if (IsInteger(s.va)) {
      on_grid_line->push_back(s);
      return;
    }
    const int j = static_cast<int>(std::floor(s.va));
    const double u0 = std::min(s.ua, s.ub), u1 = std::max(s.ua, s.ub);
    for (int i = static_cast<int>(std::floor(u0)); i <= static_cast<int>(std::ceil(u1)) - 1; ++i) {
      raster->Mark(i, j);
    }
    return;
  }
  const double vmin = std::min(s.va, s.vb), vmax = std::max(s.va, s.vb);
  for (int j = static_cast<int>(std::floor(vmin)); j <= static_cast<int>(std::ceil(vmax)) - 1;
       ++j) {
    // The part of the segment within the row band [j, j+1].
    const double v0 = std::max(vmin, static_cast<double>(j));
    const double v1 = std::min(vmax, static_cast<double>(j + 1));
    const double du_dv = (s.ub - s.ua) / (s.vb - s.va);
    const double ua = Snap(s.ua + (v0 - s.va) * du_dv);
    const double ub = Snap(s.ua + (v1 - s.va) * du_dv);
    const double u0 = std::min(ua, ub), u1 = std::max(ua, ub);
    if (u0 == u1) {
      if (IsInteger(u0)) {
        on_grid_line->push_back(Seg{u0, v0, u1, v1});
      } else {
        raster->Mark(static_cast<int>(std::floor(u0)), j);
      }
      continue;
    }
    for (int i = static_cast<int>(std::floor(u0)); i <= static_cast<int>(std::ceil(u1)) - 1; ++i) {
      raster->Mark(i, j);
    }
  }
}

// A segment on a grid line marks the cell on its +x/+y side, unless a cell on either side is already
// occupied (then it is the face of something solid and marking more would thicken it).
void MarkGridLineSegment(const Seg& s, Raster* raster) {
  if (s.ua == s.ub) {  // vertical, on the line u = s.ua
    const int line = static_cast<int>(s.ua);
    const double vmin = std::min(s.va, s.vb), vmax = std::max(s.va, s.vb);
    for (int j = static_cast<int>(std::floor(vmin)); j <= static_cast<int>(std::ceil(vmax)) - 1;
         ++j) {
      if (!raster->Get(line - 1, j) && !raster->Get(line, j)) {
        raster->Mark(line < raster->w ? line : line - 1, j);
      }
    }
  } else {  // horizontal, on the line v = s.va
    const int line = static_cast<int>(s.va);
    const double umin = std::min(s.ua, s.ub), umax = std::max(s.ua, s.ub);
    for (int i = static_cast<int>(std::floor(umin)); i <= static_cast<int>(std::ceil(umax)) - 1;
         ++i) {
      if (!raster->Get(i, line - 1) && !raster->Get(i, line)) {
        raster->Mark(i, line < raster->h ? line : line - 1);
      }
    }
  }
}

}  // namespace

OccupancyImage RenderSlice(const WorldSlice& slice, double resolution, double margin) {
  if (!(resolution > 0.0) || !std::isfinite(resolution)) {
    throw std::invalid_argument("RenderSlice: resolution must be positive");
  }
  if (!(margin >= 0.0) || !std::isfinite(margin)) {
    throw std::invalid_argument("RenderSlice: margin must be non-negative");
  }
  if (slice.segments().empty() && slice.circles().empty()) {
    throw std::invalid_argument("RenderSlice: the world has no geometry at height " +
                                std::to_string(slice.height()));
  }
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const Segment2& s : slice.segments()) {
    lo = lo.cwiseMin(s.a).cwiseMin(s.b);
    hi = hi.cwiseMax(s.a).cwiseMax(s.b);
  }
  for (const Circle2& c : slice.circles()) {
    lo = lo.cwiseMin(c.center - Eigen::Vector2d::Constant(c.radius));
    hi = hi.cwiseMax(c.center + Eigen::Vector2d::Constant(c.radius));
  }
  OccupancyImage image;
  image.resolution = resolution;
  // Snapped to multiples of the resolution so that walls on round coordinates fill whole cells.
  image.origin = Eigen::Vector2d(std::floor(Snap((lo.x() - margin) / resolution)) * resolution,
                                 std::floor(Snap((lo.y() - margin) / resolution)) * resolution);
  const double cols = std::ceil(Snap((hi.x() + margin - image.origin.x()) / resolution));
  const double rows = std::ceil(Snap((hi.y() + margin - image.origin.y()) / resolution));
  if (cols * rows > kMaxCells) {
    throw std::invalid_argument("RenderSlice: map of " + std::to_string(cols) + " x " +
                                std::to_string(rows) + " cells is too large");
  }
  image.width = std::max(1, static_cast<int>(cols));
  image.height = std::max(1, static_cast<int>(rows));
  image.occupied.assign(static_cast<std::size_t>(image.width) * image.height, 0);
  Raster raster{image.width, image.height, &image.occupied};

  auto to_cells = [&](const Segment2& s) {
    return Seg{Snap((s.a.x() - image.origin.x()) / resolution),
               Snap((s.a.y() - image.origin.y()) / resolution),
               Snap((s.b.x() - image.origin.x()) / resolution),
               Snap((s.b.y() - image.origin.y()) / resolution)};
  };
  std::map<int, std::vector<Seg>> by_shape;
  for (const Segment2& s : slice.segments()) by_shape[s.shape].push_back(to_cells(s));
  for (const auto& kv : by_shape) FillShape(kv.second, &raster);

  std::vector<Seg> on_grid_line;
  for (const auto& kv : by_shape) {
    for (const Seg& s : kv.second) MarkSegment(s, &raster, &on_grid_line);
  }
  for (const Circle2& c : slice.circles()) {
    const double cu = (c.center.x() - image.origin.x()) / resolution;
    const double cv = (c.center.y() - image.origin.y()) / resolution;
    const double r = c.radius / resolution;
    const int i0 = std::max(0, static_cast<int>(std::floor(cu - r)));
    const int i1 = std::min(image.width - 1, static_cast<int>(std::floor(cu + r)));
    const int j0 = std::max(0, static_cast<int>(std::floor(cv - r)));
    const int j1 = std::min(image.height - 1, static_cast<int>(std::floor(cv + r)));
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        // The open cell meets the closed disc iff the nearest point of the closed cell is
        // strictly within r.
        const double nu = std::clamp(cu, static_cast<double>(i), static_cast<double>(i + 1));
        const double nv = std::clamp(cv, static_cast<double>(j), static_cast<double>(j + 1));
        if ((nu - cu) * (nu - cu) + (nv - cv) * (nv - cv) < r * r) raster.Mark(i, j);
      }
    }
  }
  for (const Seg& s : on_grid_line) MarkGridLineSegment(s, &raster);
  return image;
}

void WriteMapServerFiles(const OccupancyImage& image, const std::string& out_basename) {
  if (image.width <= 0 || image.height <= 0 ||
      image.occupied.size() != static_cast<std::size_t>(image.width) * image.height) {
    throw std::invalid_argument(out_basename + ": occupancy image is empty or inconsistent");
  }
  minibot3d_map_io::OccupancyGrid grid;
  grid.resolution = image.resolution;
  // The origin is a multiple of the resolution computed in floating point (-73 * 0.05 =
  // -3.6500000000000004); 12 significant digits give the value meant, which is what the map
  // files have always said.
  grid.origin_x = RoundToSignificant(image.origin.x(), 12);
  grid.origin_y = RoundToSignificant(image.origin.y(), 12);
  grid.origin_theta = 0.0;
  grid.width = image.width;
  grid.height = image.height;
  grid.data.resize(image.occupied.size());
  for (std::size_t k = 0; k < image.occupied.size(); ++k) {
    grid.data[k] = image.occupied[k] ? 100 : 0;  // same row order: row 0 at the lowest y
  }
  minibot3d_map_io::SaveOptions options;
  options.pgm_comment = "minibot3d_sim ground-truth map";
  options.explain_grey_levels = false;  // 0 and 254 only
  minibot3d_map_io::SaveMap(grid, out_basename, options);
}

}  // namespace minibot3d_sim
