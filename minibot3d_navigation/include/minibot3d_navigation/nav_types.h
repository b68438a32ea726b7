// Value types shared by the ROS-free navigation core (costmaps, global
// planners, the DWA local planner): the workspace's planar pose, twist and
// point (minibot3d_common), paths, and the planners' errors.
#ifndef MINIBOT3D_NAVIGATION_NAV_TYPES_H_
#define MINIBOT3D_NAVIGATION_NAV_TYPES_H_

#include <stdexcept>
#include <string>
#include <vector>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_common/laser_scan.h"
#include "minibot3d_map_io/map_io.h"

namespace minibot3d_navigation {
namespace nav {

using minibot3d_common::AngleDiff;
using minibot3d_common::Between;
using minibot3d_common::Compose;
using minibot3d_common::kPi;
using minibot3d_common::LaserScan;
using minibot3d_common::MakeBeamAngles;
using minibot3d_common::NormalizeAngle;
using minibot3d_common::Point2;
using minibot3d_common::Pose2;
using minibot3d_common::Twist2;

// The workspace's occupancy grid (map_server's layout; -1 unknown, 0 free .. 100 occupied).
using OccupancyGrid = minibot3d_map_io::OccupancyGrid;

// A path in the costmap's frame, start first.
using Path = std::vector<Pose2>;

// Why a plan could not be made.  Global planners throw this instead of
// returning false, so the action server can tell the user which start/goal
// failed and how (nav_core2 / Nav2 planner_exceptions style).
class PlanningError : public std::runtime_error {
 public:
  enum class Code {
    kStartOffMap,
    kStartOccupied,
    kGoalOffMap,
    kGoalOccupied,
    kNoPath,
    kTimeout,
    kInvalidInput,
  };
  PlanningError(Code code, const std::string& what)
      : std::runtime_error(what), code_(code) {}
  Code code() const { return code_; }

 private:
  Code code_;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_NAV_TYPES_H_
