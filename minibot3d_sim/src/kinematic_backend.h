// KinematicBackend: the robot moves exactly as its wheel speeds say, with no dynamics.
//
// Model: the no-slip body twist the drive's targets ask for (DriveTargets::body_twist: the wheel
// speeds' twist for a wheeled drive, the command for a holonomic one), integrated exactly as a
// constant twist over each step (a straight line or a circular arc, IntegrateTwist). Walls are
// handled by refusing steps: every body part (each link's collision shapes) at the step's end pose
// is tested against the world's cross-sections at the heights it spans (BodyCollider). A step that
// would overlap is not taken, the robot stands still (twist 0, wheels 0) and a Contact is
// reported. Since a blocked step is never taken the robot never penetrates anything, and reversing
// out of a contact is always possible.
//
// It is meant to be cheap (well under 1 µs per step in the open): the overlap tests run only when
// the robot may have come within reach of an obstacle. A clearance is cached and steps are taken
// unchecked until the motion since then uses it up: in the open, the clearance of the robot's
// centre in every cross-section minus the parts' radius (used up by the centre's travel); near
// walls, a margin the body grown by it is clear by (used up by the furthest a body point can
// move, translation plus radius times rotation), halved after a miss and doubled after a hit, so
// a robot driving beside a wall or backing out of a contact tests its polygons every few dozen
// steps rather than every step. A step refused once is refused again without a test while the
// robot stands still and asks the same.
#ifndef MINIBOT3D_SIM_KINEMATIC_BACKEND_H_
#define MINIBOT3D_SIM_KINEMATIC_BACKEND_H_

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "minibot3d_sim/body_collider.h"
#include "minibot3d_sim/physics_backend.h"
#include "minibot3d_sim/robot_model.h"
#include "minibot3d_sim/world.h"
#include "minibot3d_sim/world_slice.h"

namespace minibot3d_sim {

class KinematicBackend : public PhysicsBackend {
 public:
  // `slices` (of `world`; null: the backend keeps its own) must outlive the backend.
  KinematicBackend(const RobotModel& robot, const World& world, SliceCache* slices = nullptr);

  std::string name() const override { return "kinematic"; }
  void SetPose(const Pose2& pose) override;
  void SetTargets(const DriveTargets& targets) override;
  void Step(double dt, std::vector<Contact>* contacts) override;

  Pose2 pose() const override { return pose_; }
  Twist2 twist() const override { return twist_; }
  const std::vector<double>& wheel_velocities() const override { return wheel_velocities_; }
  const std::vector<double>& wheel_positions() const override { return wheel_positions_; }

  // Number of steps that ran the polygon test (for tests and benchmarks of the distance cache).
  long collision_checks() const { return collision_checks_; }

 private:
  // Whether a body part at `p` overlaps the world; *shape gets one shape it touches, and the part
  // and cross-section are remembered for MakeContact.
  bool Collides(const Pose2& p, int* shape);
  // The contact of the last overlapping part at pose_ with the nearest world geometry of `shape`
  // in the last overlapping cross-section (any shape when none matches).
  Contact MakeContact(int shape) const;

  std::unique_ptr<SliceCache> own_slices_;
  BodyCollider collider_;
  BodyCollider::Hit hit_;

  Pose2 pose_;
  Twist2 twist_;
  DriveTargets targets_;
  std::vector<double> wheel_velocities_;
  std::vector<double> wheel_positions_;

  // Clearance cache, filled at a pose the robot then moved to: kCentre: nothing within
  // clearance_ of the centre's reach (clearance_ + collider_.radius()), used up by the centre's
  // travel; kBody: nothing within clearance_ of the body, used up by the furthest a body point
  // moves. travelled_ sums the motion since it was filled.
  enum class Cache { kNone, kCentre, kBody };
  void Fill(Cache kind, double clearance);
  static constexpr double kMinMargin = 0.001, kMaxMargin = 0.064;  // m
  Cache cache_ = Cache::kNone;
  double clearance_ = 0.0;
  double travelled_ = 0.0;
  double margin_ = 0.008;  // m, the next body margin tried
  bool start_colliding_ = false;  // after SetPose into an obstacle, see Step()

  // The state at the start of the last step, restored by SetPose to that pose.
  struct StepStart {
    bool valid = false;
    Pose2 pose;
    bool colliding = false;
    Cache cache = Cache::kNone;
    double clearance = 0.0, travelled = 0.0;
  };
  StepStart step_start_;

  // The end pose of the last step, when it was refused and the robot has not moved since.
  bool blocked_end_valid_ = false;
  Pose2 blocked_end_;

  // The last blocked step's contact, valid while the robot has not moved since.
  bool blocked_contact_valid_ = false;
  Contact blocked_contact_;
  long collision_checks_ = 0;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_KINEMATIC_BACKEND_H_
