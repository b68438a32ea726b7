#include "minibot3d_navigation/tracking/obstacle_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace options = minibot3d_common::options;

namespace minibot3d_navigation {
namespace nav {

const options::OptionTable<ObstacleTrackerOptions>& ObstacleTrackerOptionTable() {
  using options::Field;
  using O = ObstacleTrackerOptions;
  static const options::OptionTable<O> table(
      "obstacle_tracker",
      {Field("enabled", &O::enabled,
             "Track moving obstacles in the local costmap's sensors and let the local planner "
             "avoid where they will be (false: the costmap alone). Off by default: from a moving "
             "robot the tracker still takes parts of walls and furniture for moving obstacles, "
             "which changes paths in worlds with nobody in them."),
       Field("cluster_tolerance", &O::cluster_tolerance,
             "Largest distance (m) between two points of one cluster."),
       Field("min_points", &O::min_points, "Fewest points a tracked cluster has."),
       Field("max_diameter", &O::max_diameter,
             "Widest cluster (m) that is tracked; wider ones (walls) are left to the costmap."),
       Field("range", &O::range, "Points farther than this (m) from the sensor are not tracked."),
       Field("max_speed", &O::max_speed,
             "Fastest obstacle (m/s) the association expects: a cluster farther than "
             "max_speed * dt + gate_margin from a track's prediction is another obstacle."),
       Field("gate_margin", &O::gate_margin, "Added to the association gate (m)."),
       Field("process_noise_acc", &O::process_noise_acc,
             "Standard deviation (m/s^2) of the random acceleration of the constant-velocity "
             "model."),
       Field("measurement_noise", &O::measurement_noise,
             "Standard deviation (m) of a cluster's centre as a measurement of the obstacle's "
             "position."),
       Field("confirm_hits", &O::confirm_hits,
             "Consecutive observations at min_speed or more a track needs to become a moving "
             "obstacle."),
       Field("max_missed_time", &O::max_missed_time,
             "A track unseen this long (s) is dropped."),
       Field("min_speed", &O::min_speed,
             "A track becomes a moving obstacle (and stays one while tracked) once its speed has "
             "been at least this (m/s) for confirm_hits observations and it has gone min_travel."),
       Field("min_travel", &O::min_travel,
             "Distance (m) a track must have gone from where it was first seen to become a "
             "moving obstacle (the centroid of a wall seen in part moves as the robot passes, "
             "not far).")});
  return table;
}

void ValidateObstacleTrackerOptions(const ObstacleTrackerOptions& o) {
  options::Problems p("obstacle_tracker");
  p.Positive("cluster_tolerance", o.cluster_tolerance);
  p.Require(o.min_points >= 1, "min_points = " + std::to_string(o.min_points) + ": must be >= 1");
  p.Positive("max_diameter", o.max_diameter);
  p.Positive("range", o.range);
  p.Positive("max_speed", o.max_speed);
  p.NonNegative("gate_margin", o.gate_margin);
  p.Positive("process_noise_acc", o.process_noise_acc);
  p.Positive("measurement_noise", o.measurement_noise);
  p.Require(o.confirm_hits >= 1,
            "confirm_hits = " + std::to_string(o.confirm_hits) + ": must be >= 1");
  p.Positive("max_missed_time", o.max_missed_time);
  p.NonNegative("min_speed", o.min_speed);
  p.NonNegative("min_travel", o.min_travel);
  p.ThrowIfAny();
}

ObstacleTracker::ObstacleTracker(const ObstacleTrackerOptions& options) : options_(options) {
  ValidateObstacleTrackerOptions(options_);
}

void ObstacleTracker::Reset() {
  tracks_.clear();
  filters_.clear();
  have_stamp_ = false;
}

std::vector<ObstacleTracker::Cluster> ObstacleTracker::Clusters(
    const Point2& origin, const std::vector<Point2>& points) const {
  // Points in range, bucketed on a grid of cluster_tolerance cells: neighbours of a point lie in
  // its cell or the 8 around it.
  const double cell = options_.cluster_tolerance;
  const double tol2 = cell * cell;
  const double range2 = options_.range * options_.range;
  std::vector<int> kept;
  kept.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const double dx = points[i].x - origin.x, dy = points[i].y - origin.y;
    if (std::isfinite(dx) && std::isfinite(dy) && dx * dx + dy * dy <= range2) {
      kept.push_back(static_cast<int>(i));
    }
  }
  auto key = [cell](const Point2& p, int ox, int oy) {
    const int64_t cx = static_cast<int64_t>(std::floor(p.x / cell)) + ox;
    const int64_t cy = static_cast<int64_t>(std::floor(p.y / cell)) + oy;
    return (cx << 32) ^ (cy & 0xffffffff);
  };
  std::unordered_map<int64_t, std::vector<int>> grid;
  grid.reserve(kept.size());
  for (int k = 0; k < static_cast<int>(kept.size()); ++k) {
    grid[key(points[kept[k]], 0, 0)].push_back(k);
  }
  std::vector<int> label(kept.size(), -1);
  std::vector<Cluster> out;
  std::vector<int> stack, members;
  for (int seed = 0; seed < static_cast<int>(kept.size()); ++seed) {
    if (label[seed] >= 0) continue;
    label[seed] = seed;
    stack.assign(1, seed);
    members.clear();
    while (!stack.empty()) {
      const int k = stack.back();
      stack.pop_back();
      members.push_back(k);
      const Point2& p = points[kept[k]];
      for (int ox = -1; ox <= 1; ++ox) {
        for (int oy = -1; oy <= 1; ++oy) {
          const auto it = grid.find(key(p, ox, oy));
          if (it == grid.end()) continue;
          for (int j : it->second) {
            if (label[j] >= 0) continue;
            const Point2& q = points[kept[j]];
            if ((q.x - p.x) * (q.x - p.x) + (q.y - p.y) * (q.y - p.y) <= tol2) {
              label[j] = seed;
              stack.push_back(j);
            }
          }
        }
      }
    }
    if (static_cast<int>(members.size()) < options_.min_points) continue;
    Cluster c;
    c.points = static_cast<int>(members.size());
    for (int k : members) {
      c.centre.x += points[kept[k]].x;
      c.centre.y += points[kept[k]].y;
    }
    c.centre.x /= members.size();
    c.centre.y /= members.size();
    double widest = 0.0;
    for (size_t a = 0; a < members.size(); ++a) {
      const Point2& p = points[kept[members[a]]];
      c.radius = std::max(c.radius, std::hypot(p.x - c.centre.x, p.y - c.centre.y));
    }
    // The diameter: the largest distance between two of its points (at most twice the radius
    // round the centroid; measured exactly for clusters near the limit).
    if (2.0 * c.radius > options_.max_diameter) {
      for (size_t a = 0; a < members.size() && widest <= options_.max_diameter; ++a) {
        const Point2& p = points[kept[members[a]]];
        for (size_t b = a + 1; b < members.size(); ++b) {
          const Point2& q = points[kept[members[b]]];
          widest = std::max(widest, std::hypot(p.x - q.x, p.y - q.y));
        }
      }
      if (widest > options_.max_diameter) continue;
    }
    // The outline: members in their input (scan) order, evenly thinned.
    std::sort(members.begin(), members.end());
    const size_t n = members.size();
    const size_t keep = std::min<size_t>(n, kOutlinePoints);
    for (size_t k = 0; k < keep; ++k) {
      const size_t m = keep == 1 ? 0 : k * (n - 1) / (keep - 1);
      const Point2& p = points[kept[members[m]]];
      c.outline.push_back({p.x - c.centre.x, p.y - c.centre.y});
    }
    out.push_back(c);
  }
  return out;
}

void ObstacleTracker::Predict(Filter* f, double dt) const {
  // x' = F x, P' = F P F^T + Q with F = [I dt*I; 0 I] and the white-noise acceleration Q.
  f->x[0] += dt * f->x[2];
  f->x[1] += dt * f->x[3];
  double (&P)[4][4] = f->P;
  for (int a = 0; a < 2; ++a) {
    const int v = a + 2;
    // Rows then columns of F applied to the (a, v) block.
    P[a][a] += dt * (P[v][a] + P[a][v]) + dt * dt * P[v][v];
    P[a][v] += dt * P[v][v];
    P[v][a] = P[a][v];
  }
  // The cross terms between the x and y axes (P[0][1], ...) stay 0: both axes start and stay
  // independent (the measurement and the noise are per axis).
  const double q = options_.process_noise_acc * options_.process_noise_acc;
  const double dt2 = dt * dt, dt3 = dt2 * dt, dt4 = dt3 * dt;
  for (int a = 0; a < 2; ++a) {
    const int v = a + 2;
    P[a][a] += q * dt4 / 4.0;
    P[a][v] += q * dt3 / 2.0;
    P[v][a] = P[a][v];
    P[v][v] += q * dt2;
  }
}

void ObstacleTracker::Correct(Filter* f, const Point2& z) const {
  const double r = options_.measurement_noise * options_.measurement_noise;
  double (&P)[4][4] = f->P;
  const double zz[2] = {z.x, z.y};
  for (int a = 0; a < 2; ++a) {
    const int v = a + 2;
    const double s = P[a][a] + r;
    const double kp = P[a][a] / s, kv = P[v][a] / s;
    const double innovation = zz[a] - f->x[a];
    f->x[a] += kp * innovation;
    f->x[v] += kv * innovation;
    const double paa = P[a][a], pav = P[a][v], pvv = P[v][v];
    P[a][a] = (1.0 - kp) * paa;
    P[a][v] = (1.0 - kp) * pav;
    P[v][a] = P[a][v];
    P[v][v] = pvv - kv * pav;
  }
}

bool ObstacleTracker::Update(double stamp, const Point2& origin,
                             const std::vector<Point2>& points) {
  if (!std::isfinite(stamp) || (have_stamp_ && stamp < last_stamp_)) return false;
  const double dt = have_stamp_ ? stamp - last_stamp_ : 0.0;
  last_stamp_ = stamp;
  have_stamp_ = true;
  for (Filter& f : filters_) Predict(&f, dt);

  const std::vector<Cluster> clusters = Clusters(origin, points);
  // Greedy association, nearest pair first, within the gate.
  struct Pair {
    double d;
    int track, cluster;
  };
  std::vector<Pair> pairs;
  for (size_t t = 0; t < tracks_.size(); ++t) {
    const double age = stamp - tracks_[t].last_seen;
    const double gate = options_.max_speed * age + options_.gate_margin;
    for (size_t c = 0; c < clusters.size(); ++c) {
      const double d = std::hypot(clusters[c].centre.x - filters_[t].x[0],
                                  clusters[c].centre.y - filters_[t].x[1]);
      if (d <= gate) pairs.push_back({d, static_cast<int>(t), static_cast<int>(c)});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
    return a.d < b.d || (a.d == b.d && (a.track < b.track ||
                                        (a.track == b.track && a.cluster < b.cluster)));
  });
  std::vector<bool> track_taken(tracks_.size(), false), cluster_taken(clusters.size(), false);
  for (const Pair& p : pairs) {
    if (track_taken[p.track] || cluster_taken[p.cluster]) continue;
    track_taken[p.track] = cluster_taken[p.cluster] = true;
    Correct(&filters_[p.track], clusters[p.cluster].centre);
    TrackedObstacle& t = tracks_[p.track];
    t.radius = clusters[p.cluster].radius;
    t.outline = clusters[p.cluster].outline;
    t.hits += 1;
    t.last_seen = stamp;
  }
  // Drop tracks unseen too long; start tracks on the clusters left.
  size_t w = 0;
  for (size_t t = 0; t < tracks_.size(); ++t) {
    if (stamp - tracks_[t].last_seen > options_.max_missed_time) continue;
    tracks_[w] = tracks_[t];
    filters_[w] = filters_[t];
    ++w;
  }
  tracks_.resize(w);
  filters_.resize(w);
  const double r = options_.measurement_noise * options_.measurement_noise;
  const double v0 = options_.max_speed * options_.max_speed / 4.0;
  for (size_t c = 0; c < clusters.size(); ++c) {
    if (cluster_taken[c]) continue;
    Filter f{};
    f.x[0] = clusters[c].centre.x;
    f.x[1] = clusters[c].centre.y;
    f.P[0][0] = f.P[1][1] = r;
    f.P[2][2] = f.P[3][3] = v0;  // speed unknown: up to about max_speed / 2 (1 sigma)
    filters_.push_back(f);
    TrackedObstacle t;
    t.id = next_id_++;
    t.radius = clusters[c].radius;
    t.outline = clusters[c].outline;
    t.hits = 1;
    t.last_seen = stamp;
    t.first_seen = clusters[c].centre;
    tracks_.push_back(t);
  }
  for (size_t t = 0; t < tracks_.size(); ++t) {
    TrackedObstacle& o = tracks_[t];
    o.position = {filters_[t].x[0], filters_[t].x[1]};
    o.velocity = {filters_[t].x[2], filters_[t].x[3]};
    if (o.last_seen == stamp) {
      o.fast_updates = std::hypot(o.velocity.x, o.velocity.y) >= options_.min_speed
                           ? o.fast_updates + 1
                           : 0;
    }
    o.moving = o.moving ||
               (o.fast_updates >= options_.confirm_hits &&
                std::hypot(o.position.x - o.first_seen.x, o.position.y - o.first_seen.y) >=
                    options_.min_travel);
  }
  return true;
}

std::vector<TrackedObstacle> ObstacleTracker::MovingAt(double t) const {
  std::vector<TrackedObstacle> out;
  const double dt = have_stamp_ ? std::max(0.0, t - last_stamp_) : 0.0;
  for (const TrackedObstacle& o : tracks_) {
    if (!o.moving) continue;
    TrackedObstacle p = o;
    p.position.x += o.velocity.x * dt;
    p.position.y += o.velocity.y * dt;
    out.push_back(p);
  }
  return out;
}

}  // namespace nav
}  // namespace minibot3d_navigation
