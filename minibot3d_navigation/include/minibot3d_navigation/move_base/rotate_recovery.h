// move_base's rotate_recovery: one full turn on the spot, stopping before the
// footprint would touch a lethal cell of the local costmap.
#ifndef MINIBOT3D_NAVIGATION_MOVE_BASE_ROTATE_RECOVERY_H_
#define MINIBOT3D_NAVIGATION_MOVE_BASE_ROTATE_RECOVERY_H_

#include <string>

#include "minibot3d_navigation/costmap/footprint.h"
#include "minibot3d_navigation/move_base/recovery_behavior.h"

namespace minibot3d_navigation {
namespace nav {

struct RotateRecoveryOptions {
  double max_rotational_vel = 1.0;     // rad/s (max_vel_theta)
  double min_rotational_vel = 0.4;     // rad/s (min_in_place_vel_theta)
  double acc_lim_th = 3.2;             // rad/s^2
  double frequency = 20.0;             // Hz, the control rate
  double sim_granularity = 0.017;      // rad between footprint checks
  double tolerance = 0.10;             // rad short of a full turn = done
  double timeout = 30.0;               // s; a turn that does not progress stops
};

class RotateRecovery : public RecoveryBehavior {
 public:
  RotateRecovery(std::string name, const RotateRecoveryOptions& options,
                 Footprint footprint);
  std::string name() const override { return name_; }
  void Start(const RobotState& state) override;
  bool Step(const RobotState& state, Twist2* cmd) override;

 private:
  std::string name_;
  RotateRecoveryOptions options_;
  Footprint footprint_;
  double start_time_ = 0.0;
  double last_yaw_ = 0.0;
  double turned_ = 0.0;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_MOVE_BASE_ROTATE_RECOVERY_H_
