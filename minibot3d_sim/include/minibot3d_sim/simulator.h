// The simulator core, ROS-free: one world, one or more robots (each a robot model + drive plugin +
// physics backend + sensors), advanced together in fixed steps of `physics_step` seconds. It owns
// the clock — time is steps × physics_step, never read from a wall clock — so a run is
// reproducible and can go at any real-time factor; the ROS node only converts its outputs to
// messages and paces it against the wall clock.
//
// Per step: each robot's drive plugin turns its last command into targets (wheel speeds or, for a
// holonomic base, the body's velocity) and its backend advances; robots whose bodies now overlap
// (BodyOverlap: every part, at its height) are put back where they were before the step, at rest,
// and the contact is reported on both — robots are solid to each other and none pushes another;
// then each drive observes the step (its odometry) and contacts that begin become collision
// events. Sensors fire when sim time reaches a multiple of their period (every step for a rate of
// 0); lasers and cameras see the other robots' bodies where they are.
//
// The world's actors (actor.h) move on their scripts with sim time. Each is an upright cylinder of
// `actor_radius` and `actor_height`: lasers and cameras see it where it is at the scan's time, a
// robot that drives into one is put back where it was (a robot an actor walks into may drive out)
// and the contact is reported naming the actor ("actor NAME"). Pedestrians of the social force
// model (social_force.h) advance every SocialForceParams::step of sim time, pushed by each other,
// by the walls at 0.1 m (their legs' height) and by the robots' bounding circles.
#ifndef MINIBOT3D_SIM_SIMULATOR_H_
#define MINIBOT3D_SIM_SIMULATOR_H_

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_sim/body_collider.h"
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
  // Sensor noise and odometry error; robot i's streams start from seed + 1000003 i.
  unsigned seed = 1;
  // The robot of the single-robot constructor (RobotOptions has them per robot otherwise).
  Pose2 spawn;
  double odom_wheel_separation_multiplier = 1.0;
  double cmd_wheel_separation_multiplier = 1.0;
  OdometryErrorOptions odom_error;
  // The upright cylinder that stands for each of the world's actors (m).
  double actor_radius = 0.25;
  double actor_height = 1.8;
  SocialForceParams social_force;
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

// One robot of a simulation: its own spawn pose, odometry calibration and error.
struct RobotOptions {
  std::string name;  // unique among the robots; may be empty for a robot alone
  Pose2 spawn;
  // Skid-steer only: the odometry's and the command's effective track as multiples of
  // wheelSeparation (see DriveSettings).
  double odom_wheel_separation_multiplier = 1.0;
  double cmd_wheel_separation_multiplier = 1.0;
  OdometryErrorOptions odom_error;
};

struct RobotEntry {
  RobotModel model;
  RobotOptions options;
};

class Simulator;

// A robot in a Simulator: commands in, true state, odometry, sensors, collisions out.
class SimRobot {
 public:
  SimRobot(const SimRobot&) = delete;
  SimRobot& operator=(const SimRobot&) = delete;

  const std::string& name() const { return options_.name; }
  size_t index() const { return index_; }
  const RobotModel& model() const { return model_; }
  const RobotOptions& options() const { return options_; }
  double time() const;
  double physics_step() const;

  // A body twist command (m/s, m/s, rad/s), as received on cmd_vel; stamped with the sim time.
  void Command(const Twist2& command);

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

  // Lasers, in RobotModel::lasers order. A scan sees the world and the other robots' bodies.
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

  // Cameras (RobotModel::cameras order), ray cast against the full 3-D world, every robot's
  // collision shapes (but those of this robot's camera links). Each frame's noise is seeded by the
  // robot's seed and the frame's number, so a frame nobody asked for can be skipped without
  // changing the frames after it.
  size_t camera_count() const { return cameras_.size(); }
  bool CameraDue(size_t i) const { return camera_clocks_[i].Due(time()); }
  void TakeFrame(size_t i, DepthFrame* frame);
  void SkipFrame(size_t i);
  const DepthCamera& camera(size_t i) const { return *cameras_[i]; }
  // Pose of camera i's Gazebo camera frame (+x ahead) in the world now.
  Eigen::Isometry3d CameraPose(size_t i) const;

  // Collision events since the last call: one each time the body starts touching a world shape
  // or another robot it has not touched for kContactRelease seconds (a robot pushing against a
  // wall keeps flickering in and out of contact from step to step; that is one collision, not
  // hundreds).
  std::vector<CollisionEvent> TakeCollisionEvents();
  std::uint64_t collision_count() const { return collision_count_; }
  bool in_contact() const { return in_contact_; }

  // Back to the spawn pose at rest, odometry zeroed, command cleared. Time goes on.
  void Reset();
  // Teleports the robot (at rest); odometry is not told, as when a robot is kidnapped.
  void SetPose(const Pose2& pose);
  // Whether the robot's body at `pose` would overlap the world or another robot; *what names the
  // object (or "robot NAME") when it would.
  bool PoseCollides(const Pose2& pose, std::string* what) const;
  // Distance from the robot's body to the nearest obstacle of the world (m; a lower bound: the
  // centre's distance minus the body's radius).
  double Clearance() const;

  const PhysicsBackend& backend() const { return *backend_; }
  const BodyCollider& collider() const { return *collider_; }

 private:
  friend class Simulator;
  SimRobot(Simulator* sim, size_t index, RobotEntry entry, unsigned seed);
  // Before the step: the drive's targets to the backend, which advances.
  void Advance(double t, double dt);
  // After the step (and the robots' contacts): the drive's odometry, the collision events.
  void Observe(double t, double dt);
  // The bodies of the other robots and the actors at `height` within `reach` of `from` (an
  // actor's cylinder as a 32-gon, within 0.5 % of its radius).
  void OtherBodies(const Eigen::Vector2d& from, double height, double reach,
                   std::vector<BodyOutline>* out) const;

  Simulator* sim_;
  size_t index_;
  RobotModel model_;
  RobotOptions options_;
  unsigned seed_;
  std::unique_ptr<DrivePlugin> drive_;
  std::unique_ptr<PhysicsBackend> backend_;
  std::unique_ptr<BodyCollider> collider_;
  std::vector<std::unique_ptr<Lidar>> lidars_;
  std::vector<SensorClock> scan_clocks_;
  std::vector<BodyOutline> bodies_scratch_;
  std::vector<Imu> imus_;
  std::vector<SensorClock> imu_clocks_;
  int body_ = -1;       // this robot's shapes in the simulator's ray scene, as others see them
  int self_body_ = -1;  // as its own cameras see them (without their links); may be body_
  std::unique_ptr<OdometryError> odom_error_;  // null: none
  std::vector<std::unique_ptr<DepthCamera>> cameras_;
  std::vector<SensorClock> camera_clocks_;
  std::vector<std::uint64_t> camera_frames_;
  std::vector<GroundTruth> ground_truths_;
  std::vector<SensorClock> truth_clocks_;
  Pose2 before_step_;
  std::vector<Contact> contacts_;
  static constexpr double kContactRelease = 0.25;  // s
  std::map<int, double> last_touch_;  // shape (world shape or robot id) → sim time last touched
  std::vector<CollisionEvent> events_;
  std::uint64_t collision_count_ = 0;
  bool in_contact_ = false;
};

class Simulator {
 public:
  using BackendFactory =
      std::function<std::unique_ptr<PhysicsBackend>(const RobotModel&, const World&)>;

  // One robot, unnamed, with options' spawn pose, multipliers and odometry error.
  // `make_backend` replaces the factory of options.physics (benchmarks measure other backends).
  Simulator(const RobotModel& robot, World world, const SimulatorOptions& options,
            const BackendFactory& make_backend = nullptr);
  // Several robots (options' spawn, multipliers and odometry error are not used: each robot has
  // its own). Throws std::invalid_argument naming the robots when two share a name, several are
  // unnamed, or two bodies overlap where they spawn.
  Simulator(std::vector<RobotEntry> robots, World world, const SimulatorOptions& options,
            const BackendFactory& make_backend = nullptr);
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  void Step();
  double time() const { return static_cast<double>(steps_) * options_.physics_step; }
  std::uint64_t steps() const { return steps_; }
  double physics_step() const { return options_.physics_step; }
  const World& world() const { return world_; }
  const SimulatorOptions& options() const { return options_; }

  size_t robot_count() const { return robots_.size(); }
  SimRobot& at(size_t i) { return *robots_[i]; }
  const SimRobot& at(size_t i) const { return *robots_[i]; }
  // The robot of this name; null when there is none.
  SimRobot* Find(const std::string& name);
  // Id of robot i in Contact::shape and last-touch maps: after the world's shapes.
  int RobotShapeId(size_t i) const { return static_cast<int>(world_.shapes.size() + i); }

  // The world's actors where they are now (in World::actors order), and actor k's id in
  // Contact::shape: after the robots'.
  size_t actor_count() const { return world_.actors.size(); }
  const ActorState& actor_state(size_t k) const { return actor_states_[k]; }
  int ActorShapeId(size_t k) const {
    return static_cast<int>(world_.shapes.size() + robots_.size() + k);
  }

  // The first robot (the only one of a single-robot simulation).
  void Command(const Twist2& command) { at(0).Command(command); }
  void SetCommand(double v, double w) { at(0).Command(Twist2{v, 0.0, w}); }
  Pose2 true_pose() const { return at(0).true_pose(); }
  Twist2 true_twist() const { return at(0).true_twist(); }
  const DrivePlugin& drive() const { return at(0).drive(); }
  Pose2 odom_pose() const { return at(0).odom_pose(); }
  Twist2 odom_twist() const { return at(0).odom_twist(); }
  const std::vector<double>& wheel_positions() const { return at(0).wheel_positions(); }
  const std::vector<double>& wheel_velocities() const { return at(0).wheel_velocities(); }
  size_t laser_count() const { return at(0).laser_count(); }
  bool ScanDue(size_t laser) const { return at(0).ScanDue(laser); }
  void TakeScan(size_t laser, std::vector<float>* ranges) { at(0).TakeScan(laser, ranges); }
  const Lidar& lidar(size_t laser) const { return at(0).lidar(laser); }
  size_t imu_count() const { return at(0).imu_count(); }
  bool ImuDue(size_t i) const { return at(0).ImuDue(i); }
  ImuReading TakeImu(size_t i) { return at(0).TakeImu(i); }
  size_t ground_truth_count() const { return at(0).ground_truth_count(); }
  bool GroundTruthDue(size_t i) const { return at(0).GroundTruthDue(i); }
  GroundTruthReading TakeGroundTruth(size_t i) { return at(0).TakeGroundTruth(i); }
  size_t camera_count() const { return at(0).camera_count(); }
  bool CameraDue(size_t i) const { return at(0).CameraDue(i); }
  void TakeFrame(size_t i, DepthFrame* frame) { at(0).TakeFrame(i, frame); }
  void SkipFrame(size_t i) { at(0).SkipFrame(i); }
  const DepthCamera& camera(size_t i) const { return at(0).camera(i); }
  Eigen::Isometry3d CameraPose(size_t i) const { return at(0).CameraPose(i); }
  std::vector<CollisionEvent> TakeCollisionEvents() { return at(0).TakeCollisionEvents(); }
  std::uint64_t collision_count() const { return at(0).collision_count(); }
  bool in_contact() const { return at(0).in_contact(); }
  void Reset() { at(0).Reset(); }
  void SetPose(const Pose2& pose) { at(0).SetPose(pose); }
  bool PoseCollides(const Pose2& pose, std::string* what) const {
    return at(0).PoseCollides(pose, what);
  }
  double Clearance() const { return at(0).Clearance(); }
  const RobotModel& robot() const { return at(0).model(); }
  const PhysicsBackend& backend() const { return at(0).backend(); }

 private:
  friend class SimRobot;
  void Build(std::vector<RobotEntry> robots, const BackendFactory& make_backend);
  // Robots that moved into another this step go back to where they were; both report contact.
  void SeparateRobots(double t);
  // The ray scene with every robot's body where it is now, as robot `viewer`'s cameras see it.
  const RayScene& SceneNow(size_t viewer);
  // The actors' states at the current time.
  void UpdateActors();
  // Robots that moved into an actor this step go back to where they were; contacts reported.
  void SeparateFromActors();

  World world_;
  SimulatorOptions options_;
  SliceCache slices_;
  std::unique_ptr<RayScene> ray_scene_;  // when a robot has a camera
  std::vector<std::unique_ptr<SimRobot>> robots_;
  std::vector<ActorState> actor_states_;
  std::vector<int> actor_bodies_;  // each actor's cylinder in the ray scene
  std::vector<Eigen::Vector2d> actor_outline_;  // an actor's cylinder as lasers see it
  double actor_outline_radius_ = 0.0;
  std::unique_ptr<SocialForceCrowd> crowd_;  // the social-force actors, if any
  std::vector<size_t> crowd_actor_;         // crowd agent k is World::actors[crowd_actor_[k]]
  std::uint64_t crowd_every_ = 1;           // physics steps per crowd step
  std::uint64_t steps_ = 0;
  struct Separation {  // SeparateRobots' working lists
    std::vector<char> reverted, moved, moved_now;
    std::vector<std::pair<size_t, size_t>> touching, candidates;
    std::vector<Eigen::Vector2d> normals;
    std::vector<size_t> order;
    std::vector<double> lo, hi;
    struct Tested {  // a pair's overlap test: robots a < b at poses pa, pb
      size_t a, b;
      Pose2 pa, pb;
      bool overlap;
      Eigen::Vector2d normal;
    };
    std::vector<Tested> tested, last;  // this step's tests; the last step's, by (a, b)
  };
  Separation separation_;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_SIMULATOR_H_
