#include "minibot3d_navigation/move_base/clear_costmap_recovery.h"

#include <utility>

namespace minibot3d_navigation {
namespace nav {

ClearCostmapRecovery::ClearCostmapRecovery(std::string name, double reset_distance,
                                           std::function<void(double)> clear)
    : name_(std::move(name)), reset_distance_(reset_distance), clear_(std::move(clear)) {}

void ClearCostmapRecovery::Start(const RobotState&) {
  if (clear_) clear_(reset_distance_);
}

bool ClearCostmapRecovery::Step(const RobotState&, Twist2* cmd) {
  *cmd = Twist2();
  return false;
}

}  // namespace nav
}  // namespace minibot3d_navigation
