#include "bullet_backend.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>

namespace minibot3d_sim {
namespace {

constexpr double kGravity = 9.81;
// Gauss–Seidel sweeps over the four wheel blocks per step, until no impulse changes by more than
// kWheelTolerance (N s). Each block is solved exactly and the solve is warm-started from the
// previous step, so one or two sweeps usually suffice (trajectories after 3 s agree with a
// 64-sweep solve to ~1e-5 m).
constexpr int kMaxWheelIterations = 8;
constexpr double kWheelTolerance = 1e-7;

// The chassis hull is inflated by its margin; 1 mm is invisible to a navigation robot.
constexpr btScalar kChassisMargin = 0.001;
// Manifold points within this distance (m) after the step count as touching.
constexpr double kTouchingDistance = 1e-3;
// A filter group of its own for floor planes: the planar chassis rides on z = 0 and must not
// collide with the floor it is held above.
constexpr int kFloorGroup = 1 << 6;
// Chassis–wall friction (Bullet multiplies it with the wall's default 0.5).
constexpr btScalar kChassisFriction = 0.6;

double YawOf(const btTransform& t) {
  const btMatrix3x3& b = t.getBasis();
  return std::atan2(b[1][0], b[0][0]);
}

}  // namespace

// The friction impulse of one wheel given the slip velocity s (along, across) its contact has
// with the impulse `acc` currently applied. Exactly solves
//   minimise ½ λᵀ K λ + λᵀ s0   subject to   (λ_along / L_along)² + (λ_across / L_across)² ≤ 1,
// s0 = s − K acc being the slip without this wheel's friction: inside the ellipse the contact
// sticks (post-impulse slip 0); on its boundary the optimality condition says the post-impulse slip
// is normal to the ellipse, i.e. λ ∝ −(L_along² s_along, L_across² s_across) — Coulomb's maximum
// dissipation for anisotropic friction. (Scaling the sticking impulse onto the ellipse instead
// would be exact only for isotropic friction.) Boundary case: a 2-D trust-region problem, solved
// with Newton on the secular equation 1/|z(ν)| = 1 in coordinates where the ellipse is the unit
// circle (Moré & Sorensen 1983).
void BulletBackend::FrictionImpulse(const Wheel& wheel, const Response& k, double s_along,
                                    double s_across, double* along, double* across) {
  const double acc_a = wheel.impulse_along, acc_c = wheel.impulse_across;
  // Sticking impulse: the slip after it is zero.
  double la = acc_a - (k.inv00 * s_along + k.inv01 * s_across);
  double lc = acc_c - (k.inv01 * s_along + k.inv11 * s_across);
  const double l1 = wheel.limit_along, l2 = wheel.limit_across;
  if (la * la * wheel.inv_limit2_along + lc * lc * wheel.inv_limit2_across <= 1.0 && l1 > 0.0 &&
      l2 > 0.0) {
    *along = la;
    *across = lc;
    return;
  }
  const double s0a = s_along - (k.k00 * acc_a + k.k01 * acc_c);
  const double s0c = s_across - (k.k01 * acc_a + k.k11 * acc_c);
  if (!(l1 > 0.0) || !(l2 > 0.0)) {
    // Degenerate ellipse (a mu or the load is 0): friction in one direction at most.
    *along = l1 > 0.0 ? std::clamp(-s0a / k.k00, -l1, l1) : 0.0;
    *across = l2 > 0.0 ? std::clamp(-s0c / k.k11, -l2, l2) : 0.0;
    return;
  }
  // z = (λ_along / l1, λ_across / l2): minimise ½ zᵀ Q z + cᵀ z over |z| <= 1.
  const double q00 = l1 * l1 * k.k00, q01 = l1 * l2 * k.k01, q11 = l2 * l2 * k.k11;
  const double c0 = l1 * s0a, c1 = l2 * s0c;
  double nu = 0.0, z0 = 0.0, z1 = 0.0;
  for (int i = 0; i < 20; ++i) {
    // z(ν) = −(Q + ν I)⁻¹ c
    const double a00 = q00 + nu, a11 = q11 + nu;
    const double inv_det = 1.0 / (a00 * a11 - q01 * q01);
    z0 = -(a11 * c0 - q01 * c1) * inv_det;
    z1 = -(a00 * c1 - q01 * c0) * inv_det;
    const double norm2 = z0 * z0 + z1 * z1;
    const double norm = std::sqrt(norm2);
    // φ(ν) = 1/|z| − 1 is concave and increasing: Newton from ν = 0 (|z| > 1) never overshoots.
    const double phi = 1.0 / norm - 1.0;
    if (std::abs(phi) < 1e-10) break;
    // φ'(ν) = zᵀ (Q + ν I)⁻¹ z / |z|³
    const double w0 = (a11 * z0 - q01 * z1) * inv_det;
    const double w1 = (a00 * z1 - q01 * z0) * inv_det;
    nu -= phi * norm2 * norm / (z0 * w0 + z1 * w1);
    if (nu < 0.0) nu = 0.0;
  }
  const double n = std::hypot(z0, z1);
  if (n > 1.0) {  // stay inside despite rounding
    z0 /= n;
    z1 /= n;
  }
  *along = l1 * z0;
  *across = l2 * z1;
}

namespace {

// Centre of mass in the root frame: the body box and the wheels, each at its centre.
Eigen::Vector2d CentreOfMass(const RobotModel& robot) {
  const Eigen::Vector3d body_centre = robot.body_pose.translation();
  double m_sum = std::max(robot.body_mass, 0.0);
  Eigen::Vector2d moment = m_sum * body_centre.head<2>();
  for (const WheelSpec& w : robot.wheels) {
    m_sum += std::max(w.mass, 0.0);
    moment += std::max(w.mass, 0.0) * w.position.head<2>();
  }
  return m_sum > 0.0 ? Eigen::Vector2d(moment / m_sum) : Eigen::Vector2d(body_centre.head<2>());
}

// Yaw inertia: given about the root; moved to the centre of mass (parallel axis theorem), or the
// body box's when that leaves nothing.
double YawInertia(const RobotModel& robot, double mass, const Eigen::Vector2d& com) {
  double inertia = robot.body_inertia_z - mass * com.squaredNorm();
  if (!(inertia > 0.0)) {
    const Eigen::Vector3d& s = robot.body_size;
    inertia = std::max(mass * (s.x() * s.x() + s.y() * s.y()) / 12.0, 1e-6);
  }
  return inertia;
}

// A wheel the backend can drive: a radius and a torque limit.
const WheelSpec& CheckedWheel(const WheelSpec& spec) {
  if (!(spec.radius > 0.0)) throw std::invalid_argument("BulletBackend: wheel radius must be > 0");
  if (!(spec.torque > 0.0)) {
    throw std::invalid_argument("BulletBackend: wheel '" + spec.joint + "' has no torque > 0");
  }
  return spec;
}

// Static loads of the floor contacts (wheels, then casters): the least-norm N with sum N = m g
// and no moment about the centre of mass; with more than three supports this is the symmetric
// answer of a statically indeterminate problem.
Eigen::VectorXd StaticLoads(const RobotModel& robot, const Eigen::Vector2d& com, double mass) {
  const int n = static_cast<int>(robot.wheels.size());
  const int contacts = n + static_cast<int>(robot.supports.size());
  Eigen::Matrix<double, 3, Eigen::Dynamic> a(3, contacts);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d arm = robot.wheels[i].position.head<2>() - com;
    a.col(i) << 1.0, arm.x(), arm.y();
  }
  for (int i = n; i < contacts; ++i) {
    const Eigen::Vector2d arm = robot.supports[i - n].position - com;
    a.col(i) << 1.0, arm.x(), arm.y();
  }
  const Eigen::Vector3d b(mass * kGravity, 0.0, 0.0);
  const Eigen::Matrix3d aat = a * a.transpose();
  Eigen::VectorXd loads = Eigen::VectorXd::Constant(contacts, mass * kGravity / std::max(contacts, 1));
  if (contacts > 0 && std::abs(aat.determinant()) > 1e-12) {
    loads = a.transpose() * aat.ldlt().solve(b);
    loads = loads.cwiseMax(0.0);  // centre of mass outside the supports: the far ones lift
    loads *= mass * kGravity / loads.sum();
  }
  return loads;
}

void ConfigureWorld(btDiscreteDynamicsWorld* world) {
  world->setGravity(btVector3(0, 0, 0));  // the floor carries the weight: planar body
  world->setForceUpdateAllAabbs(false);
  btContactSolverInfo& info = world->getSolverInfo();
  // Resolve every penetration with split impulses (position only), so pushing out of a wall
  // never turns into a bounce-back velocity.
  info.m_splitImpulse = 1;
  info.m_splitImpulsePenetrationThreshold = 1e6;
  // One body against static geometry, warm-started: 4 sweeps hold it against a wall as well as
  // the default 10 (0.3 mm difference in the resting position) at ~20 % less cost per contact step.
  info.m_numIterations = 4;
}

// The robot's height band, from the floor clearance to its top part; the chassis only meets meshes
// within it, where they become boxes a few centimetres tall each.
MeshBand ChassisBand(const std::vector<BodyPart>& parts) {
  MeshBand band;
  band.z_min = std::numeric_limits<double>::infinity();
  band.z_max = -band.z_min;
  for (const BodyPart& p : parts) {
    band.z_min = std::min(band.z_min, p.z_min);
    band.z_max = std::max(band.z_max, p.z_max);
  }
  if (!(band.z_max > band.z_min)) band.z_max = band.z_min + 0.01;
  band.layers = std::max(1, static_cast<int>(std::ceil((band.z_max - band.z_min) / 0.05)));
  return band;
}

// Floor planes go into a filter group of their own, which the chassis does not collide with.
void MarkFloorPlanes(btDiscreteDynamicsWorld* world) {
  btCollisionObjectArray& objects = world->getCollisionObjectArray();
  for (int i = 0; i < objects.size(); ++i) {
    btCollisionObject* o = objects[i];
    if (o->getCollisionShape()->getShapeType() != STATIC_PLANE_PROXYTYPE) continue;
    const auto* plane = static_cast<const btStaticPlaneShape*>(o->getCollisionShape());
    const btVector3 n = o->getWorldTransform().getBasis() * plane->getPlaneNormal();
    if (std::abs(n.z()) > 0.7) o->getBroadphaseHandle()->m_collisionFilterGroup = kFloorGroup;
  }
}

// Radius of the largest circle about the centre of mass inside the outline (for CCD).
double InnerRadius(const std::vector<Eigen::Vector2d>& outline, const Eigen::Vector2d& com) {
  double inner_radius = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < outline.size(); ++i) {
    const Eigen::Vector2d e = outline[(i + 1) % outline.size()] - outline[i];
    const Eigen::Vector2d to_com = com - outline[i];
    if (e.norm() > 0.0) {
      inner_radius = std::min(inner_radius, std::abs(e.x() * to_com.y() - e.y() * to_com.x()) /
                                                e.norm());
    }
  }
  if (!std::isfinite(inner_radius) || inner_radius <= 0.0) inner_radius = 0.01;
  return inner_radius;
}

// The part of the largest area seen from above (the body, on any robot with one).
const BodyPart& LargestPart(const std::vector<BodyPart>& parts) {
  const auto area = [](const BodyPart& p) {
    double a2 = 0.0;
    for (std::size_t i = 0; i < p.outline.size(); ++i) {
      const Eigen::Vector2d& u = p.outline[i];
      const Eigen::Vector2d& v = p.outline[(i + 1) % p.outline.size()];
      a2 += u.x() * v.y() - u.y() * v.x();
    }
    return std::abs(a2);
  };
  return *std::max_element(parts.begin(), parts.end(), [&](const BodyPart& a, const BodyPart& b) {
    return area(a) < area(b);
  });
}

// One hull per body part: its outline extruded over its band, relative to the centre of mass.
// Polyhedral features let Bullet clip whole faces against boxes (a full contact manifold in one
// step) instead of adding one GJK point per step.
std::unique_ptr<btConvexHullShape> PartHull(const BodyPart& part, const Eigen::Vector2d& com,
                                            double com_height) {
  auto hull = std::make_unique<btConvexHullShape>();
  for (const Eigen::Vector2d& p : part.outline) {
    const Eigen::Vector2d q = p - com;
    hull->addPoint(btVector3(q.x(), q.y(), part.z_min - com_height), false);
    hull->addPoint(btVector3(q.x(), q.y(), part.z_max - com_height), false);
  }
  hull->recalcLocalAabb();
  hull->setMargin(kChassisMargin);
  hull->initializePolyhedralFeatures();
  return hull;
}

// The planar chassis body: x, y and yaw free, no damping, bouncing or gyroscopic terms.
std::unique_ptr<btRigidBody> MakeChassis(double mass, double inertia_z, btCollisionShape* shape,
                                         double inner_radius) {
  btRigidBody::btRigidBodyConstructionInfo ci(mass, nullptr, shape,
                                              btVector3(inertia_z, inertia_z, inertia_z));
  ci.m_friction = kChassisFriction;
  ci.m_restitution = 0;
  ci.m_linearDamping = 0;
  ci.m_angularDamping = 0;
  auto chassis = std::make_unique<btRigidBody>(ci);
  chassis->setLinearFactor(btVector3(1, 1, 0));
  chassis->setAngularFactor(btVector3(0, 0, 1));
  chassis->setFlags(0);  // no gyroscopic terms: yaw only
  chassis->setActivationState(DISABLE_DEACTIVATION);
  // Continuous collision (a swept sphere inside the hull) only for steps that move the chassis by
  // more than half its inner radius; smaller steps are caught by discrete contacts, and sweeping
  // every step would cost more than the rest of the step.
  chassis->setCcdMotionThreshold(0.5 * inner_radius);
  chassis->setCcdSweptSphereRadius(0.8 * inner_radius);
  return chassis;
}

}  // namespace

BulletBackend::BulletBackend(const RobotModel& robot, const World& world) {
  mass_ = robot.total_mass;
  if (!(mass_ > 0.0)) throw std::invalid_argument("BulletBackend: robot total_mass must be > 0");
  com_ = CentreOfMass(robot);
  com_height_ = robot.body_pose.translation().z();
  inertia_z_ = YawInertia(robot, mass_, com_);

  const int n = static_cast<int>(robot.wheels.size());
  wheels_.resize(n);
  wheel_velocities_.assign(n, 0.0);
  wheel_positions_.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    const WheelSpec& spec = CheckedWheel(robot.wheels[i]);
    Wheel& w = wheels_[i];
    w.arm = spec.position.head<2>() - com_;
    w.radius = spec.radius;
    w.inertia = spec.inertia_axle > 0.0 ? spec.inertia_axle
                                        : 0.5 * std::max(spec.mass, 0.01) * w.radius * w.radius;
    w.mu1 = std::max(spec.mu1, 0.0);
    w.mu2 = std::max(spec.mu2, 0.0);
    w.torque = spec.torque;
  }
  const Eigen::VectorXd loads = StaticLoads(robot, com_, mass_);
  inv_mass_ = 1.0 / mass_;
  inv_inertia_ = 1.0 / inertia_z_;
  for (int i = 0; i < n; ++i) {
    Wheel& w = wheels_[i];
    w.load = loads[i];
    // Chassis response at the contact to unit impulses along / across the rolling direction,
    // K = [k00 k01; k01 k11]; with a spinning (torque-limited) wheel its own response r^2 / I
    // adds to k00. Both inverses are constant in the body frame.
    const double px = w.arm.x(), py = w.arm.y();
    const double k00 = inv_mass_ + py * py * inv_inertia_;
    const double k11 = inv_mass_ + px * px * inv_inertia_;
    const double k01 = -px * py * inv_inertia_;
    auto response = [&](double a00, Response* out) {
      const double det = a00 * k11 - k01 * k01;
      *out = Response{a00, k01, k11, k11 / det, -k01 / det, a00 / det};
    };
    response(k00, &w.held);
    response(k00 + w.radius * w.radius / w.inertia, &w.spinning);
  }

  // Bullet world: only the chassis moves, so the broadphase sees one moving proxy against the
  // static set and the static AABBs are never recomputed.
  collision_config_ = std::make_unique<btDefaultCollisionConfiguration>();
  dispatcher_ = std::make_unique<btCollisionDispatcher>(collision_config_.get());
  broadphase_ = std::make_unique<btDbvtBroadphase>();
  solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
  dynamics_world_ = std::make_unique<btDiscreteDynamicsWorld>(
      dispatcher_.get(), broadphase_.get(), solver_.get(), collision_config_.get());
  ConfigureWorld(dynamics_world_.get());
  const std::vector<BodyPart> parts = BodyParts(robot);
  if (parts.empty()) throw std::invalid_argument("BulletBackend: the robot has no body part");
  world_objects_ =
      std::make_unique<BulletWorldObjects>(world, dynamics_world_.get(), ChassisBand(parts));
  MarkFloorPlanes(dynamics_world_.get());
  chassis_shape_ = std::make_unique<btCompoundShape>(/*enableDynamicAabbTree=*/parts.size() > 4);
  for (const BodyPart& part : parts) {
    part_hulls_.push_back(PartHull(part, com_, com_height_));
    chassis_shape_->addChildShape(btTransform::getIdentity(), part_hulls_.back().get());
  }
  chassis_ = MakeChassis(mass_, inertia_z_, chassis_shape_.get(),
                         InnerRadius(LargestPart(parts).outline, com_));
  dynamics_world_->addRigidBody(chassis_.get(), btBroadphaseProxy::DefaultFilter,
                                btBroadphaseProxy::StaticFilter);
  SetPose(Pose2{});
}

BulletBackend::~BulletBackend() {
  dynamics_world_->removeRigidBody(chassis_.get());
  world_objects_.reset();
}

void BulletBackend::SetPose(const Pose2& pose) {
  const Eigen::Vector2d c = TransformPoint(pose, com_);
  com_pose_ = Pose2{c.x(), c.y(), NormalizeAngle(pose.yaw)};
  PutChassisAt(com_pose_);
  chassis_->setLinearVelocity(btVector3(0, 0, 0));
  chassis_->setAngularVelocity(btVector3(0, 0, 0));
  chassis_->setInterpolationLinearVelocity(btVector3(0, 0, 0));
  chassis_->setInterpolationAngularVelocity(btVector3(0, 0, 0));
  chassis_->clearForces();
  if (chassis_->getBroadphaseHandle() != nullptr) {
    dynamics_world_->updateSingleAabb(chassis_.get());
    // Old contact points (and their warm-start impulses) belong to the old place.
    broadphase_->getOverlappingPairCache()->cleanProxyFromPairs(chassis_->getBroadphaseHandle(),
                                                                dispatcher_.get());
  }
  for (size_t i = 0; i < wheels_.size(); ++i) {
    Wheel& w = wheels_[i];
    w.omega = 0.0;
    w.impulse_along = w.impulse_across = w.impulse_motor = 0.0;
    wheel_velocities_[i] = 0.0;
  }
  last_dt_ = 0.0;
}

void BulletBackend::SetTargets(const DriveTargets& targets) {
  body_velocity_ = targets.body_velocity;
  body_twist_ = targets.body_twist;
  for (size_t i = 0; i < wheels_.size(); ++i) {
    wheels_[i].target = body_velocity_ ? 0.0 : targets.wheel_speeds[i];
  }
}

double BulletBackend::SolveWheelBlock(Wheel* wheel, double* u, double* v, double* w) const {
  const double px = wheel->arm.x(), py = wheel->arm.y();
  const double r = wheel->radius, inv_iw = 1.0 / wheel->inertia;
  // Chassis velocity at the contact point, along and across the rolling direction.
  const double v_along = *u - *w * py;
  const double v_across = *v + *w * px;

  // Case 1: the motor holds the wheel at its target speed, so the slip along is the chassis
  // point's speed minus r·target.
  double along, across;
  FrictionImpulse(*wheel, wheel->held, v_along - r * wheel->target, v_across, &along, &across);
  double d_along = along - wheel->impulse_along;
  // Motor impulse that puts the wheel at its target against the friction reaction.
  double d_motor = wheel->inertia * (wheel->target - wheel->omega) + r * d_along;
  double motor = wheel->impulse_motor + d_motor;
  if (std::abs(motor) > wheel->limit_motor) {
    // Case 2: the motor is at its torque limit; the wheel spins freely under the limited torque
    // and the friction reaction, so its inertia joins the longitudinal response.
    motor = std::clamp(motor, -wheel->limit_motor, wheel->limit_motor);
    d_motor = motor - wheel->impulse_motor;
    const double s_along = v_along - r * (wheel->omega + d_motor * inv_iw);
    FrictionImpulse(*wheel, wheel->spinning, s_along, v_across, &along, &across);
    d_along = along - wheel->impulse_along;
  }
  const double d_across = across - wheel->impulse_across;
  *u += inv_mass_ * d_along;
  *v += inv_mass_ * d_across;
  *w += inv_inertia_ * (px * d_across - py * d_along);
  wheel->omega += (d_motor - r * d_along) * inv_iw;
  wheel->impulse_along = along;
  wheel->impulse_across = across;
  wheel->impulse_motor = motor;
  return std::max({std::abs(d_along), std::abs(d_across), std::abs(d_motor)});
}

void BulletBackend::SolveWheels(double dt, double* u, double* v, double* w) {
  // Warm start: re-apply last step's impulses (rescaled if the step changed).
  const double scale = last_dt_ > 0.0 ? dt / last_dt_ : 0.0;
  for (Wheel& wh : wheels_) {
    wh.limit_along = wh.mu1 * wh.load * dt;
    wh.limit_across = wh.mu2 * wh.load * dt;
    wh.inv_limit2_along = wh.limit_along > 0.0 ? 1.0 / (wh.limit_along * wh.limit_along) : 0.0;
    wh.inv_limit2_across =
        wh.limit_across > 0.0 ? 1.0 / (wh.limit_across * wh.limit_across) : 0.0;
    wh.limit_motor = wh.torque * dt;
    wh.impulse_along *= scale;
    wh.impulse_across *= scale;
    wh.impulse_motor *= scale;
    *u += inv_mass_ * wh.impulse_along;
    *v += inv_mass_ * wh.impulse_across;
    *w += inv_inertia_ * (wh.arm.x() * wh.impulse_across - wh.arm.y() * wh.impulse_along);
    wh.omega += (wh.impulse_motor - wh.radius * wh.impulse_along) / wh.inertia;
  }
  for (int it = 0; it < kMaxWheelIterations; ++it) {
    double change = 0.0;
    for (Wheel& wh : wheels_) change = std::max(change, SolveWheelBlock(&wh, u, v, w));
    if (change < kWheelTolerance) break;
  }
  last_dt_ = dt;
}

void BulletBackend::Step(double dt, std::vector<Contact>* contacts) {
  if (!(dt > 0.0)) return;
  const double c = std::cos(com_pose_.yaw), s = std::sin(com_pose_.yaw);
  const btVector3 lv = chassis_->getLinearVelocity();
  double u = c * lv.x() + s * lv.y();
  double v = -s * lv.x() + c * lv.y();
  double w = chassis_->getAngularVelocity().z();

  if (body_velocity_) {
    // The commanded twist of the root, at the centre of mass: v + w × (com − root).
    w = body_twist_.wz;
    u = body_twist_.vx - w * com_.y();
    v = body_twist_.vy + w * com_.x();
    for (Wheel& wh : wheels_) wh.omega = 0.0;
  } else {
    SolveWheels(dt, &u, &v, &w);
  }

  chassis_->setLinearVelocity(btVector3(c * u - s * v, s * u + c * v, 0));
  chassis_->setAngularVelocity(btVector3(0, 0, w));
  // One internal step of exactly dt (maxSubSteps = 0): the simulator owns the fixed step.
  dynamics_world_->stepSimulation(dt, 0, dt);

  // Bullet's single-precision transform loses ~1e-7 of the distance from the origin every step
  // (2 % of the distance travelled at 0.05 m/s, 40 m out). The pose is therefore integrated in
  // double from Bullet's post-contact velocity, exactly as Bullet integrates it (x += v dt,
  // yaw += w dt), and Bullet's own result is taken only when it moved the chassis otherwise, i.e.
  // when split impulses pushed it out of a wall.
  const btVector3 v1 = chassis_->getLinearVelocity();
  const double w1 = chassis_->getAngularVelocity().z();
  Pose2 next{com_pose_.x + v1.x() * dt, com_pose_.y + v1.y() * dt,
             NormalizeAngle(com_pose_.yaw + w1 * dt)};
  const btTransform& t1 = chassis_->getWorldTransform();
  const double rounding =
      8.0 * std::numeric_limits<btScalar>::epsilon() *
      std::max({1.0, std::abs(next.x), std::abs(next.y)});
  const double yaw1 = YawOf(t1);
  if (std::abs(t1.getOrigin().x() - next.x) > rounding ||
      std::abs(t1.getOrigin().y() - next.y) > rounding ||
      std::abs(NormalizeAngle(yaw1 - next.yaw)) > 8.0 * std::numeric_limits<btScalar>::epsilon()) {
    next = Pose2{t1.getOrigin().x(), t1.getOrigin().y(), yaw1};
  }
  com_pose_ = next;
  PutChassisAt(com_pose_);

  for (size_t i = 0; i < wheels_.size(); ++i) {
    wheels_[i].angle += wheels_[i].omega * dt;
    wheel_velocities_[i] = wheels_[i].omega;
    wheel_positions_[i] = wheels_[i].angle;
  }
  if (contacts != nullptr) AppendContacts(contacts);
}

void BulletBackend::PutChassisAt(const Pose2& com_pose) {
  const btTransform t(btQuaternion(btVector3(0, 0, 1), com_pose.yaw),
                      btVector3(com_pose.x, com_pose.y, com_height_));
  chassis_->setWorldTransform(t);
  chassis_->setInterpolationWorldTransform(t);
}

void BulletBackend::AppendContacts(std::vector<Contact>* contacts) {
  const int n = dispatcher_->getNumManifolds();
  for (int i = 0; i < n; ++i) {
    btPersistentManifold* m = dispatcher_->getManifoldByIndexInternal(i);
    const btCollisionObject* a = m->getBody0();
    const btCollisionObject* b = m->getBody1();
    const bool robot_is_a = a == chassis_.get();
    if (!robot_is_a && b != chassis_.get()) continue;
    const btCollisionObject* other = robot_is_a ? b : a;
    for (int j = 0; j < m->getNumContacts(); ++j) {
      const btManifoldPoint& p = m->getContactPoint(j);
      // The point was measured before integration: its distance at the new poses (what
      // btPersistentManifold::refreshContactPoints computes, without editing the manifold, so
      // that asking for contacts never changes the simulation).
      const btVector3 on_a = a->getWorldTransform() * p.m_localPointA;
      const btVector3 on_b = b->getWorldTransform() * p.m_localPointB;
      const btScalar distance = (on_a - on_b).dot(p.m_normalWorldOnB);
      if (distance > kTouchingDistance) continue;
      // Bullet's normal points from B towards A.
      const btVector3 normal = robot_is_a ? p.m_normalWorldOnB : -p.m_normalWorldOnB;
      const btVector3& at = robot_is_a ? on_b : on_a;
      Contact contact;
      contact.point = Eigen::Vector3d(at.x(), at.y(), at.z());
      contact.normal = Eigen::Vector3d(normal.x(), normal.y(), normal.z());
      contact.depth = std::max(0.0, -static_cast<double>(distance));
      contact.shape = other->getUserIndex();
      contacts->push_back(contact);
    }
  }
}

Pose2 BulletBackend::pose() const {
  const double c = std::cos(com_pose_.yaw), s = std::sin(com_pose_.yaw);
  return Pose2{com_pose_.x - (c * com_.x() - s * com_.y()),
               com_pose_.y - (s * com_.x() + c * com_.y()), com_pose_.yaw};
}

Twist2 BulletBackend::twist() const {
  const double c = std::cos(com_pose_.yaw), s = std::sin(com_pose_.yaw);
  const btVector3 lv = chassis_->getLinearVelocity();
  const double w = chassis_->getAngularVelocity().z();
  // Body-frame velocity of the centre of mass, then moved to the root: v + w × (root - com).
  const double u = c * lv.x() + s * lv.y();
  const double v = -s * lv.x() + c * lv.y();
  return Twist2{u + w * com_.y(), v - w * com_.x(), w};
}

}  // namespace minibot3d_sim
