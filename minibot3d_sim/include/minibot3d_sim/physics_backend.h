// The physics extension point: how the robot's body moves given its drive's targets (wheel speed
// targets, or the body velocity of a holonomic base).
//
// Lifecycle: construct with the robot model and the world → SetPose(spawn) → repeatedly
// SetTargets() and Step(dt) with a fixed dt → read pose()/twist()/wheel_*(). The simulator
// owns the clock; a backend never looks at wall time.
#ifndef MINIBOT3D_SIM_PHYSICS_BACKEND_H_
#define MINIBOT3D_SIM_PHYSICS_BACKEND_H_

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_sim/drive.h"
#include "minibot3d_sim/robot_model.h"
#include "minibot3d_sim/world.h"

namespace minibot3d_sim {

using minibot3d_common::NormalizeAngle;
using minibot3d_common::Pose2;
using minibot3d_common::TransformPoint;
using minibot3d_common::Twist2;

// The robot's body touching the world.
struct Contact {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // world frame
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // pointing from the world into the robot
  double depth = 0.0;                                // penetration (m), >= 0
  int shape = -1;                                    // index into World::shapes
};

class PhysicsBackend {
 public:
  virtual ~PhysicsBackend() = default;

  virtual std::string name() const = 0;

  // Places the robot at rest at `pose` (of the root frame, base_footprint) on the floor; wheel
  // angles are kept, wheel speeds zeroed.
  virtual void SetPose(const Pose2& pose) = 0;

  // What the drive asks for the next steps: wheel joint speeds (rad/s, RobotModel::wheels order)
  // as its motors command, or the body's velocity.
  virtual void SetTargets(const DriveTargets& targets) = 0;

  // Advances by dt seconds. Appends to *contacts the robot–world contacts present after the step
  // (may be null).
  virtual void Step(double dt, std::vector<Contact>* contacts) = 0;

  virtual Pose2 pose() const = 0;    // true pose of the root frame in the world
  virtual Twist2 twist() const = 0;  // true body-frame twist of the root frame
  virtual const std::vector<double>& wheel_velocities() const = 0;  // joint speeds (rad/s)
  virtual const std::vector<double>& wheel_positions() const = 0;   // joint angles (rad), unwrapped
};

class SliceCache;

// Factory: "bullet" or "kinematic". Throws std::invalid_argument naming an unknown backend.
// `slices` (of `world`), when given, is shared with a kinematic backend and must outlive it.
std::unique_ptr<PhysicsBackend> MakePhysicsBackend(const std::string& name,
                                                   const RobotModel& robot, const World& world,
                                                   SliceCache* slices = nullptr);

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_PHYSICS_BACKEND_H_
