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
  if (!std::isfinite(o.spawn.x) || !std::isfinite(o.spawn.y) || !std::isfinite(o.spawn.yaw)) {
    bad("spawn pose (x, y, yaw) must be finite");
  }
}

Simulator::Simulator(const RobotModel& robot, World world, const SimulatorOptions& options,
                     const BackendFactory& make_backend)
    : robot_(robot), world_(std::move(world)), options_(options) {
  ValidateOptions(options_);
  DriveSettings drive;
  drive.cmd_timeout = options_.cmd_timeout;
  drive.odom_wheel_separation_multiplier = options_.odom_wheel_separation_multiplier;
  drive.cmd_wheel_separation_multiplier = options_.cmd_wheel_separation_multiplier;
  drive.physics_step = options_.physics_step;
  drive_ = MakeDrive(robot_, drive);
  if (options_.odom_error.enabled()) {
    odom_error_ = std::make_unique<OdometryError>(options_.odom_error, options_.seed);
  }
  backend_ = make_backend ? make_backend(robot_, world_)
                          : MakePhysicsBackend(options_.physics, robot_, world_);
  for (size_t i = 0; i < robot_.lasers.size(); ++i) {
    const LaserSpec& spec = robot_.lasers[i];
    const double height = spec.pose_in_root.translation().z();
    auto& slice = laser_slices_[std::llround(height * 1e6)];
    if (!slice) slice = std::make_unique<WorldSlice>(world_, height);
    // Each laser its own noise stream; the first keeps the simulator's seed.
    lidars_.push_back(std::make_unique<Lidar>(spec, slice.get(), options_.seed + 7919u * i));
    scan_clocks_.emplace_back(spec.update_rate);
  }
  for (size_t i = 0; i < robot_.imus.size(); ++i) {
    imus_.emplace_back(robot_.imus[i], options_.seed + 104729u + 7919u * i);
    imu_clocks_.emplace_back(robot_.imus[i].update_rate);
  }
  for (size_t i = 0; i < robot_.ground_truths.size(); ++i) {
    ground_truths_.emplace_back(robot_.ground_truths[i], options_.seed + 224737u + 7919u * i);
    truth_clocks_.emplace_back(robot_.ground_truths[i].options.update_rate);
  }
  if (!robot_.cameras.empty()) {
    ray_scene_ = std::make_unique<RayScene>(world_);
    // The robot sees itself, but not the shapes of the links its cameras sit on.
    std::vector<Shape> own;
    for (const CollisionShape& c : robot_.collisions) {
      bool camera_link = false;
      for (const CameraSpec& cam : robot_.cameras) camera_link |= cam.link == c.link;
      if (!camera_link) own.push_back(c.shape);
    }
    if (!own.empty()) robot_body_ = ray_scene_->AddBody(own, robot_.name);
    for (size_t i = 0; i < robot_.cameras.size(); ++i) {
      const CameraSpec& c = robot_.cameras[i];
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
      cameras_.push_back(std::make_unique<DepthCamera>(spec));
      camera_clocks_.emplace_back(c.update_rate);
      camera_frames_.push_back(0);
    }
  }
  body_slice_ = std::make_unique<WorldSlice>(world_, robot_.body_pose.translation().z());
  backend_->SetPose(options_.spawn);
}

Eigen::Isometry3d Simulator::CameraPose(size_t i) const {
  return RootTransform(backend_->pose()) * robot_.cameras[i].pose_in_root;
}

void Simulator::TakeFrame(size_t i, DepthFrame* frame) {
  if (robot_body_ >= 0) {
    ray_scene_->SetBodyPose(robot_body_, RootTransform(backend_->pose()));
    ray_scene_->Commit();
  }
  cameras_[i]->Reseed(options_.seed + 15485863u * static_cast<unsigned>(i + 1) +
                      static_cast<unsigned>(camera_frames_[i]));
  cameras_[i]->Render(*ray_scene_, CameraPose(i), frame);
  SkipFrame(i);
}

void Simulator::SkipFrame(size_t i) {
  camera_clocks_[i].Fired();
  ++camera_frames_[i];
}

void Simulator::Command(const Twist2& command) { drive_->OnCommand(command, time()); }

void Simulator::Step() {
  const double dt = options_.physics_step;
  backend_->SetTargets(drive_->Actuate(time(), dt));
  contacts_.clear();
  backend_->Step(dt, &contacts_);
  ++steps_;

  DriveState state;
  state.time = time();
  state.dt = dt;
  state.pose = backend_->pose();
  state.twist = backend_->twist();
  state.wheel_positions = &backend_->wheel_positions();
  state.wheel_velocities = &backend_->wheel_velocities();
  drive_->Observe(state);
  if (odom_error_) odom_error_->Update(drive_->odometry_pose(), drive_->odometry_twist());

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

void Simulator::TakeScan(size_t laser, std::vector<float>* ranges) {
  lidars_[laser]->Scan(backend_->pose(), ranges);
  scan_clocks_[laser].Fired();
}

ImuReading Simulator::TakeImu(size_t i) {
  imu_clocks_[i].Fired();
  return imus_[i].Sample(time(), backend_->pose(), backend_->twist());
}

GroundTruthReading Simulator::TakeGroundTruth(size_t i) {
  truth_clocks_[i].Fired();
  return ground_truths_[i].Sample(backend_->pose(), backend_->twist());
}

std::vector<CollisionEvent> Simulator::TakeCollisionEvents() {
  std::vector<CollisionEvent> out;
  out.swap(events_);
  return out;
}

void Simulator::Reset() {
  backend_->SetPose(options_.spawn);
  drive_->Reset();
  if (odom_error_) odom_error_->Reset();
  for (auto& imu : imus_) imu.Restart();
  last_touch_.clear();
  in_contact_ = false;
}

void Simulator::SetPose(const Pose2& pose) {
  backend_->SetPose(pose);
  drive_->Stop();
  for (auto& imu : imus_) imu.Restart();
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
