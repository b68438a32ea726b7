#include "minibot3d_sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace minibot3d_sim {

void ValidateOptions(const SimulatorOptions& o) {
  auto bad = [](const std::string& what) { throw std::invalid_argument(what); };
  if (!(o.physics_step > 0.0 && o.physics_step <= 0.02)) {
    bad("physics_step must be in (0, 0.02] s, got " + std::to_string(o.physics_step));
  }
  if (!(o.odom_wheel_separation_multiplier > 0.0)) {
    bad("odom_wheel_separation_multiplier must be > 0, got " +
        std::to_string(o.odom_wheel_separation_multiplier));
  }
  if (!(o.cmd_wheel_separation_multiplier > 0.0)) {
    bad("cmd_wheel_separation_multiplier must be > 0, got " +
        std::to_string(o.cmd_wheel_separation_multiplier));
  }
  ValidateOdometryError(o.odom_error);
  if (!(o.cmd_timeout > 0.0)) bad("cmd_timeout must be > 0 s, got " + std::to_string(o.cmd_timeout));
  if (!(o.actor_radius > 0.0)) bad("actor_radius must be > 0 m, got " + std::to_string(o.actor_radius));
  if (!(o.actor_height > 0.0)) bad("actor_height must be > 0 m, got " + std::to_string(o.actor_height));
  if (!(o.social_force.step >= o.physics_step && o.social_force.step <= 0.1)) {
    bad("the social force step must be in [physics_step, 0.1] s, got " +
        std::to_string(o.social_force.step));
  }
  if (!std::isfinite(o.spawn.x) || !std::isfinite(o.spawn.y) || !std::isfinite(o.spawn.yaw)) {
    bad("spawn pose (x, y, yaw) must be finite");
  }
}

namespace {

// A robot's own cameras see through their links (a camera is not hidden by its own housing);
// others see every shape.
std::vector<Shape> BodyShapes(const RobotModel& robot, bool without_camera_links) {
  std::vector<Shape> shapes;
  for (const CollisionShape& c : robot.collisions) {
    bool camera_link = false;
    for (const CameraSpec& cam : robot.cameras) camera_link |= cam.link == c.link;
    if (!(camera_link && without_camera_links)) shapes.push_back(c.shape);
  }
  return shapes;
}

// Where a body waits while it is not to be seen: far below the floor.
Eigen::Isometry3d Hidden() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(0.0, 0.0, -1e4);
  return t;
}

DepthCameraSpec CameraSpecOf(const CameraSpec& c) {
  DepthCameraSpec spec;
  spec.width = c.sensor.width;
  spec.height = c.sensor.height;
  spec.horizontal_fov = c.sensor.horizontal_fov;
  spec.near_clip = c.sensor.clip_near;
  spec.far_clip = c.sensor.clip_far;
  spec.format = c.sensor.format == "B8G8R8" ? PixelFormat::kB8G8R8
                : c.sensor.format == "L8"   ? PixelFormat::kL8
                                            : PixelFormat::kR8G8B8;
  if (c.sensor.noise_type == "gaussian") {
    spec.noise_mean = c.sensor.noise_mean;
    spec.noise_stddev = c.sensor.noise_stddev;
  }
  return spec;
}

constexpr int kActorSides = 32;

}  // namespace

// ---- SimRobot ----

SimRobot::SimRobot(Simulator* sim, size_t index, RobotEntry entry, unsigned seed)
    : sim_(sim),
      index_(index),
      model_(std::move(entry.model)),
      options_(std::move(entry.options)),
      seed_(seed) {}

double SimRobot::time() const { return sim_->time(); }
double SimRobot::physics_step() const { return sim_->physics_step(); }

void SimRobot::Command(const Twist2& command) { drive_->OnCommand(command, time()); }

void SimRobot::Advance(double t, double dt) {
  backend_->SetTargets(drive_->Actuate(t, dt));
  before_step_ = backend_->pose();
  contacts_.clear();
  backend_->Step(dt, &contacts_);
}

void SimRobot::Observe(double now, double dt) {
  DriveState state;
  state.time = now;
  state.dt = dt;
  state.pose = backend_->pose();
  state.twist = backend_->twist();
  state.wheel_positions = &backend_->wheel_positions();
  state.wheel_velocities = &backend_->wheel_velocities();
  drive_->Observe(state);
  if (odom_error_) odom_error_->Update(drive_->odometry_pose(), drive_->odometry_twist());

  in_contact_ = !contacts_.empty();
  const int world_shapes = static_cast<int>(sim_->world_.shapes.size());
  for (const Contact& c : contacts_) {
    auto it = last_touch_.find(c.shape);
    const bool begins = it == last_touch_.end() || now - it->second > kContactRelease;
    last_touch_[c.shape] = now;
    if (!begins) continue;
    CollisionEvent e;
    e.time = now;
    e.contact = c;
    if (c.shape >= 0 && c.shape < world_shapes) {
      e.shape_name = sim_->world_.shapes[c.shape].name;
    } else if (c.shape >= world_shapes && c.shape - world_shapes < static_cast<int>(sim_->robot_count())) {
      e.shape_name = "robot " + sim_->at(c.shape - world_shapes).name();
    } else if (c.shape >= sim_->ActorShapeId(0) &&
               c.shape - sim_->ActorShapeId(0) < static_cast<int>(sim_->actor_count())) {
      e.shape_name = "actor " + sim_->world_.actors[c.shape - sim_->ActorShapeId(0)].name;
    } else {
      e.shape_name = "(unknown)";
    }
    events_.push_back(e);
    ++collision_count_;
  }
}

void SimRobot::OtherBodies(const Eigen::Vector2d& from, double height, double reach,
                           std::vector<BodyOutline>* out) const {
  out->clear();
  for (size_t j = 0; j < sim_->robot_count(); ++j) {
    if (j == index_) continue;
    const SimRobot& other = sim_->at(j);
    const Pose2 p = other.true_pose();
    if (std::hypot(p.x - from.x(), p.y - from.y()) - other.collider().radius() > reach) continue;
    for (const BodyCollider::Part& part : other.collider().parts()) {
      if (height < part.z_min || height > part.z_max) continue;
      out->push_back(BodyOutline{&part.outline, p, minibot3d_common::TransformPoint(p, part.center),
                                 part.radius});
    }
  }
  const double r = sim_->options_.actor_radius;
  if (height < 0.0 || height > sim_->options_.actor_height) return;
  for (const ActorState& a : sim_->actor_states_) {
    if (std::hypot(a.x - from.x(), a.y - from.y()) - r > reach) continue;
    out->push_back(BodyOutline{&sim_->actor_outline_, Pose2{a.x, a.y, 0.0},
                               Eigen::Vector2d(a.x, a.y), sim_->actor_outline_radius_});
  }
}

void SimRobot::TakeScan(size_t laser, std::vector<float>* ranges) {
  const Pose2 pose = backend_->pose();
  if (sim_->robot_count() > 1 || sim_->actor_count() > 0) {
    const LaserSpec& spec = lidars_[laser]->spec();
    const Eigen::Vector2d at =
        minibot3d_common::TransformPoint(pose, Eigen::Vector2d(spec.pose_in_root.translation().x(),
                                                               spec.pose_in_root.translation().y()));
    OtherBodies(at, spec.pose_in_root.translation().z(),
                spec.max_range + 5.0 * spec.noise_stddev, &bodies_scratch_);
    lidars_[laser]->Scan(pose, ranges, &bodies_scratch_);
  } else {
    lidars_[laser]->Scan(pose, ranges);
  }
  scan_clocks_[laser].Fired();
}

ImuReading SimRobot::TakeImu(size_t i) {
  imu_clocks_[i].Fired();
  return imus_[i].Sample(time(), backend_->pose(), backend_->twist());
}

GroundTruthReading SimRobot::TakeGroundTruth(size_t i) {
  truth_clocks_[i].Fired();
  return ground_truths_[i].Sample(backend_->pose(), backend_->twist());
}

Eigen::Isometry3d SimRobot::CameraPose(size_t i) const {
  return RootTransform(backend_->pose()) * model_.cameras[i].pose_in_root;
}

void SimRobot::TakeFrame(size_t i, DepthFrame* frame) {
  const RayScene& scene = sim_->SceneNow(index_);
  cameras_[i]->Reseed(seed_ + 15485863u * static_cast<unsigned>(i + 1) +
                      static_cast<unsigned>(camera_frames_[i]));
  cameras_[i]->Render(scene, CameraPose(i), frame);
  SkipFrame(i);
}

void SimRobot::SkipFrame(size_t i) {
  camera_clocks_[i].Fired();
  ++camera_frames_[i];
}

std::vector<CollisionEvent> SimRobot::TakeCollisionEvents() {
  std::vector<CollisionEvent> out;
  out.swap(events_);
  return out;
}

void SimRobot::Reset() {
  backend_->SetPose(options_.spawn);
  drive_->Reset();
  if (odom_error_) odom_error_->Reset();
  for (auto& imu : imus_) imu.Restart();
  last_touch_.clear();
  in_contact_ = false;
}

void SimRobot::SetPose(const Pose2& pose) {
  backend_->SetPose(pose);
  drive_->Stop();
  for (auto& imu : imus_) imu.Restart();
  last_touch_.clear();
  in_contact_ = false;
}

bool SimRobot::PoseCollides(const Pose2& pose, std::string* what) const {
  BodyCollider::Hit hit;
  if (collider_->Collides(pose, &hit)) {
    if (what) {
      *what = hit.shape >= 0 && hit.shape < static_cast<int>(sim_->world_.shapes.size())
                  ? sim_->world_.shapes[hit.shape].name
                  : "(unknown)";
    }
    return true;
  }
  for (size_t j = 0; j < sim_->robot_count(); ++j) {
    if (j == index_) continue;
    const SimRobot& other = sim_->at(j);
    if (BodyOverlap(*collider_, pose, other.collider(), other.true_pose())) {
      if (what) *what = "robot " + other.name();
      return true;
    }
  }
  for (size_t k = 0; k < sim_->actor_count(); ++k) {
    const ActorState& a = sim_->actor_states_[k];
    if (BodyTouchesDisc(*collider_, pose, Eigen::Vector2d(a.x, a.y), sim_->options_.actor_radius,
                        0.0, sim_->options_.actor_height)) {
      if (what) *what = "actor " + sim_->world_.actors[k].name;
      return true;
    }
  }
  return false;
}

double SimRobot::Clearance() const {
  const Pose2 p = backend_->pose();
  return std::max(0.0, collider_->Distance(Eigen::Vector2d(p.x, p.y)) - collider_->radius());
}

// ---- Simulator ----

Simulator::Simulator(const RobotModel& robot, World world, const SimulatorOptions& options,
                     const BackendFactory& make_backend)
    : world_(std::move(world)), options_(options), slices_(&world_) {
  ValidateOptions(options_);
  RobotEntry entry;
  entry.model = robot;
  entry.options.spawn = options_.spawn;
  entry.options.odom_wheel_separation_multiplier = options_.odom_wheel_separation_multiplier;
  entry.options.cmd_wheel_separation_multiplier = options_.cmd_wheel_separation_multiplier;
  entry.options.odom_error = options_.odom_error;
  std::vector<RobotEntry> robots;
  robots.push_back(std::move(entry));
  Build(std::move(robots), make_backend);
}

Simulator::Simulator(std::vector<RobotEntry> robots, World world, const SimulatorOptions& options,
                     const BackendFactory& make_backend)
    : world_(std::move(world)), options_(options), slices_(&world_) {
  ValidateOptions(options_);
  if (robots.empty()) throw std::invalid_argument("the simulation has no robot");
  std::map<std::string, size_t> names;
  for (size_t i = 0; i < robots.size(); ++i) {
    const RobotOptions& o = robots[i].options;
    if (robots.size() > 1 && o.name.empty()) {
      throw std::invalid_argument("robot " + std::to_string(i + 1) + " of " +
                                  std::to_string(robots.size()) +
                                  " has no name: several robots need one each");
    }
    if (!names.emplace(o.name, i).second) {
      throw std::invalid_argument("two robots are named '" + o.name + "'");
    }
    if (!(o.odom_wheel_separation_multiplier > 0.0) || !(o.cmd_wheel_separation_multiplier > 0.0)) {
      throw std::invalid_argument("robot '" + o.name +
                                  "': the wheel separation multipliers must be > 0");
    }
    if (!std::isfinite(o.spawn.x) || !std::isfinite(o.spawn.y) || !std::isfinite(o.spawn.yaw)) {
      throw std::invalid_argument("robot '" + o.name + "': its spawn pose must be finite");
    }
    try {
      ValidateOdometryError(o.odom_error);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("robot '" + o.name + "': " + e.what());
    }
  }
  Build(std::move(robots), make_backend);
  for (size_t i = 0; i < robots_.size(); ++i) {
    for (size_t j = i + 1; j < robots_.size(); ++j) {
      if (BodyOverlap(robots_[i]->collider(), robots_[i]->true_pose(), robots_[j]->collider(),
                      robots_[j]->true_pose())) {
        throw std::invalid_argument("robots '" + robots_[i]->name() + "' and '" +
                                    robots_[j]->name() + "' overlap where they spawn");
      }
    }
  }
}

void Simulator::Build(std::vector<RobotEntry> robots, const BackendFactory& make_backend) {
  {
    // A polygon circumscribing the circle would be seen up to 0.5 % of r too early; one inscribed
    // too late: vertices at the radius that keeps the polygon's area the circle's.
    const double r = options_.actor_radius;
    const double rv =
        r * std::sqrt(2.0 * M_PI / (kActorSides * std::sin(2.0 * M_PI / kActorSides)));
    for (int k = 0; k < kActorSides; ++k) {
      const double t = 2.0 * M_PI * k / kActorSides;
      actor_outline_.emplace_back(rv * std::cos(t), rv * std::sin(t));
    }
    actor_outline_radius_ = rv;
  }
  bool cameras = false;
  for (const RobotEntry& e : robots) cameras |= !e.model.cameras.empty();
  if (cameras) ray_scene_ = std::make_unique<RayScene>(world_);
  for (size_t r = 0; r < robots.size(); ++r) {
    auto robot = std::unique_ptr<SimRobot>(
        new SimRobot(this, r, std::move(robots[r]), options_.seed + 1000003u * static_cast<unsigned>(r)));
    SimRobot& x = *robot;
    const RobotModel& m = x.model_;
    DriveSettings drive;
    drive.cmd_timeout = options_.cmd_timeout;
    drive.odom_wheel_separation_multiplier = x.options_.odom_wheel_separation_multiplier;
    drive.cmd_wheel_separation_multiplier = x.options_.cmd_wheel_separation_multiplier;
    drive.physics_step = options_.physics_step;
    x.drive_ = MakeDrive(m, drive);
    if (x.options_.odom_error.enabled()) {
      x.odom_error_ = std::make_unique<OdometryError>(x.options_.odom_error, x.seed_);
    }
    x.backend_ = make_backend ? make_backend(m, world_)
                              : MakePhysicsBackend(options_.physics, m, world_, &slices_);
    x.collider_ = std::make_unique<BodyCollider>(m, world_, &slices_);
    for (size_t i = 0; i < m.lasers.size(); ++i) {
      const LaserSpec& spec = m.lasers[i];
      // Each laser its own noise stream; the first keeps the robot's seed.
      x.lidars_.push_back(std::make_unique<Lidar>(
          spec, slices_.At(spec.pose_in_root.translation().z()), x.seed_ + 7919u * i));
      x.scan_clocks_.emplace_back(spec.update_rate);
    }
    for (size_t i = 0; i < m.imus.size(); ++i) {
      x.imus_.emplace_back(m.imus[i], x.seed_ + 104729u + 7919u * i);
      x.imu_clocks_.emplace_back(m.imus[i].update_rate);
    }
    for (size_t i = 0; i < m.ground_truths.size(); ++i) {
      x.ground_truths_.emplace_back(m.ground_truths[i], x.seed_ + 224737u + 7919u * i);
      x.truth_clocks_.emplace_back(m.ground_truths[i].options.update_rate);
    }
    if (ray_scene_) {
      const std::string name = x.options_.name.empty() ? m.name : x.options_.name;
      const std::vector<Shape> all = BodyShapes(m, false);
      if (!all.empty()) x.body_ = ray_scene_->AddBody(all, name);
      const std::vector<Shape> seen_by_self = BodyShapes(m, true);
      if (!m.cameras.empty() && !seen_by_self.empty()) {
        x.self_body_ = seen_by_self.size() == all.size()
                           ? x.body_
                           : ray_scene_->AddBody(seen_by_self, name + " (its own view)");
      }
    }
    for (const CameraSpec& c : m.cameras) {
      x.cameras_.push_back(std::make_unique<DepthCamera>(CameraSpecOf(c)));
      x.camera_clocks_.emplace_back(c.update_rate);
      x.camera_frames_.push_back(0);
    }
    x.backend_->SetPose(x.options_.spawn);
    robots_.push_back(std::move(robot));
  }
  if (ray_scene_) {
    for (const Actor& a : world_.actors) {
      Shape cylinder;
      cylinder.type = ShapeType::kCylinder;
      cylinder.name = "actor " + a.name;
      cylinder.size = Eigen::Vector3d(options_.actor_radius, options_.actor_radius,
                                      options_.actor_height);
      cylinder.pose.translation() = Eigen::Vector3d(0.0, 0.0, 0.5 * options_.actor_height);
      cylinder.color = Eigen::Vector3f(0.25f, 0.3f, 0.55f);  // clothes: a dark blue
      actor_bodies_.push_back(ray_scene_->AddBody({cylinder}, cylinder.name));
    }
  }
  std::vector<SocialForceAgent> agents;
  for (size_t k = 0; k < world_.actors.size(); ++k) {
    const Actor& a = world_.actors[k];
    if (!a.social_force) continue;
    SocialForceAgent agent;
    agent.position = Eigen::Vector2d(a.x, a.y);
    agent.radius = options_.actor_radius;
    agent.options = a.social;
    agents.push_back(agent);
    crowd_actor_.push_back(k);
  }
  actor_states_.resize(world_.actors.size());
  if (!agents.empty()) {
    const WorldSlice* legs = slices_.At(0.1);
    auto wall = [legs](const Eigen::Vector2d& p, double /*reach*/, Eigen::Vector2d* away) {
      return legs->Distance(p, away);
    };
    crowd_ = std::make_unique<SocialForceCrowd>(std::move(agents), options_.social_force, wall,
                                                options_.seed + 2750159u);
    crowd_every_ = std::max<std::uint64_t>(
        1, std::llround(options_.social_force.step / options_.physics_step));
    for (size_t k : crowd_actor_) actor_states_[k].yaw = world_.actors[k].yaw;
  }
  UpdateActors();
}

void Simulator::UpdateActors() {
  const double t = time();
  for (size_t k = 0; k < world_.actors.size(); ++k) {
    if (!world_.actors[k].social_force) actor_states_[k] = ActorAt(world_.actors[k], t);
  }
  if (!crowd_) return;
  if (steps_ > 0 && steps_ % crowd_every_ == 0) {
    std::vector<SocialForceObstacle> robots;
    for (const auto& r : robots_) {
      const Pose2 p = r->true_pose();
      const Twist2 v = r->true_twist();  // in the robot's frame
      const double c = std::cos(p.yaw), s = std::sin(p.yaw);
      robots.push_back(SocialForceObstacle{Eigen::Vector2d(p.x, p.y), r->collider().radius(),
                                           Eigen::Vector2d(c * v.vx - s * v.vy,
                                                           s * v.vx + c * v.vy)});
    }
    crowd_->Step(robots);
  }
  for (size_t i = 0; i < crowd_actor_.size(); ++i) {
    const SocialForceAgent& agent = crowd_->agents()[i];
    ActorState& s = actor_states_[crowd_actor_[i]];
    s.x = agent.position.x();
    s.y = agent.position.y();
    s.vx = agent.velocity.x();
    s.vy = agent.velocity.y();
    // Facing where it walks; a pedestrian standing still keeps its heading.
    if (agent.velocity.norm() > 0.05) s.yaw = std::atan2(s.vy, s.vx);
    s.wz = 0.0;
  }
}

void Simulator::SeparateFromActors() {
  for (auto& r : robots_) {
    for (size_t k = 0; k < actor_states_.size(); ++k) {
      const ActorState& a = actor_states_[k];
      const Eigen::Vector2d centre(a.x, a.y);
      Eigen::Vector2d normal;
      if (!BodyTouchesDisc(r->collider(), r->true_pose(), centre, options_.actor_radius, 0.0,
                           options_.actor_height, &normal)) {
        continue;
      }
      if (!minibot3d_common::SamePose(r->true_pose(), r->before_step_) &&
          !BodyTouchesDisc(r->collider(), r->before_step_, centre, options_.actor_radius, 0.0,
                           options_.actor_height)) {
        r->backend_->SetPose(r->before_step_);
      }
      Contact c;
      c.point = Eigen::Vector3d(a.x + options_.actor_radius * normal.x(),
                                a.y + options_.actor_radius * normal.y(), 0.0);
      c.normal = Eigen::Vector3d(normal.x(), normal.y(), 0.0);
      c.shape = ActorShapeId(k);
      r->contacts_.push_back(c);
    }
  }
}

SimRobot* Simulator::Find(const std::string& name) {
  for (auto& r : robots_) {
    if (r->name() == name) return r.get();
  }
  return nullptr;
}

const RayScene& Simulator::SceneNow(size_t viewer) {
  for (auto& r : robots_) {
    const Eigen::Isometry3d at = RootTransform(r->true_pose());
    const bool self = r->index_ == viewer && r->self_body_ >= 0;
    if (r->body_ >= 0 && r->body_ != r->self_body_) {
      ray_scene_->SetBodyPose(r->body_, self ? Hidden() : at);
    }
    if (r->self_body_ >= 0 && r->self_body_ != r->body_) {
      ray_scene_->SetBodyPose(r->self_body_, self ? at : Hidden());
    }
    if (r->body_ >= 0 && r->body_ == r->self_body_) ray_scene_->SetBodyPose(r->body_, at);
  }
  for (size_t k = 0; k < actor_bodies_.size(); ++k) {
    const ActorState& a = actor_states_[k];
    ray_scene_->SetBodyPose(actor_bodies_[k], RootTransform(Pose2{a.x, a.y, a.yaw}));
  }
  ray_scene_->Commit();
  return *ray_scene_;
}

void Simulator::Step() {
  const double dt = options_.physics_step;
  const double t = time();
  for (auto& r : robots_) r->Advance(t, dt);
  ++steps_;
  const double now = time();
  if (!world_.actors.empty()) {
    UpdateActors();
    SeparateFromActors();
  }
  if (robots_.size() > 1) SeparateRobots(now);
  for (auto& r : robots_) r->Observe(now, dt);
}

void Simulator::SeparateRobots(double /*now*/) {
  const size_t n = robots_.size();
  // Scratch kept between steps (no allocation per step).
  Separation& w = separation_;
  std::vector<char>& reverted = w.reverted;
  std::vector<std::pair<size_t, size_t>>& touching = w.touching;
  std::vector<Eigen::Vector2d>& normals = w.normals;
  std::vector<std::pair<size_t, size_t>>& candidates = w.candidates;
  std::vector<size_t>& order = w.order;
  std::vector<double>& lo = w.lo;
  std::vector<double>& hi = w.hi;
  std::vector<char>& moved = w.moved;
  std::vector<char>& moved_now = w.moved_now;
  reverted.assign(n, 0);
  touching.clear();
  normals.clear();
  order.resize(n);
  lo.resize(n);
  hi.resize(n);
  // Sweep and prune along x: only robots whose bounding circles overlap in x are tested, in the
  // order (a, b) with a < b so the outcome does not depend on where the robots stand.
  // Robots put back during the last pass; a pair of which neither was has been settled with the
  // poses it has now, and is not tested again.
  moved.assign(n, 1);
  moved_now.assign(n, 0);
  for (bool changed = true; changed;) {
    changed = false;
    std::fill(moved_now.begin(), moved_now.end(), 0);
    for (size_t i = 0; i < n; ++i) order[i] = i;
    for (size_t i = 0; i < n; ++i) {
      const double x = robots_[i]->true_pose().x, r = robots_[i]->collider().radius();
      lo[i] = x - r;
      hi[i] = x + r;
    }
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return lo[a] < lo[b] || (lo[a] == lo[b] && a < b); });
    candidates.clear();
    for (size_t i = 0; i < n; ++i) {
      for (size_t j = i + 1; j < n && lo[order[j]] <= hi[order[i]]; ++j) {
        candidates.emplace_back(std::min(order[i], order[j]), std::max(order[i], order[j]));
      }
    }
    std::sort(candidates.begin(), candidates.end());
    for (const auto& pair : candidates) {
      const size_t a = pair.first, b = pair.second;
      if (!moved[a] && !moved[b]) continue;
      SimRobot& ra = *robots_[a];
      SimRobot& rb = *robots_[b];
      const Pose2 pa = ra.true_pose(), pb = rb.true_pose();
      const double reach = ra.collider().radius() + rb.collider().radius();
      if ((pa.x - pb.x) * (pa.x - pb.x) + (pa.y - pb.y) * (pa.y - pb.y) > reach * reach) continue;
      Eigen::Vector2d normal = Eigen::Vector2d::UnitX();
      // The same two poses as a test of the last step (a robot held against another asks for
      // the same step again): the same answer.
      const auto from = std::lower_bound(
          w.last.begin(), w.last.end(), std::make_pair(a, b),
          [](const Separation::Tested& t, const std::pair<size_t, size_t>& k) {
            return std::make_pair(t.a, t.b) < k;
          });
      int known = -1;
      for (auto it = from; it != w.last.end() && it->a == a && it->b == b; ++it) {
        if (minibot3d_common::SamePose(it->pa, pa) && minibot3d_common::SamePose(it->pb, pb)) {
          known = it->overlap ? 1 : 0;
          normal = it->normal;
          break;
        }
      }
      const bool overlap = known >= 0
                               ? known == 1
                               : BodyOverlap(ra.collider(), pa, rb.collider(), pb, &normal);
      w.tested.push_back(Separation::Tested{a, b, pa, pb, overlap, normal});
      if (!overlap) continue;
      if (std::find(touching.begin(), touching.end(), std::make_pair(a, b)) == touching.end()) {
        touching.emplace_back(a, b);
        normals.push_back(normal);
      }
      for (SimRobot* r : {&ra, &rb}) {
        if (reverted[r->index_] || minibot3d_common::SamePose(r->true_pose(), r->before_step_)) {
          continue;
        }
        r->backend_->SetPose(r->before_step_);
        reverted[r->index_] = 1;
        moved_now[r->index_] = 1;
        changed = true;
      }
    }
    moved.swap(moved_now);
  }
  // By pair (the order among one pair's tests does not matter: each holds for its poses).
  std::sort(w.tested.begin(), w.tested.end(),
            [](const Separation::Tested& x, const Separation::Tested& y) {
              return std::make_pair(x.a, x.b) < std::make_pair(y.a, y.b);
            });
  w.last.swap(w.tested);
  w.tested.clear();
  for (size_t k = 0; k < touching.size(); ++k) {
    SimRobot& ra = *robots_[touching[k].first];
    SimRobot& rb = *robots_[touching[k].second];
    const Pose2 pa = ra.true_pose(), pb = rb.true_pose();
    Contact c;
    c.point = Eigen::Vector3d(0.5 * (pa.x + pb.x), 0.5 * (pa.y + pb.y), 0.0);
    c.normal = Eigen::Vector3d(normals[k].x(), normals[k].y(), 0.0);
    c.shape = RobotShapeId(rb.index_);
    ra.contacts_.push_back(c);
    c.normal = -c.normal;
    c.shape = RobotShapeId(ra.index_);
    rb.contacts_.push_back(c);
  }
}

}  // namespace minibot3d_sim
