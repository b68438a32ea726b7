// BulletBackend: the default, physical backend ("bullet").
//
// Model. The robot drives on a flat floor (z = 0), so its chassis is one planar btRigidBody (x, y,
// yaw free; z, roll, pitch locked with linear/angular factors, no gravity) carrying the whole
// robot's mass and yaw inertia about its centre of mass, in a btDiscreteDynamicsWorld holding the
// static world. Walls stop it through Bullet's own contacts: the chassis' collision shape is a
// compound of every link's collision shapes (BodyParts: each shape's outline from above extruded
// over its own height band, a convex hull with polyhedral features, so faces are clipped into full
// manifolds), so a mast, a bumper or a wheel meets what is at its height and a table top above the
// body does not stop it; Bullet's sequential-impulse solver resolves the contacts (split impulses:
// pushing out of a wall never becomes a bounce).
//
// Wheels are not Bullet bodies. Each driven wheel is a 1-DOF rotor (axle inertia from the URDF)
// driven by a velocity motor whose torque is clamped to the drive's torque — what Gazebo's drive
// plugins do with a joint's "vel"/"fmax". Each wheel touches the floor at one point under its
// centre with the normal load N it carries at rest (m g shared by the least-norm statics of all
// floor contacts about the centre of mass: the wheels and the casters, which carry load but no
// traction). A holonomic base (planar move) is instead given the commanded body velocity every
// step, as Gazebo's planar-move plugin sets the model's velocity; walls still stop it. Before
// every Bullet step the wheel–ground contacts are solved as velocity-level constraints by projected Gauss–Seidel (sequential impulses, warm
// started): per wheel one block couples the motor, the longitudinal slip (chassis velocity at the
// contact minus r·ω) and the lateral slip; its friction impulse is confined to Coulomb's
// anisotropic friction ellipse (λ_along / μ1 N dt)² + (λ_across / μ2 N dt)² ≤ 1 (mu1/mu2 of the
// URDF's wheel links) and, when sliding, chosen by maximum dissipation (force opposing the slip in
// the ellipse's metric). The impulses change the chassis velocity and the wheel spins; then Bullet
// resolves wall contacts and integrates. So skid-steer turning slips (lateral friction resists the
// yaw the wheel speeds ask for: in place, the yaw rate settles at b²/(a²+b²) of the no-slip rate
// for wheels at (±a, ±b)), acceleration is limited by torque and by friction, and the wheels spin
// when the robot pushes a wall.
//
// Why not wheels as Bullet bodies: the straightforward set-up (NaiveBulletBackend: chassis + four
// hinge-motor wheel bodies on a ground plane) costs ~17 µs per 1 ms step driving in an apartment
// of ~40 shapes (~25 µs pushing a wall), mostly wheel–ground contact generation and a 5-body
// constraint solve; a simulator aiming at ≥ 100× real time has ~5 µs per step for all physics.
// This model costs ~1.5 µs driving and ~3.8 µs pushing a wall (bench/physics_bench.cpp), and its
// steady speeds and slipping yaw rates agree with the full model within a few per cent
// (bullet_backend_test): slip, torque and friction limits and wall contacts are kept. What it
// leaves out: suspension/pitch, load transfer under acceleration, rolling resistance, climbing
// over obstacles lower than a quarter wheel radius (the parts start there; they are ignored).
//
// Precision: Bullet is used in single precision (the Debian default); the pose is kept in double
// and integrated from Bullet's post-contact velocity, see Step().
#ifndef MINIBOT3D_SIM_BULLET_BACKEND_H_
#define MINIBOT3D_SIM_BULLET_BACKEND_H_

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

class BulletBackend : public PhysicsBackend {
 public:
  BulletBackend(const RobotModel& robot, const World& world);
  ~BulletBackend() override;
  BulletBackend(const BulletBackend&) = delete;
  BulletBackend& operator=(const BulletBackend&) = delete;

  std::string name() const override { return "bullet"; }
  void SetPose(const Pose2& pose) override;
  void SetTargets(const DriveTargets& targets) override;
  void Step(double dt, std::vector<Contact>* contacts) override;

  Pose2 pose() const override;
  Twist2 twist() const override;
  const std::vector<double>& wheel_velocities() const override { return wheel_velocities_; }
  const std::vector<double>& wheel_positions() const override { return wheel_positions_; }

 private:
  // Chassis (+ free wheel) velocity response at a wheel contact to unit impulses along / across:
  // K = [k00 k01; k01 k11] and its inverse.
  struct Response {
    double k00 = 0.0, k01 = 0.0, k11 = 0.0;
    double inv00 = 0.0, inv01 = 0.0, inv11 = 0.0;
  };

  struct Wheel {
    Eigen::Vector2d arm = Eigen::Vector2d::Zero();  // contact point - centre of mass, body frame
    double radius = 0.0;
    double inertia = 0.0;       // about the axle
    double mu1 = 1.0, mu2 = 1.0;
    double load = 0.0;          // normal force (N)
    double target = 0.0;        // commanded joint speed
    double omega = 0.0;         // joint speed
    double angle = 0.0;         // joint angle, unwrapped
    // Impulses accumulated over the last solve, reused as its starting point (warm start): while
    // cruising or pushing they barely change from one step to the next.
    double impulse_along = 0.0, impulse_across = 0.0, impulse_motor = 0.0;
    // Contact response with the wheel held by its motor / spinning free under a saturated motor.
    Response held, spinning;
    double torque = 0.0;        // the motor's torque limit (N m)
    // Per-step impulse limits: friction ellipse semi-axes (and 1 / their squares), motor.
    double limit_along = 0.0, limit_across = 0.0, limit_motor = 0.0;
    double inv_limit2_along = 0.0, inv_limit2_across = 0.0;
  };

  // Solves the wheel–ground and motor constraints for one step, updating the body-frame chassis
  // velocity (*u, *v, *w at the centre of mass) and the wheel spins.
  void SolveWheels(double dt, double* u, double* v, double* w);
  // Returns the largest impulse change it made.
  double SolveWheelBlock(Wheel* wheel, double* u, double* v, double* w) const;
  static void FrictionImpulse(const Wheel& wheel, const Response& k, double s_along,
                              double s_across, double* along, double* across);
  void AppendContacts(std::vector<Contact>* contacts);
  void PutChassisAt(const Pose2& com_pose);

  double mass_ = 0.0;
  double inertia_z_ = 0.0;  // about the centre of mass
  double inv_mass_ = 0.0, inv_inertia_ = 0.0;
  Eigen::Vector2d com_ = Eigen::Vector2d::Zero();  // centre of mass in the root frame
  double com_height_ = 0.0;
  // The chassis' centre-of-mass pose in double precision: the authoritative pose (see Step()).
  Pose2 com_pose_;
  std::vector<Wheel> wheels_;
  std::vector<double> wheel_velocities_, wheel_positions_;
  // A holonomic base (planar move) is given its body twist directly; its wheels idle.
  bool body_velocity_ = false;
  Twist2 body_twist_;
  double last_dt_ = 0.0;

  std::unique_ptr<btDefaultCollisionConfiguration> collision_config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btBroadphaseInterface> broadphase_;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> dynamics_world_;
  std::unique_ptr<BulletWorldObjects> world_objects_;
  std::unique_ptr<btCompoundShape> chassis_shape_;                  // one child per body part
  std::vector<std::unique_ptr<btConvexHullShape>> part_hulls_;
  std::unique_ptr<btRigidBody> chassis_;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_BULLET_BACKEND_H_
