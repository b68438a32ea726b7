// The simulator core, ROS-free: robot + world + physics backend + drive plugin + sensors, advanced
// in fixed steps of `physics_step` seconds. It owns the clock — time is steps × physics_step, never
// read from a wall clock — so a run is reproducible and can go at any real-time factor; the ROS node
// only converts its outputs to messages and paces it against the wall clock.
//
// Per step: the drive plugin turns the last command into targets (wheel speeds or, for a holonomic
// base, the body's velocity), the backend advances, the drive observes the step (its odometry), and
// contacts that begin are turned into collision events. Sensors fire when sim time reaches a
// multiple of their period (every step for a rate of 0).
#ifndef MINIBOT3D_SIM_SIMULATOR_H_
#define MINIBOT3D_SIM_SIMULATOR_H_

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_sim/depth_camera.h"
#include "minibot3d_sim/drive.h"
#include "minibot3d_sim/imu.h"
#include "minibot3d_sim/lidar.h"
#include "minibot3d_sim/odometry_error.h"
#include "minibot3d_sim/physics_backend.h"
#include "minibot3d_sim/ray_scene.h"
#include "minibot3d_sim/robot_model.h"
#include "minibot3d_sim/world.h"
#include "minibot3d_sim/world_slice.h"

namespace minibot3d_sim {

using minibot3d_common::Pose2;
using minibot3d_common::Twist2;

struct SimulatorOptions {
  std::string physics = "bullet";  // "bullet" or "kinematic"
  double physics_step = 0.001;     // s
  double cmd_timeout = 0.5;        // s of sim time (drives without a timeout of their own)
  Pose2 spawn;
  unsigned seed = 1;               // sensor noise
  // Skid-steer only: the odometry's and the command's effective track as multiples of
  // wheelSeparation (see DriveSettings).
  double odom_wheel_separation_multiplier = 1.0;
  double cmd_wheel_separation_multiplier = 1.0;
  // Error laid over the drive's odometry (odometry_error.h), seeded by `seed`; none by default.
  OdometryErrorOptions odom_error;
};

// Throws std::invalid_argument naming the offending option and value.
void ValidateOptions(const SimulatorOptions& options);

struct CollisionEvent {
  double time = 0.0;
  Contact contact;
  std::string shape_name;
};

// When a sensor with a rate fires: at origin + k / rate (every step for a rate of 0).
class SensorClock {
 public:
  explicit SensorClock(double rate) : rate_(rate) {}
  bool Due(double t) const { return rate_ <= 0.0 || t + 1e-9 >= origin_ + count_ / rate_; }
  void Fired() { ++count_; }
  double rate() const { return rate_; }

 private:
  double rate_;
  double origin_ = 0.0;
  double count_ = 0.0;
};

class Simulator {
 public:
  using BackendFactory =
      std::function<std::unique_ptr<PhysicsBackend>(const RobotModel&, const World&)>;

  // `make_backend` replaces the factory of options.physics (benchmarks measure other backends).
  Simulator(const RobotModel& robot, World world, const SimulatorOptions& options,
            const BackendFactory& make_backend = nullptr);

  // A body twist command (m/s, m/s, rad/s), as received on cmd_vel; stamped with the sim time.
  void Command(const Twist2& command);
  void SetCommand(double v, double w) { Command(Twist2{v, 0.0, w}); }
  void Step();

  double time() const { return static_cast<double>(steps_) * options_.physics_step; }
  std::uint64_t steps() const { return steps_; }
  double physics_step() const { return options_.physics_step; }

  Pose2 true_pose() const { return backend_->pose(); }
  Twist2 true_twist() const { return backend_->twist(); }
  const DrivePlugin& drive() const { return *drive_; }
  // The odometry the robot reports: the drive's, with the odometry error if one is set.
  Pose2 odom_pose() const { return odom_error_ ? odom_error_->pose() : drive_->odometry_pose(); }
  Twist2 odom_twist() const {
    return odom_error_ ? odom_error_->twist() : drive_->odometry_twist();
  }
  const std::vector<double>& wheel_positions() const { return backend_->wheel_positions(); }
  const std::vector<double>& wheel_velocities() const { return backend_->wheel_velocities(); }

  // Lasers, in RobotModel::lasers order.
  size_t laser_count() const { return lidars_.size(); }
  bool ScanDue(size_t laser) const { return scan_clocks_[laser].Due(time()); }
  // Casts the scan for the current pose and schedules the next one.
  void TakeScan(size_t laser, std::vector<float>* ranges);
  const Lidar& lidar(size_t laser) const { return *lidars_[laser]; }

  // IMUs and ground-truth plugins, in RobotModel order.
  size_t imu_count() const { return imus_.size(); }
  bool ImuDue(size_t i) const { return imu_clocks_[i].Due(time()); }
  ImuReading TakeImu(size_t i);
  size_t ground_truth_count() const { return ground_truths_.size(); }
  bool GroundTruthDue(size_t i) const { return truth_clocks_[i].Due(time()); }
  GroundTruthReading TakeGroundTruth(size_t i);

  // Cameras (RobotModel::cameras order), ray cast against the full 3-D world and the robot's own
  // collision shapes (but those of the camera's link). Each frame's noise is seeded by the
  // simulator's seed and the frame's number, so a frame nobody asked for can be skipped without
  // changing the frames after it.
  size_t camera_count() const { return cameras_.size(); }
  bool CameraDue(size_t i) const { return camera_clocks_[i].Due(time()); }
  void TakeFrame(size_t i, DepthFrame* frame);
  void SkipFrame(size_t i);
  const DepthCamera& camera(size_t i) const { return *cameras_[i]; }
  // Pose of camera i's Gazebo camera frame (+x ahead) in the world now.
  Eigen::Isometry3d CameraPose(size_t i) const;

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
  std::unique_ptr<DrivePlugin> drive_;
  std::unique_ptr<PhysicsBackend> backend_;
  // One slice per distinct laser height (keyed by the height in µm), and the body's.
  std::map<long long, std::unique_ptr<WorldSlice>> laser_slices_;  // NOLINT(runtime/int)
  std::unique_ptr<WorldSlice> body_slice_;
  std::vector<std::unique_ptr<Lidar>> lidars_;
  std::vector<SensorClock> scan_clocks_;
  std::vector<Imu> imus_;
  std::vector<SensorClock> imu_clocks_;
  std::unique_ptr<RayScene> ray_scene_;
  int robot_body_ = -1;  // the robot's own shapes in ray_scene_
  std::unique_ptr<OdometryError> odom_error_;  // null: none
  std::vector<std::unique_ptr<DepthCamera>> cameras_;
  std::vector<SensorClock> camera_clocks_;
  std::vector<std::uint64_t> camera_frames_;
  std::vector<GroundTruth> ground_truths_;
  std::vector<SensorClock> truth_clocks_;
  std::uint64_t steps_ = 0;
  std::vector<Contact> contacts_;
  static constexpr double kContactRelease = 0.25;  // s
  std::map<int, double> last_touch_;  // world shape → sim time it was last touched
  std::vector<CollisionEvent> events_;
  std::uint64_t collision_count_ = 0;
  bool in_contact_ = false;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_SIMULATOR_H_
