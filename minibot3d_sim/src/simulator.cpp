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
  if (!(o.cmd_timeout > 0.0)) bad("cmd_timeout must be > 0 s, got " + std::to_string(o.cmd_timeout));
  if (!std::isfinite(o.spawn.x) || !std::isfinite(o.spawn.y) || !std::isfinite(o.spawn.yaw)) {
    bad("spawn pose (x, y, yaw) must be finite");
  }
}

Simulator::Simulator(const RobotModel& robot, World world, const SimulatorOptions& options)
    : robot_(robot), world_(std::move(world)), options_(options) {
  ValidateOptions(options_);
  geometry_.wheel_separation = robot_.drive.wheel_separation;
  geometry_.wheel_radius = robot_.drive.wheel_diameter / 2.0;
  odom_geometry_ = geometry_;
  odom_geometry_.wheel_separation *= options_.odom_wheel_separation_multiplier;
  geometry_.wheel_separation *= options_.cmd_wheel_separation_multiplier;
  backend_ = MakePhysicsBackend(options_.physics, robot_, world_);
  lidar_slice_ = std::make_unique<WorldSlice>(world_, robot_.lidar.pose_in_root.translation().z());
  body_slice_ = std::make_unique<WorldSlice>(world_, robot_.body_pose.translation().z());
  lidar_ = std::make_unique<Lidar>(robot_.lidar, lidar_slice_.get(), options_.seed);
  backend_->SetPose(options_.spawn);
}

void Simulator::SetCommand(double v, double w) {
  cmd_v_ = v;
  cmd_w_ = w;
  cmd_time_ = time();
}

bool Simulator::command_active() const {
  return time() - cmd_time_ <= options_.cmd_timeout + 1e-12;
}

void Simulator::Step() {
  std::array<double, 4> targets{};
  if (command_active()) {
    targets = WheelSpeedsForTwist(cmd_v_, cmd_w_, geometry_);
    // The motors cannot exceed the joints' velocity limits.
    for (int i = 0; i < 4; ++i) {
      const double limit = robot_.wheels[i].velocity_limit;
      if (limit > 0) targets[i] = std::clamp(targets[i], -limit, limit);
    }
  }
  backend_->SetWheelTargets(targets);
  contacts_.clear();
  const double dt = options_.physics_step;
  backend_->Step(dt, &contacts_);
  ++steps_;

  // Wheel odometry: what the encoders say, integrated exactly over the step.
  const Twist2 wheels = TwistFromWheelSpeeds(backend_->wheel_velocities(), odom_geometry_);
  odom_twist_ = wheels;
  odom_pose_ = IntegrateTwist(odom_pose_, wheels.vx, wheels.wz, dt);

  const double now = time();
  in_contact_ = !contacts_.empty();
  for (const Contact& c : contacts_) {
    auto it = last_touch_.find(c.shape);
    const bool begins = it == last_touch_.end() || now - it->second > kContactRelease;
    last_touch_[c.shape] = now;
    if (!begins) continue;
    CollisionEvent e;
    e.time = now;
    e.contact = c;
    e.shape_name = c.shape >= 0 && c.shape < static_cast<int>(world_.shapes.size())
                       ? world_.shapes[c.shape].name
                       : std::string("(unknown)");
    events_.push_back(e);
    ++collision_count_;
  }
}

bool Simulator::ScanDue() const {
  const double due = scan_origin_ + static_cast<double>(scans_) / robot_.lidar.update_rate;
  return time() + 1e-9 >= due;
}

void Simulator::TakeScan(std::vector<float>* ranges) {
  lidar_->Scan(backend_->pose(), ranges);
  ++scans_;
}

std::vector<CollisionEvent> Simulator::TakeCollisionEvents() {
  std::vector<CollisionEvent> out;
  out.swap(events_);
  return out;
}

void Simulator::Reset() {
  backend_->SetPose(options_.spawn);
  odom_pose_ = Pose2{};
  odom_twist_ = Twist2{};
  cmd_v_ = cmd_w_ = 0.0;
  cmd_time_ = -1e9;
  last_touch_.clear();
  in_contact_ = false;
}

void Simulator::SetPose(const Pose2& pose) {
  backend_->SetPose(pose);
  cmd_v_ = cmd_w_ = 0.0;
  cmd_time_ = -1e9;
  last_touch_.clear();
  in_contact_ = false;
}

bool Simulator::PoseCollides(const Pose2& pose, std::string* what) const {
  std::vector<Eigen::Vector2d> polygon;
  for (const auto& v : robot_.footprint) polygon.push_back(TransformPoint(pose, v));
  int shape = -1;
  if (!body_slice_->PolygonCollides(polygon, &shape)) return false;
  if (what) {
    *what = shape >= 0 && shape < static_cast<int>(world_.shapes.size()) ? world_.shapes[shape].name
                                                                        : "(unknown)";
  }
  return true;
}

double Simulator::Clearance() const {
  // Distance from the centre minus the footprint's circumradius: a lower bound on the gap.
  double radius = 0.0;
  for (const auto& v : robot_.footprint) radius = std::max(radius, v.norm());
  const Pose2 p = backend_->pose();
  return std::max(0.0, body_slice_->Distance(Eigen::Vector2d(p.x, p.y)) - radius);
}

}  // namespace minibot3d_sim
