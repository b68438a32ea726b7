// NaiveBulletBackend: the textbook Bullet vehicle, the yardstick the default BulletBackend is
// measured against (bench/physics_bench.cpp, test/bullet_backend_test.cpp); it ships in no library
// (a four-wheel skid-steer robot only).
//
// Model: a full 3-D btDiscreteDynamicsWorld under gravity. The chassis is a box body; each wheel
// is a cylinder body joined to it by a btHingeConstraint whose angular motor drives it towards
// the target speed with an impulse limited to torque·dt (as Gazebo's joint "vel"/"fmax"). Wheels
// roll on a btStaticPlaneShape ground at z = 0 through Bullet's contact manifolds; wheel friction
// is the URDF's mu1 along / mu2 across the rolling direction (Bullet's anisotropic friction on the
// wheel, ground friction 1, Bullet multiplies the two). Walls stop chassis and wheels through the
// same contacts. Physically the most direct, but every step generates and solves wheel–ground
// manifolds and a 9-body constraint system, which costs several times the default backend.
#ifndef MINIBOT3D_SIM_NAIVE_BULLET_BACKEND_H_
#define MINIBOT3D_SIM_NAIVE_BULLET_BACKEND_H_

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <btBulletDynamicsCommon.h>
#include <Eigen/Core>

#include "minibot3d_sim/bullet_world.h"
#include "minibot3d_sim/physics_backend.h"
#include "minibot3d_sim/robot_model.h"
#include "minibot3d_sim/world.h"

namespace minibot3d_sim {

class NaiveBulletBackend : public PhysicsBackend {
 public:
  NaiveBulletBackend(const RobotModel& robot, const World& world);
  ~NaiveBulletBackend() override;
  NaiveBulletBackend(const NaiveBulletBackend&) = delete;
  NaiveBulletBackend& operator=(const NaiveBulletBackend&) = delete;

  std::string name() const override { return "bullet_naive"; }
  void SetPose(const Pose2& pose) override;
  void SetTargets(const DriveTargets& targets) override;
  void Step(double dt, std::vector<Contact>* contacts) override;

  Pose2 pose() const override;
  Twist2 twist() const override;
  const std::vector<double>& wheel_velocities() const override;
  const std::vector<double>& wheel_positions() const override;

 private:
  // Wheel joint speed: the wheel's angular velocity relative to the chassis about its axle.
  double WheelSpeed(int i) const;
  bool IsRobot(const btCollisionObject* o) const;

  double torque_limit_ = 0.0;
  btTransform body_in_root_;                 // chassis box frame in the root frame
  std::array<btVector3, 4> wheel_in_root_;   // wheel centres in the root frame
  std::array<double, 4> targets_{};
  std::array<double, 4> angles_{};
  mutable std::vector<double> velocities_out_, positions_out_;

  std::unique_ptr<btDefaultCollisionConfiguration> collision_config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btBroadphaseInterface> broadphase_;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> dynamics_world_;
  std::unique_ptr<BulletWorldObjects> world_objects_;
  std::unique_ptr<btStaticPlaneShape> ground_shape_;
  std::unique_ptr<btCollisionObject> ground_;
  std::unique_ptr<btBoxShape> chassis_shape_;
  std::unique_ptr<btRigidBody> chassis_;
  std::array<std::unique_ptr<btCylinderShape>, 4> wheel_shapes_;
  std::array<std::unique_ptr<btRigidBody>, 4> wheels_;
  std::array<std::unique_ptr<btHingeConstraint>, 4> hinges_;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_NAIVE_BULLET_BACKEND_H_
