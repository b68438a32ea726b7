#include "minibot3d_navigation/costmap/footprint.h"

#include <algorithm>
#include <cmath>
#include <cctype>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "minibot3d_common/line_walker.h"

namespace minibot3d_navigation {
namespace nav {
namespace {

// Parses a number at text[*pos], skipping blanks; throws naming the position.
double ParseNumber(const std::string& text, size_t* pos) {
  while (*pos < text.size() && std::isspace(static_cast<unsigned char>(text[*pos]))) ++*pos;
  const char* begin = text.c_str() + *pos;
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (end == begin) {
    throw std::invalid_argument("footprint \"" + text + "\": expected a number at character " +
                                std::to_string(*pos));
  }
  *pos += static_cast<size_t>(end - begin);
  return v;
}

void Expect(const std::string& text, size_t* pos, char c) {
  while (*pos < text.size() && std::isspace(static_cast<unsigned char>(text[*pos]))) ++*pos;
  if (*pos >= text.size() || text[*pos] != c) {
    throw std::invalid_argument("footprint \"" + text + "\": expected '" + std::string(1, c) +
                                "' at character " + std::to_string(*pos));
  }
  ++*pos;
}

bool Peek(const std::string& text, size_t* pos, char c) {
  while (*pos < text.size() && std::isspace(static_cast<unsigned char>(text[*pos]))) ++*pos;
  return *pos < text.size() && text[*pos] == c;
}

void LineCells(int x0, int y0, int x1, int y1, std::vector<std::pair<int, int>>* cells) {
  for (minibot3d_common::LineWalker w(x0, y0, x1, y1);; w.Next()) {
    cells->emplace_back(w.x(), w.y());
    if (w.done()) break;
  }
}

}  // namespace

Footprint ParseFootprint(const std::string& text) {
  Footprint fp;
  size_t pos = 0;
  Expect(text, &pos, '[');
  while (true) {
    Expect(text, &pos, '[');
    Point2 p;
    p.x = ParseNumber(text, &pos);
    Expect(text, &pos, ',');
    p.y = ParseNumber(text, &pos);
    Expect(text, &pos, ']');
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
      throw std::invalid_argument("footprint \"" + text + "\": point " +
                                  std::to_string(fp.size()) + " is not finite");
    }
    fp.push_back(p);
    if (Peek(text, &pos, ',')) { ++pos; continue; }
    Expect(text, &pos, ']');
    break;
  }
  while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos]))) ++pos;
  if (pos != text.size()) {
    throw std::invalid_argument("footprint \"" + text + "\": unexpected text after the list");
  }
  if (fp.size() < 3) {
    throw std::invalid_argument("footprint \"" + text + "\": needs at least 3 points, got " +
                                std::to_string(fp.size()));
  }
  return fp;
}

std::string FootprintToString(const Footprint& footprint) {
  std::ostringstream out;
  out.precision(17);
  out << "[";
  for (size_t i = 0; i < footprint.size(); ++i) {
    out << (i ? ", " : "") << "[" << footprint[i].x << ", " << footprint[i].y << "]";
  }
  out << "]";
  return out.str();
}

Footprint MakeCircleFootprint(double radius) {
  if (!(radius > 0.0) || !std::isfinite(radius)) {
    throw std::invalid_argument("robot_radius must be a positive number, got " +
                                std::to_string(radius));
  }
  constexpr int kPoints = 16;
  Footprint fp;
  for (int i = 0; i < kPoints; ++i) {
    const double a = 2.0 * kPi * i / kPoints;
    fp.push_back({radius * std::cos(a), radius * std::sin(a)});
  }
  return fp;
}

Footprint PadFootprint(const Footprint& footprint, double padding) {
  Footprint out = footprint;
  for (Point2& p : out) {
    p.x += (p.x > 0.0 ? padding : (p.x < 0.0 ? -padding : 0.0));
    p.y += (p.y > 0.0 ? padding : (p.y < 0.0 ? -padding : 0.0));
  }
  return out;
}

void FootprintRadii(const Footprint& footprint, double* inscribed, double* circumscribed) {
  double min_d = std::numeric_limits<double>::infinity(), max_d = 0.0;
  const Point2 origin;
  for (size_t i = 0; i < footprint.size(); ++i) {
    const Point2& a = footprint[i];
    const Point2& b = footprint[(i + 1) % footprint.size()];
    min_d = std::min(min_d, minibot3d_common::PointSegmentDistance(origin, a, b));
    max_d = std::max(max_d, std::hypot(a.x, a.y));
  }
  if (footprint.empty()) min_d = 0.0;
  *inscribed = min_d;
  *circumscribed = max_d;
}

Footprint TransformFootprint(const Footprint& footprint, const Pose2& pose) {
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  Footprint out;
  out.reserve(footprint.size());
  for (const Point2& p : footprint) {
    out.push_back({pose.x + c * p.x - s * p.y, pose.y + s * p.x + c * p.y});
  }
  return out;
}

void PolygonOutlineCells(const Costmap2D& costmap, const Footprint& polygon,
                         std::vector<std::pair<int, int>>* cells) {
  cells->clear();
  const size_t n = polygon.size();
  for (size_t i = 0; i < n; ++i) {
    int x0, y0, x1, y1;
    costmap.WorldToMapNoBounds(polygon[i].x, polygon[i].y, &x0, &y0);
    costmap.WorldToMapNoBounds(polygon[(i + 1) % n].x, polygon[(i + 1) % n].y, &x1, &y1);
    LineCells(x0, y0, x1, y1, cells);
  }
}

int FootprintCost(const Costmap2D& costmap, const Footprint& footprint, const Pose2& pose) {
  int cx, cy;
  if (!costmap.WorldToMap(pose.x, pose.y, &cx, &cy)) return -1;
  int worst = costmap.cost(cx, cy);
  if (worst == kLethalObstacle) return worst;
  // Walk the outline without allocating: Bresenham per transformed edge.
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  const size_t n = footprint.size();
  auto to_cell = [&](const Point2& p, int* mx, int* my) {
    costmap.WorldToMapNoBounds(pose.x + c * p.x - s * p.y, pose.y + s * p.x + c * p.y, mx, my);
  };
  int first_x = 0, first_y = 0;
  int x0 = 0, y0 = 0;
  if (n > 0) {
    to_cell(footprint[0], &first_x, &first_y);
    x0 = first_x;
    y0 = first_y;
  }
  for (size_t i = 0; i < n; ++i) {
    int x1, y1;
    if (i + 1 < n) {
      to_cell(footprint[i + 1], &x1, &y1);
    } else {
      x1 = first_x;
      y1 = first_y;
    }
    for (minibot3d_common::LineWalker w(x0, y0, x1, y1);; w.Next()) {
      if (!costmap.InBounds(w.x(), w.y())) return -1;
      const int v = costmap.cost(w.x(), w.y());
      if (v == kLethalObstacle) return v;
      // Unknown (255) ranks below lethal: it is returned only if nothing on
      // the outline is lethal.
      if (v > worst) worst = v;
      if (w.done()) break;
    }
    x0 = x1;
    y0 = y1;
  }
  return worst;
}

}  // namespace nav
}  // namespace minibot3d_navigation
