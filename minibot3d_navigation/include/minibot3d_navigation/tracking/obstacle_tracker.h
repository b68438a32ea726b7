// Tracking of moving obstacles (people, carts) in a range sensor's points, for the local planner's
// short-horizon prediction.
//
// Each observation (the points one scan or cloud hit, in the costmap's fixed frame, with the
// sensor's position) is cut into clusters by Euclidean distance (two points closer than
// cluster_tolerance share a cluster, found on a grid of that cell size); clusters with fewer than
// min_points, or wider than max_diameter (walls, furniture rows), are not tracked. A cluster's
// position is the centroid of its points; its outline, up to kOutlinePoints of its points evenly
// spaced along the scan, relative to the centroid, is what the planner keeps clear of; its radius
// the largest distance from the centroid to a point.
// Clusters are associated with the tracks greedily, nearest predicted track first, within a gate
// of max_speed * dt + gate_margin; a track follows a constant-velocity Kalman filter (state
// x, y, vx, vy; white-noise acceleration of process_noise_acc m/s^2; position measurements with
// measurement_noise m of standard deviation: Bar-Shalom, Li & Kirubarajan, "Estimation with
// Applications to Tracking and Navigation", 2001, ch. 6). A cluster no track takes starts a track;
// a track unseen for max_missed_time is dropped. A track becomes a moving obstacle once its speed
// has been at least min_speed in each of its last confirm_hits updates and it has gone min_travel
// from where it was first seen (the visible part of a wall grows as the robot passes it and its
// centroid moves, but not far), and stays one while it is tracked: a person who stops is still
// a person. Things that never moved (a table leg, a standing person never seen walking) are left
// to the costmap.
#ifndef MINIBOT3D_NAVIGATION_TRACKING_OBSTACLE_TRACKER_H_
#define MINIBOT3D_NAVIGATION_TRACKING_OBSTACLE_TRACKER_H_

#include <string>
#include <vector>

#include "minibot3d_common/options.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {

struct ObstacleTrackerOptions {
  bool enabled = false;
  double cluster_tolerance = 0.15;  // m between two points of one cluster
  int min_points = 3;
  double max_diameter = 1.0;        // m: wider clusters are not tracked
  double range = 4.0;               // m from the sensor: farther points are not clustered
  double max_speed = 2.0;           // m/s: the association gate's speed
  double gate_margin = 0.1;         // m added to the gate
  double process_noise_acc = 2.0;   // m/s^2
  double measurement_noise = 0.05;  // m
  int confirm_hits = 5;
  double max_missed_time = 0.5;     // s
  double min_speed = 0.15;          // m/s
  double min_travel = 0.4;          // m from where the track was first seen
};

const minibot3d_common::options::OptionTable<ObstacleTrackerOptions>& ObstacleTrackerOptionTable();

// Throws std::invalid_argument naming every bad value.
void ValidateObstacleTrackerOptions(const ObstacleTrackerOptions& options);

struct TrackedObstacle {
  int id = 0;
  Point2 position;  // at the tracker's last update
  Point2 velocity;  // m/s
  double radius = 0.0;
  std::vector<Point2> outline;  // the points last seen, relative to position
  int hits = 0;
  double last_seen = 0.0;  // s
  Point2 first_seen;       // position where the track began
  int fast_updates = 0;    // consecutive updates at min_speed or more
  bool moving = false;     // has moved (see the file comment)
};

class ObstacleTracker {
 public:
  // Throws std::invalid_argument if `options` fail ValidateObstacleTrackerOptions.
  explicit ObstacleTracker(const ObstacleTrackerOptions& options);

  // One observation at time `stamp` (s): `points` in the fixed frame, seen from `origin`.
  // Observations must come in time order; an older one is ignored (returns false).
  bool Update(double stamp, const Point2& origin, const std::vector<Point2>& points);

  // The moving obstacles, predicted to time `t` (>= the last update) at constant velocity.
  std::vector<TrackedObstacle> MovingAt(double t) const;

  // Every track, confirmed or not (for tests and diagnostics).
  const std::vector<TrackedObstacle>& tracks() const { return tracks_; }

  // Forgets every track (the fixed frame jumped).
  void Reset();

  const ObstacleTrackerOptions& options() const { return options_; }

  static constexpr int kOutlinePoints = 12;
  struct Cluster {
    Point2 centre;
    double radius = 0.0;
    int points = 0;
    std::vector<Point2> outline;  // relative to centre
  };
  // The clusters of `points` that pass min_points and max_diameter (exposed for tests).
  std::vector<Cluster> Clusters(const Point2& origin, const std::vector<Point2>& points) const;

 private:
  struct Filter {
    double x[4];      // x, y, vx, vy
    double P[4][4];   // covariance
  };
  void Predict(Filter* f, double dt) const;
  void Correct(Filter* f, const Point2& z) const;

  ObstacleTrackerOptions options_;
  std::vector<TrackedObstacle> tracks_;
  std::vector<Filter> filters_;
  double last_stamp_ = 0.0;
  bool have_stamp_ = false;
  int next_id_ = 1;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_TRACKING_OBSTACLE_TRACKER_H_
