// move_base's clear_costmap_recovery (conservative_reset, aggressive_reset):
// see recovery_behavior.h.
#ifndef MINIBOT3D_NAVIGATION_MOVE_BASE_CLEAR_COSTMAP_RECOVERY_H_
#define MINIBOT3D_NAVIGATION_MOVE_BASE_CLEAR_COSTMAP_RECOVERY_H_

#include <functional>
#include <string>

#include "minibot3d_navigation/move_base/recovery_behavior.h"

namespace minibot3d_navigation {
namespace nav {

class ClearCostmapRecovery : public RecoveryBehavior {
 public:
  // `clear` is called with reset_distance once, at Start.
  ClearCostmapRecovery(std::string name, double reset_distance,
                       std::function<void(double)> clear);
  std::string name() const override { return name_; }
  void Start(const RobotState& state) override;
  bool Step(const RobotState& state, Twist2* cmd) override;

 private:
  std::string name_;
  double reset_distance_;
  std::function<void(double)> clear_;
};

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_MOVE_BASE_CLEAR_COSTMAP_RECOVERY_H_
