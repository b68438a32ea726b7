// Map consistency from free-space/occupied contradictions between passes (map_consistency.h).
#include "minibot3d_slam/map_consistency.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "minibot3d_common/line_walker.h"

namespace minibot3d_slam {

namespace opt = minibot3d_common::options;

const opt::OptionTable<ConsistencyOptions>& ConsistencyOptionTable() {
  using O = ConsistencyOptions;
  static const opt::OptionTable<O> t(
      "map_consistency",
      {opt::Field("resolution", &O::resolution, "Cell size of the grid the passes are compared on (m)."),
       opt::Field("max_range", &O::max_range,
                  "Beams are used up to this range (m); a longer reading marks free space up to it "
                  "and has no endpoint (heading errors grow with range)."),
       opt::Field("tolerance", &O::tolerance,
                  "An endpoint agrees with another pass when that pass hit a cell within this "
                  "distance (m); beams mark free space only up to this distance before their "
                  "endpoint."),
       opt::Field("separation", &O::separation,
                  "Scans count as different passes when the robot drove more than this between "
                  "them (m of path)."),
       opt::Field("every_distance", &O::every_distance,
                  "Scans checked: the first, then one each time the robot moved this far (m)..."),
       opt::Field("every_angle", &O::every_angle, "... or turned this much (rad)."),
       opt::Field("min_scan_endpoints", &O::min_scan_endpoints,
                  "A checked scan is judged when at least this many of its endpoints fall where "
                  "another pass looked."),
       opt::Field("scan_conflict_fraction", &O::scan_conflict_fraction,
                  "A judged scan is inconsistent when more than this fraction of those endpoints "
                  "conflict.")});
  return t;
}

void ValidateConsistencyOptions(const ConsistencyOptions& o) {
  opt::Problems p("map_consistency");
  p.Positive("resolution", o.resolution);
  p.Positive("max_range", o.max_range);
  p.NonNegative("tolerance", o.tolerance);
  p.Positive("separation", o.separation);
  p.NonNegative("every_distance", o.every_distance);
  p.NonNegative("every_angle", o.every_angle);
  p.Check(o.min_scan_endpoints >= 1, "min_scan_endpoints", o.min_scan_endpoints, ">= 1");
  p.InUnitInterval("scan_conflict_fraction", o.scan_conflict_fraction);
  if (std::isfinite(o.resolution) && o.resolution > 0.0 && std::isfinite(o.max_range) &&
      o.max_range / o.resolution > 1e5) {
    p.Add("max_range / resolution must be <= 1e5 cells");
  }
  p.ThrowIfAny();
}

namespace {

constexpr float kNone = std::numeric_limits<float>::infinity();

// Per cell: the smallest and largest path length of the scans that hit it and that saw it free.
struct Passes {
  float hit_lo = kNone, hit_hi = -kNone, free_lo = kNone, free_hi = -kNone;
};

inline void Mark(float s, float* lo, float* hi) {
  *lo = std::min(*lo, s);
  *hi = std::max(*hi, s);
}

// Whether a pass more than `sep` of path away from s is among [lo, hi].
inline bool OtherPass(float lo, float hi, float s, float sep) { return lo < s - sep || hi > s + sep; }

struct Beam {
  double sx, sy;  // sensor
  double ex, ey;  // end of the beam (endpoint, or cut at max_range)
  bool endpoint;
};

class Grid {
 public:
  Grid(double min_x, double min_y, double max_x, double max_y, double res)
      : res_(res), x0_(min_x), y0_(min_y),
        w_(static_cast<int>(std::floor((max_x - min_x) / res)) + 1),
        h_(static_cast<int>(std::floor((max_y - min_y) / res)) + 1),
        cells_(static_cast<size_t>(w_) * static_cast<size_t>(h_)) {}
  int Cx(double x) const { return static_cast<int>(std::floor((x - x0_) / res_)); }
  int Cy(double y) const { return static_cast<int>(std::floor((y - y0_) / res_)); }
  bool In(int x, int y) const { return x >= 0 && y >= 0 && x < w_ && y < h_; }
  Passes& At(int x, int y) { return cells_[static_cast<size_t>(y) * w_ + x]; }

 private:
  double res_, x0_, y0_;
  int w_, h_;
  std::vector<Passes> cells_;
};

template <typename F>
void ForEachBeam(const PlacedScan& ps, double max_range, F f) {
  const Pose2 sensor = minibot3d_common::Compose(ps.pose, ps.scan.sensor_in_base);
  for (size_t i = 0; i < ps.scan.ranges.size(); ++i) {
    const double r = ps.scan.ranges[i];
    if (!std::isfinite(r) || r <= 0.0 || r < ps.scan.range_min) continue;
    if (ps.scan.range_max > 0.0 && r > ps.scan.range_max) continue;
    const bool endpoint = r <= max_range;
    const double len = endpoint ? r : max_range;
    const double a = sensor.yaw + ps.scan.angles[i];
    f(Beam{sensor.x, sensor.y, sensor.x + len * std::cos(a), sensor.y + len * std::sin(a), endpoint});
  }
}

}  // namespace

ConsistencyReport EvaluateConsistency(const std::vector<PlacedScan>& scans,
                                      const ConsistencyOptions& o) {
  ValidateConsistencyOptions(o);
  ConsistencyReport report;
  report.scans = static_cast<int>(scans.size());
  if (scans.empty()) return report;

  // Path length of every scan, the checked scans, and the grid's extent.
  std::vector<double> s(scans.size(), 0.0);
  std::vector<bool> checked(scans.size(), false);
  double min_x = kNone, min_y = kNone, max_x = -kNone, max_y = -kNone;
  Pose2 last_checked;
  for (size_t k = 0; k < scans.size(); ++k) {
    const PlacedScan& ps = scans[k];
    if (!minibot3d_common::IsFinite(ps.pose)) {
      throw std::invalid_argument("map_consistency: the scan at time " + std::to_string(ps.time) +
                                  " has a non-finite pose");
    }
    if (ps.scan.ranges.size() != ps.scan.angles.size()) {
      throw std::invalid_argument("map_consistency: the scan at time " + std::to_string(ps.time) +
                                  " has " + std::to_string(ps.scan.ranges.size()) + " ranges but " +
                                  std::to_string(ps.scan.angles.size()) + " angles");
    }
    if (k > 0) {
      s[k] = s[k - 1] + std::hypot(ps.pose.x - scans[k - 1].pose.x, ps.pose.y - scans[k - 1].pose.y);
    }
    if (k == 0 || std::hypot(ps.pose.x - last_checked.x, ps.pose.y - last_checked.y) >= o.every_distance ||
        std::abs(minibot3d_common::AngleDiff(ps.pose.yaw, last_checked.yaw)) >= o.every_angle) {
      checked[k] = true;
      last_checked = ps.pose;
    }
    ForEachBeam(ps, o.max_range, [&](const Beam& b) {
      min_x = std::min({min_x, b.sx, b.ex});
      min_y = std::min({min_y, b.sy, b.ey});
      max_x = std::max({max_x, b.sx, b.ex});
      max_y = std::max({max_y, b.sy, b.ey});
    });
  }
  if (!(min_x <= max_x)) {  // no usable beam at all
    report.scans_checked = static_cast<int>(std::count(checked.begin(), checked.end(), true));
    return report;
  }
  const double pad = o.tolerance + 2.0 * o.resolution;
  Grid grid(min_x - pad, min_y - pad, max_x + pad, max_y + pad, o.resolution);

  // 1. Hits and free space of every scan.
  const int keep_clear = static_cast<int>(std::ceil(o.tolerance / o.resolution));
  for (size_t k = 0; k < scans.size(); ++k) {
    const float sk = static_cast<float>(s[k]);
    ForEachBeam(scans[k], o.max_range, [&](const Beam& b) {
      const int x0 = grid.Cx(b.sx), y0 = grid.Cy(b.sy), x1 = grid.Cx(b.ex), y1 = grid.Cy(b.ey);
      minibot3d_common::LineWalker w(x0, y0, x1, y1);
      const int free_cells = b.endpoint ? w.length() - 1 - keep_clear : w.length();
      for (int i = 0; i < free_cells; ++i) {
        Passes& c = grid.At(w.x(), w.y());
        Mark(sk, &c.free_lo, &c.free_hi);
        if (!w.done()) w.Next();
      }
      if (b.endpoint) {
        Passes& c = grid.At(x1, y1);
        Mark(sk, &c.hit_lo, &c.hit_hi);
      }
    });
  }

  // 2-3. The checked scans' endpoints against the other passes.
  const float sep = static_cast<float>(o.separation);
  const int r = keep_clear;
  const double r2 = (o.tolerance / o.resolution + 0.5) * (o.tolerance / o.resolution + 0.5);
  for (size_t k = 0; k < scans.size(); ++k) {
    if (!checked[k]) continue;
    ++report.scans_checked;
    const float sk = static_cast<float>(s[k]);
    ScanConsistency sc;
    sc.time = scans[k].time;
    ForEachBeam(scans[k], o.max_range, [&](const Beam& b) {
      if (!b.endpoint) return;
      ++report.endpoints;
      const int cx = grid.Cx(b.ex), cy = grid.Cy(b.ey);
      bool agreed = false;
      for (int dy = -r; dy <= r && !agreed; ++dy) {
        for (int dx = -r; dx <= r && !agreed; ++dx) {
          if (dx * dx + dy * dy > r2 || !grid.In(cx + dx, cy + dy)) continue;
          const Passes& c = grid.At(cx + dx, cy + dy);
          agreed = OtherPass(c.hit_lo, c.hit_hi, sk, sep);
        }
      }
      if (agreed) {
        ++sc.agreed;
      } else if (OtherPass(grid.At(cx, cy).free_lo, grid.At(cx, cy).free_hi, sk, sep)) {
        ++sc.conflicts;
      } else {
        ++report.not_revisited;
      }
    });
    report.agreed += sc.agreed;
    report.conflicts += sc.conflicts;
    const int counted = sc.agreed + sc.conflicts;
    if (counted >= o.min_scan_endpoints) {
      ++report.scans_judged;
      if (sc.conflicts > o.scan_conflict_fraction * counted) report.inconsistent.push_back(sc);
    }
  }
  const long long counted = report.agreed + report.conflicts;
  report.conflict_fraction = counted > 0 ? static_cast<double>(report.conflicts) / counted : 0.0;
  std::stable_sort(report.inconsistent.begin(), report.inconsistent.end(),
                   [](const ScanConsistency& a, const ScanConsistency& b) {
                     return a.conflicts * static_cast<long long>(b.agreed + b.conflicts) >
                            b.conflicts * static_cast<long long>(a.agreed + a.conflicts);
                   });
  return report;
}

namespace {

std::vector<long long> RangesInCm(const LaserScan& scan) {
  std::vector<long long> key;
  key.reserve(scan.ranges.size());
  for (const double r : scan.ranges) {
    key.push_back(std::isfinite(r) ? std::llround(r * 100.0) : std::numeric_limits<long long>::min());
  }
  return key;
}

}  // namespace

ReferenceScans::ReferenceScans(const std::vector<LaserScan>& reference)
    : size_(static_cast<int>(reference.size())) {
  for (const LaserScan& scan : reference) ++left_[RangesInCm(scan)];
}

bool ReferenceScans::Take(const LaserScan& scan) {
  const auto it = left_.find(RangesInCm(scan));
  if (it == left_.end() || it->second == 0) return false;
  --it->second;
  ++taken_;
  return true;
}

}  // namespace minibot3d_slam
