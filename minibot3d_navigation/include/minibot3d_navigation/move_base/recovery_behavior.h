// Recovery behaviours (nav_core::RecoveryBehavior), run by the navigation
// executive when planning or control keeps failing or the robot oscillates.
//
// Lifecycle: Start() once when the executive enters the recovery, then Step()
// every control cycle until it returns false (finished); the command it writes
// is sent to the base.  The two behaviours of move_base's default list:
//  - ClearCostmapRecovery: resets the obstacle layers outside a square of
//    side reset_distance centred on the robot (clear_costmap_recovery);
//  - RotateRecovery: turns in place one full turn so the sensors see all
//    around (rotate_recovery), stopping early if the footprint would hit
//    something it can see on the local costmap.
#ifndef MINIBOT3D_NAVIGATION_MOVE_BASE_RECOVERY_BEHAVIOR_H_
#define MINIBOT3D_NAVIGATION_MOVE_BASE_RECOVERY_BEHAVIOR_H_

#include <functional>
#include <string>

#include "minibot3d_navigation/costmap/costmap_2d.h"
#include "minibot3d_navigation/costmap/footprint.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {

// What a recovery (and the executive) sees each cycle.
struct RobotState {
  double time = 0.0;      // seconds, the simulator's clock
  Pose2D global_pose;     // in the global costmap's frame (map)
  Pose2D local_pose;      // in the local costmap's frame (odom)
  Twist2D velocity;       // in the robot's frame
  const Costmap2D* global_costmap = nullptr;
  const Costmap2D* local_costmap = nullptr;
};

class RecoveryBehavior {
 public:
  virtual ~RecoveryBehavior() = default;
  virtual std::string name() const = 0;
  virtual void Start(const RobotState& state) = 0;
  virtual bool Step(const RobotState& state, Twist2D* cmd) = 0;
};

class ClearCostmapRecovery : public RecoveryBehavior {
 public:
  // `clear` is called with reset_distance once, at Start.
  ClearCostmapRecovery(std::string name, double reset_distance,
                       std::function<void(double)> clear);
  std::string name() const override { return name_; }
  void Start(const RobotState& state) override;
  bool Step(const RobotState& state, Twist2D* cmd) override;

 private:
  std::string name_;
  double reset_distance_;
  std::function<void(double)> clear_;
};

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
  bool Step(const RobotState& state, Twist2D* cmd) override;

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

#endif  // MINIBOT3D_NAVIGATION_MOVE_BASE_RECOVERY_BEHAVIOR_H_
