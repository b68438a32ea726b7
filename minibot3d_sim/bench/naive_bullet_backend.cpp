#include "naive_bullet_backend.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace minibot3d_sim {
namespace {

constexpr double kGravity = 9.81;
constexpr int kFloorGroup = 1 << 6;   // the world's own floor planes: replaced by ground_
constexpr int kGroundGroup = 1 << 7;  // ground_
constexpr btScalar kRobotMargin = 0.002;
constexpr double kTouchingDistance = 1e-3;

double YawOf(const btTransform& t) {
  const btMatrix3x3& b = t.getBasis();
  return std::atan2(b[1][0], b[0][0]);
}

btTransform RootTransform(const Pose2& pose) {
  return btTransform(btQuaternion(btVector3(0, 0, 1), pose.yaw), btVector3(pose.x, pose.y, 0));
}

}  // namespace

NaiveBulletBackend::NaiveBulletBackend(const RobotModel& robot, const World& world) {
  if (robot.wheels.size() != 4) {
    throw std::invalid_argument("NaiveBulletBackend: a four-wheel robot only");
  }
  torque_limit_ = robot.wheels[0].torque;
  if (!(torque_limit_ > 0.0)) {
    throw std::invalid_argument("NaiveBulletBackend: the drive plugin's torque must be > 0");
  }
  collision_config_ = std::make_unique<btDefaultCollisionConfiguration>();
  dispatcher_ = std::make_unique<btCollisionDispatcher>(collision_config_.get());
  broadphase_ = std::make_unique<btDbvtBroadphase>();
  solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
  dynamics_world_ = std::make_unique<btDiscreteDynamicsWorld>(
      dispatcher_.get(), broadphase_.get(), solver_.get(), collision_config_.get());
  dynamics_world_->setGravity(btVector3(0, 0, -kGravity));
  dynamics_world_->setForceUpdateAllAabbs(false);

  world_objects_ = std::make_unique<BulletWorldObjects>(world, dynamics_world_.get());
  // The world's floor planes have Bullet's default friction; the wheels roll on ground_ instead,
  // whose friction makes the URDF's mu the effective one.
  btCollisionObjectArray& objects = dynamics_world_->getCollisionObjectArray();
  for (int i = 0; i < objects.size(); ++i) {
    btCollisionObject* o = objects[i];
    if (o->getCollisionShape()->getShapeType() != STATIC_PLANE_PROXYTYPE) continue;
    const auto* plane = static_cast<const btStaticPlaneShape*>(o->getCollisionShape());
    const btVector3 n = o->getWorldTransform().getBasis() * plane->getPlaneNormal();
    if (std::abs(n.z()) > 0.7) o->getBroadphaseHandle()->m_collisionFilterGroup = kFloorGroup;
  }
  ground_shape_ = std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0);
  ground_ = std::make_unique<btCollisionObject>();
  ground_->setCollisionShape(ground_shape_.get());
  ground_->setFriction(1.0);
  ground_->setCollisionFlags(btCollisionObject::CF_STATIC_OBJECT);
  dynamics_world_->addCollisionObject(ground_.get(), kGroundGroup,
                                      btBroadphaseProxy::AllFilter ^ kGroundGroup);
  const int robot_mask = btBroadphaseProxy::StaticFilter | kGroundGroup;

  // Chassis: the body box, with whatever mass is not in the wheels.
  const Eigen::Vector3d bc = robot.body_pose.translation();
  const Eigen::Quaterniond bq(robot.body_pose.rotation());
  body_in_root_ = btTransform(btQuaternion(bq.x(), bq.y(), bq.z(), bq.w()),
                              btVector3(bc.x(), bc.y(), bc.z()));
  const Eigen::Vector3d h = robot.body_size / 2.0;
  chassis_shape_ = std::make_unique<btBoxShape>(btVector3(h.x(), h.y(), h.z()));
  chassis_shape_->setMargin(std::min<btScalar>(kRobotMargin, 0.5 * h.minCoeff()));
  double wheel_mass = 0.0;
  for (const WheelSpec& w : robot.wheels) wheel_mass += w.mass;
  double body_mass = robot.body_mass > 0.0 ? robot.body_mass : robot.total_mass - wheel_mass;
  if (!(body_mass > 0.0)) throw std::invalid_argument("NaiveBulletBackend: body mass must be > 0");
  btVector3 inertia;
  chassis_shape_->calculateLocalInertia(body_mass, inertia);
  btRigidBody::btRigidBodyConstructionInfo ci(body_mass, nullptr, chassis_shape_.get(), inertia);
  ci.m_friction = 0.6;
  chassis_ = std::make_unique<btRigidBody>(ci);
  chassis_->setActivationState(DISABLE_DEACTIVATION);
  dynamics_world_->addRigidBody(chassis_.get(), btBroadphaseProxy::DefaultFilter, robot_mask);

  for (int i = 0; i < 4; ++i) {
    const WheelSpec& spec = robot.wheels[i];
    const double r = spec.radius;
    const double half_width = spec.width > 0.0 ? spec.width / 2.0 : 0.25 * r;
    wheel_in_root_[i] = btVector3(spec.position.x(), spec.position.y(), spec.position.z());
    // Cylinder along the body's y axis = the axle.
    wheel_shapes_[i] = std::make_unique<btCylinderShape>(btVector3(r, half_width, r));
    wheel_shapes_[i]->setMargin(std::min<btScalar>(kRobotMargin, 0.5 * half_width));
    const double mass = spec.mass > 0.0 ? spec.mass : 0.05;
    btVector3 wi;
    wheel_shapes_[i]->calculateLocalInertia(mass, wi);
    if (spec.inertia_axle > 0.0) wi.setY(spec.inertia_axle);
    btRigidBody::btRigidBodyConstructionInfo wci(mass, nullptr, wheel_shapes_[i].get(), wi);
    // Friction mu1 along the rolling direction, mu2 along the axle (local y): Bullet scales the
    // friction direction by the anisotropy in the wheel's frame.
    const double mu_max = std::max({spec.mu1, spec.mu2, 1e-6});
    wci.m_friction = mu_max;
    wheels_[i] = std::make_unique<btRigidBody>(wci);
    if (spec.mu1 != spec.mu2) {
      wheels_[i]->setAnisotropicFriction(
          btVector3(spec.mu1 / mu_max, spec.mu2 / mu_max, spec.mu1 / mu_max),
          btCollisionObject::CF_ANISOTROPIC_FRICTION);
    }
    wheels_[i]->setActivationState(DISABLE_DEACTIVATION);
    dynamics_world_->addRigidBody(wheels_[i].get(), btBroadphaseProxy::DefaultFilter, robot_mask);

    const btVector3 pivot_in_chassis = body_in_root_.inverse() * wheel_in_root_[i];
    const btVector3 axis_in_chassis = body_in_root_.getBasis().transpose() * btVector3(0, 1, 0);
    hinges_[i] = std::make_unique<btHingeConstraint>(*chassis_, *wheels_[i], pivot_in_chassis,
                                                     btVector3(0, 0, 0), axis_in_chassis,
                                                     btVector3(0, 1, 0));
    dynamics_world_->addConstraint(hinges_[i].get(), /*disableCollisionsBetweenLinkedBodies=*/true);
  }
  SetPose(Pose2{});
}

NaiveBulletBackend::~NaiveBulletBackend() {
  for (auto& h : hinges_) dynamics_world_->removeConstraint(h.get());
  for (auto& w : wheels_) dynamics_world_->removeRigidBody(w.get());
  dynamics_world_->removeRigidBody(chassis_.get());
  dynamics_world_->removeCollisionObject(ground_.get());
  world_objects_.reset();
}

void NaiveBulletBackend::SetPose(const Pose2& pose) {
  const btTransform root = RootTransform(pose);
  auto place = [&](btRigidBody* body, const btTransform& t) {
    body->setCenterOfMassTransform(t);
    body->setInterpolationWorldTransform(t);
    body->setLinearVelocity(btVector3(0, 0, 0));
    body->setAngularVelocity(btVector3(0, 0, 0));
    body->setInterpolationLinearVelocity(btVector3(0, 0, 0));
    body->setInterpolationAngularVelocity(btVector3(0, 0, 0));
    body->clearForces();
    if (body->getBroadphaseHandle() != nullptr) {
      dynamics_world_->updateSingleAabb(body);
      broadphase_->getOverlappingPairCache()->cleanProxyFromPairs(body->getBroadphaseHandle(),
                                                                  dispatcher_.get());
    }
  };
  place(chassis_.get(), root * body_in_root_);
  for (int i = 0; i < 4; ++i) {
    // Wheel angles are kept: turn the wheel about its axle by its joint angle.
    const btTransform spin(btQuaternion(btVector3(0, 1, 0), angles_[i]), btVector3(0, 0, 0));
    const btTransform centre(btQuaternion::getIdentity(), wheel_in_root_[i]);
    place(wheels_[i].get(), root * centre * spin);
  }
}

void NaiveBulletBackend::SetTargets(const DriveTargets& targets) {
  for (int i = 0; i < 4; ++i) targets_[i] = targets.wheel_speeds[i];
}

double NaiveBulletBackend::WheelSpeed(int i) const {
  const btVector3 axle = chassis_->getWorldTransform().getBasis() *
                         (body_in_root_.getBasis().transpose() * btVector3(0, 1, 0));
  return (wheels_[i]->getAngularVelocity() - chassis_->getAngularVelocity()).dot(axle);
}

bool NaiveBulletBackend::IsRobot(const btCollisionObject* o) const {
  if (o == chassis_.get()) return true;
  for (const auto& w : wheels_) {
    if (o == w.get()) return true;
  }
  return false;
}

void NaiveBulletBackend::Step(double dt, std::vector<Contact>* contacts) {
  if (!(dt > 0.0)) return;
  for (int i = 0; i < 4; ++i) {
    // Bullet's hinge motor drives A relative to B: the opposite sense to the wheel joint.
    hinges_[i]->enableAngularMotor(true, -targets_[i], torque_limit_ * dt);
  }
  dynamics_world_->stepSimulation(dt, 0, dt);
  for (int i = 0; i < 4; ++i) angles_[i] += WheelSpeed(i) * dt;
  if (contacts == nullptr) return;
  const int n = dispatcher_->getNumManifolds();
  for (int k = 0; k < n; ++k) {
    btPersistentManifold* m = dispatcher_->getManifoldByIndexInternal(k);
    const btCollisionObject* a = m->getBody0();
    const btCollisionObject* b = m->getBody1();
    const bool robot_is_a = IsRobot(a);
    if (robot_is_a == IsRobot(b)) continue;
    const btCollisionObject* other = robot_is_a ? b : a;
    if (other == ground_.get() || other->getUserIndex() < 0) continue;
    for (int j = 0; j < m->getNumContacts(); ++j) {
      const btManifoldPoint& p = m->getContactPoint(j);
      // The point was measured before integration: its distance at the new poses (what
      // btPersistentManifold::refreshContactPoints computes, without editing the manifold, so
      // that asking for contacts never changes the simulation).
      const btVector3 on_a = a->getWorldTransform() * p.m_localPointA;
      const btVector3 on_b = b->getWorldTransform() * p.m_localPointB;
      const btScalar distance = (on_a - on_b).dot(p.m_normalWorldOnB);
      if (distance > kTouchingDistance) continue;
      const btVector3 normal = robot_is_a ? p.m_normalWorldOnB : -p.m_normalWorldOnB;
      const btVector3& at = robot_is_a ? on_b : on_a;
      Contact c;
      c.point = Eigen::Vector3d(at.x(), at.y(), at.z());
      c.normal = Eigen::Vector3d(normal.x(), normal.y(), normal.z());
      c.depth = std::max(0.0, -static_cast<double>(distance));
      c.shape = other->getUserIndex();
      contacts->push_back(c);
    }
  }
}

Pose2 NaiveBulletBackend::pose() const {
  const btTransform root = chassis_->getWorldTransform() * body_in_root_.inverse();
  return Pose2{root.getOrigin().x(), root.getOrigin().y(), YawOf(root)};
}

Twist2 NaiveBulletBackend::twist() const {
  const btTransform root = chassis_->getWorldTransform() * body_in_root_.inverse();
  const btVector3 v = chassis_->getVelocityInLocalPoint(root.getOrigin() -
                                                        chassis_->getCenterOfMassPosition());
  const double yaw = YawOf(root);
  const double c = std::cos(yaw), s = std::sin(yaw);
  return Twist2{c * v.x() + s * v.y(), -s * v.x() + c * v.y(), chassis_->getAngularVelocity().z()};
}

const std::vector<double>& NaiveBulletBackend::wheel_velocities() const {
  velocities_out_.resize(4);
  for (int i = 0; i < 4; ++i) velocities_out_[i] = WheelSpeed(i);
  return velocities_out_;
}

const std::vector<double>& NaiveBulletBackend::wheel_positions() const {
  positions_out_.assign(angles_.begin(), angles_.end());
  return positions_out_;
}

}  // namespace minibot3d_sim
