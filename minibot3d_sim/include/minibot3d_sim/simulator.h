// The simulator core, ROS-free: robot + world + physics backend + lidar + wheel odometry, advanced
// in fixed steps of `physics_step` seconds. It owns the clock — time is steps × physics_step, never
// read from a wall clock — so a run is reproducible and can go at any real-time factor; the ROS node
// (sim_node.cpp) only converts its outputs to messages and paces it against the wall clock.
//
// Per step: the drive plugin's motors get wheel targets from the last cmd_vel (zero once it is older
// than cmd_timeout), the backend advances, odometry integrates the wheel joint speeds exactly over
// the step (so it drifts when the wheels slip, as on the real robot), and contacts that begin are
// turned into collision events.
#ifndef MINIBOT3D_SIM_SIMULATOR_H_
#define MINIBOT3D_SIM_SIMULATOR_H_

#include <cstdint>
#include <memory>
#include <map>
#include <string>
#include <vector>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_sim/lidar.h"
#include "minibot3d_sim/physics_backend.h"
#include "minibot3d_sim/robot_model.h"
#include "minibot3d_sim/skid_steer.h"
#include "minibot3d_sim/world.h"
#include "minibot3d_sim/world_slice.h"

namespace minibot3d_sim {

using minibot3d_common::Pose2;
using minibot3d_common::Twist2;

struct SimulatorOptions {
  std::string physics = "bullet";  // "bullet", "bullet_naive" or "kinematic"
  double physics_step = 0.001;     // s
  double cmd_timeout = 0.5;        // s of sim time
  Pose2 spawn;
  unsigned seed = 1;               // lidar noise
  // Odometry's effective track = wheel_separation × this (diff_drive_controller's
  // wheel_separation_multiplier). A skid-steer robot turning in place slips sideways, so its wheels
  // turn (a² + b²)/b² times more than a no-slip model expects (a: half wheelbase, b: half track);
  // real skid-steer robots calibrate this. 1.0 integrates the raw wheel speeds.
  double odom_wheel_separation_multiplier = 1.0;
  // The drive's effective track when it turns cmd_vel into wheel speeds (the same
  // multiplier of diff_drive_controller, applied on the command side): with the slip factor
  // above, commanded yaw rates are then achieved instead of b²/(a² + b²) of them, which a local
  // planner predicting arcs relies on. 1.0 is the Gazebo skid-steer plugin (no compensation).
  double cmd_wheel_separation_multiplier = 1.0;
};

// Throws std::invalid_argument naming the offending option and value.
void ValidateOptions(const SimulatorOptions& options);

struct CollisionEvent {
  double time = 0.0;
  Contact contact;
  std::string shape_name;
};

class Simulator {
 public:
  Simulator(const RobotModel& robot, World world, const SimulatorOptions& options);

  // Body twist command (m/s, rad/s), as received on cmd_vel; stamped with the current sim time.
  void SetCommand(double v, double w);
  void Step();

  double time() const { return static_cast<double>(steps_) * options_.physics_step; }
  std::uint64_t steps() const { return steps_; }
  double physics_step() const { return options_.physics_step; }

  Pose2 true_pose() const { return backend_->pose(); }
  Twist2 true_twist() const { return backend_->twist(); }
  Pose2 odom_pose() const { return odom_pose_; }
  Twist2 odom_twist() const { return odom_twist_; }
  std::array<double, 4> wheel_positions() const { return backend_->wheel_positions(); }
  std::array<double, 4> wheel_velocities() const { return backend_->wheel_velocities(); }
  bool command_active() const;

  // The lidar fires when sim time reaches a multiple of 1/update_rate.
  bool ScanDue() const;
  // Casts the scan for the current pose and schedules the next one.
  void TakeScan(std::vector<float>* ranges);
  const Lidar& lidar() const { return *lidar_; }

  // Collision events since the last call: one each time the body starts touching a world shape it
  // has not touched for kContactRelease seconds (a robot pushing against a wall keeps flickering in
  // and out of contact from step to step; that is one collision, not hundreds).
  std::vector<CollisionEvent> TakeCollisionEvents();
  std::uint64_t collision_count() const { return collision_count_; }
  bool in_contact() const { return in_contact_; }

  // Back to the spawn pose at rest, odometry zeroed, command cleared. Time goes on.
  void Reset();
  // Teleports the robot (at rest); odometry is not told, as when a robot is kidnapped.
  void SetPose(const Pose2& pose);
  // Whether the robot's footprint at `pose` would overlap the world at body height; *what names
  // the object when it would.
  bool PoseCollides(const Pose2& pose, std::string* what) const;
  // Distance from the robot's footprint outline to the nearest obstacle at body height (m).
  double Clearance() const;

  const RobotModel& robot() const { return robot_; }
  const World& world() const { return world_; }
  const PhysicsBackend& backend() const { return *backend_; }

 private:
  RobotModel robot_;
  World world_;
  SimulatorOptions options_;
  SkidSteerGeometry geometry_;       // the drive: cmd_vel → wheel speeds
  SkidSteerGeometry odom_geometry_;  // odometry: wheel speeds → twist
  std::unique_ptr<PhysicsBackend> backend_;
  std::unique_ptr<WorldSlice> lidar_slice_;
  std::unique_ptr<WorldSlice> body_slice_;
  std::unique_ptr<Lidar> lidar_;
  std::uint64_t steps_ = 0;
  std::uint64_t scans_ = 0;  // scans taken; the next is due at scans_ / update_rate
  double scan_origin_ = 0.0;  // sim time of the first scan
  double cmd_v_ = 0.0, cmd_w_ = 0.0;
  double cmd_time_ = -1e9;
  Pose2 odom_pose_;
  Twist2 odom_twist_;
  std::vector<Contact> contacts_;
  static constexpr double kContactRelease = 0.25;  // s
  std::map<int, double> last_touch_;  // world shape → sim time it was last touched
  std::vector<CollisionEvent> events_;
  std::uint64_t collision_count_ = 0;
  bool in_contact_ = false;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_SIMULATOR_H_
