// Value types shared by the ROS-free navigation core (costmaps, global
// planners, the DWA local planner).  Poses are the AMCL core's Pose2D so that
// localization and navigation speak the same type.
#ifndef MINIBOT3D_NAVIGATION_NAV_TYPES_H_
#define MINIBOT3D_NAVIGATION_NAV_TYPES_H_

#include <stdexcept>
#include <string>
#include <vector>

#include "minibot3d_navigation/amcl/types.h"

namespace minibot3d_navigation {
namespace nav {

using amcl::AngleDiff;
using amcl::Between;
using amcl::Compose;
using amcl::kPi;
using amcl::NormalizeAngle;
using amcl::Pose2D;

// A path in the costmap's frame, start first.
using Path = std::vector<Pose2D>;

// Robot velocity in its own frame (m/s, m/s, rad/s).
struct Twist2D {
  double vx = 0.0;
  double vy = 0.0;
  double vtheta = 0.0;
};

// A 2-D point (footprint vertices, costmap cells in metres).
struct Point2D {
  double x = 0.0;
  double y = 0.0;
};

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
