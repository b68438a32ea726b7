// Basic value types shared by the ROS-free AMCL core (Monte Carlo localization,
// Thrun, Burgard & Fox, "Probabilistic Robotics", ch. 8).
#ifndef MINIBOT3D_NAVIGATION_AMCL_TYPES_H_
#define MINIBOT3D_NAVIGATION_AMCL_TYPES_H_

#include <cmath>
#include <cstdint>
#include <vector>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_common/laser_scan.h"

namespace minibot3d_navigation {
namespace amcl {

using minibot3d_common::AngleDiff;
using minibot3d_common::Between;
using minibot3d_common::Compose;
using minibot3d_common::IsFinite;
using minibot3d_common::kPi;
using minibot3d_common::NormalizeAngle;
using minibot3d_common::Pose2;

// One particle: a pose hypothesis and its importance weight.  Weights of the
// filter's particle set are kept normalised (sum 1).
struct Particle {
  Pose2 pose;
  double weight = 0.0;
  // Drawn at random by augmented MCL's recovery (or descended from such a
  // draw) since the hypotheses were last set (a pose, a map-wide search, a
  // spread over free space).  A mode made of such particles was found by
  // resampling, not among the places the filter was told to consider.
  bool injected = false;
  // The seeded hypothesis (a map-wide search candidate, AmclFilter::
  // hypotheses()) this particle descends from; -1: none (a pose the user
  // gave, a uniform spread, or an injected draw).
  int16_t hypothesis = -1;
};

// One laser scan as the filter consumes it (the node fills it from a sensor_msgs/LaserScan and
// the laser->base transform); readings may be NaN or ±inf (sensor_model.h).
using minibot3d_common::LaserScan;
using minibot3d_common::MakeBeamAngles;

}  // namespace amcl
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_AMCL_TYPES_H_
