// sim_bench: real-time factor of the simulator core (physics + lidar + odometry + the robot's depth
// cameras, every frame rendered as if someone listened; no ROS) driving a square route in a world,
// and the lidar's and cameras' rays per second.
//
//   sim_bench URDF_FILE WORLD_FILE [--physics bullet|kinematic|bullet_naive] [--seconds S]
//             [--x X --y Y --yaw YAW] [--side M] [--odom-multiplier K] [--controllers YAML]
//
// --controllers: a gazebo_ros_control robot's controller YAML (config/robots/quadbot/control.yaml).
//
// The robot follows the corners of a square of side --side metres from the spawn pose, with a
// simple closed loop on the true pose (turn in place towards the next corner, then drive), so the
// route stays the same whatever the wheels' slip.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "minibot3d_sim/simulator.h"
#include "naive_bullet_backend.h"
#include "minibot3d_sim/world_loader.h"

using minibot3d_sim::Pose2;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: sim_bench URDF_FILE WORLD_FILE [--physics NAME] [--seconds S] "
                         "[--x X --y Y --yaw YAW] [--side M] [--odom-multiplier K] "
                         "[--controllers YAML]\n");
    return 2;
  }
  const std::string urdf_path = argv[1], world_path = argv[2];
  std::string controllers_path;
  minibot3d_sim::SimulatorOptions options;
  double seconds = 60.0, side = 1.0;
  for (int i = 3; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const char* v = argv[i + 1];
    if (k == "--physics") options.physics = v;
    else if (k == "--seconds") seconds = std::atof(v);
    else if (k == "--x") options.spawn.x = std::atof(v);
    else if (k == "--y") options.spawn.y = std::atof(v);
    else if (k == "--yaw") options.spawn.yaw = std::atof(v);
    else if (k == "--side") side = std::atof(v);
    else if (k == "--odom-multiplier") options.odom_wheel_separation_multiplier = std::atof(v);
    else if (k == "--controllers") controllers_path = v;
    else {
      std::fprintf(stderr, "sim_bench: unknown option %s\n", k.c_str());
      return 2;
    }
  }
  std::ifstream in(urdf_path);
  if (!in) {
    std::fprintf(stderr, "sim_bench: cannot read %s\n", urdf_path.c_str());
    return 1;
  }
  std::stringstream xml;
  xml << in.rdbuf();
  try {
    minibot3d_sim::RobotModelOptions model_options;
    if (!controllers_path.empty()) {
      model_options.controllers = minibot3d_sim::LoadControllerParams(controllers_path);
    }
    const auto robot = minibot3d_sim::ParseRobotModel(xml.str(), model_options);
    minibot3d_sim::WorldLoadOptions load;
    auto world = minibot3d_sim::LoadWorld(world_path, load, nullptr);
    // bullet_naive, the yardstick of the default backend, ships in no library.
    minibot3d_sim::Simulator::BackendFactory naive;
    if (options.physics == "bullet_naive") {
      naive = [](const minibot3d_sim::RobotModel& r, const minibot3d_sim::World& w) {
        return std::unique_ptr<minibot3d_sim::PhysicsBackend>(
            new minibot3d_sim::NaiveBulletBackend(r, w));
      };
      options.physics = "bullet";
    }
    if (robot.lasers.empty()) throw std::invalid_argument("the robot has no laser to time");
    const minibot3d_sim::LaserSpec& laser = robot.lasers[0];
    minibot3d_sim::Simulator sim(robot, std::move(world), options, naive);
    if (naive) options.physics = "bullet_naive";

    std::vector<Pose2> corners;
    for (int k = 1; k <= 4; ++k) {
      const double a = options.spawn.yaw;
      const double cx[5] = {0, side, side, 0, 0}, cy[5] = {0, 0, side, side, 0};
      corners.push_back(Pose2{options.spawn.x + std::cos(a) * cx[k] - std::sin(a) * cy[k],
                              options.spawn.y + std::sin(a) * cx[k] + std::cos(a) * cy[k], 0});
    }
    const minibot3d_sim::WorldSlice slice(sim.world(), laser.pose_in_root.translation().z());
    std::vector<Pose2> route;  // poses every 0.1 s of sim time, reused for the lidar-only timing
    size_t target = 0;
    std::vector<float> ranges;
    minibot3d_sim::DepthFrame frame;
    long camera_frames = 0, camera_rays = 0;
    double camera_wall = 0.0;  // s spent rendering frames
    double path = 0.0;
    Pose2 last = sim.true_pose();
    const auto steps = static_cast<long>(seconds / sim.physics_step());
    const auto t0 = std::chrono::steady_clock::now();
    for (long i = 0; i < steps; ++i) {
      if (i % 50 == 0) {  // a 20 Hz controller
        const Pose2 p = sim.true_pose();
        const Pose2& c = corners[target];
        const double dx = c.x - p.x, dy = c.y - p.y;
        if (std::hypot(dx, dy) < 0.05) {
          target = (target + 1) % corners.size();
        }
        const double err = minibot3d_sim::NormalizeAngle(std::atan2(dy, dx) - p.yaw);
        if (std::abs(err) > 0.3) sim.SetCommand(0.0, err > 0 ? 1.0 : -1.0);
        else sim.SetCommand(std::min(0.4, std::hypot(dx, dy)), 2.0 * err);
      }
      if (sim.ScanDue(0)) {
        sim.TakeScan(0, &ranges);
        route.push_back(sim.true_pose());
      }
      for (size_t c = 0; c < sim.camera_count(); ++c) {
        if (!sim.CameraDue(c)) continue;
        const auto r0 = std::chrono::steady_clock::now();
        sim.TakeFrame(c, &frame);
        camera_wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count();
        ++camera_frames;
        camera_rays += static_cast<long>(frame.width) * frame.height;
      }
      sim.Step();
      const Pose2 p = sim.true_pose();
      path += std::hypot(p.x - last.x, p.y - last.y);
      last = p;
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const Pose2 t = sim.true_pose(), o = sim.odom_pose();
    // Skid-steer calibration: turning in place at 1 rad/s commanded for 4 s, how far does the body
    // really turn per radian the raw wheel odometry sees? Its inverse is the odometry's
    // wheel-separation multiplier.
    double turn_ratio = 1.0;
    {
      auto calib_options = options;
      calib_options.odom_wheel_separation_multiplier = 1.0;
      if (calib_options.physics == "bullet_naive") calib_options.physics = "bullet";
      minibot3d_sim::Simulator turn(robot, minibot3d_sim::LoadWorld(world_path, load, nullptr),
                                    calib_options, naive);
      double body = 0.0, odom = 0.0;
      Pose2 lt = turn.true_pose(), lo = turn.odom_pose();
      for (int i = 0; i < 4000; ++i) {
        if (i % 50 == 0) turn.SetCommand(0.0, 1.0);
        turn.Step();
        body += minibot3d_sim::NormalizeAngle(turn.true_pose().yaw - lt.yaw);
        odom += minibot3d_sim::NormalizeAngle(turn.odom_pose().yaw - lo.yaw);
        lt = turn.true_pose();
        lo = turn.odom_pose();
      }
      turn_ratio = body / odom;
    }
    // The lidar alone: scans from the route's poses, fan cast vs one grid-walk per beam.
    double fan_rays_per_s = 0.0, walk_rays_per_s = 0.0;
    {
      minibot3d_sim::Lidar lidar(laser, &slice, 1);
      const auto f0 = std::chrono::steady_clock::now();
      const int kScans = 2000;
      for (int i = 0; i < kScans; ++i) lidar.Scan(route[i % route.size()], &ranges);
      fan_rays_per_s = kScans * laser.samples /
          std::chrono::duration<double>(std::chrono::steady_clock::now() - f0).count();
      const auto w0 = std::chrono::steady_clock::now();
      const double inc = lidar.angle_increment();
      for (int i = 0; i < kScans; ++i) {
        const Pose2& p = route[i % route.size()];
        for (int k = 0; k < laser.samples; ++k) {
          const double a = p.yaw + laser.min_angle + k * inc;
          slice.CastRay(Eigen::Vector2d(p.x, p.y), Eigen::Vector2d(std::cos(a), std::sin(a)),
                        laser.max_range);
        }
      }
      walk_rays_per_s = kScans * laser.samples /
          std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    }
    std::printf("physics=%s sim_seconds=%.1f wall_seconds=%.3f real_time_factor=%.0f "
                "us_per_step=%.2f rays=%ld rays_per_wall_second=%.0f path_m=%.2f "
                "collisions=%lu odom_drift_m=%.3f turn_in_place_body_over_odom=%.3f "
                "lidar_fan_rays_per_s=%.0f lidar_per_beam_rays_per_s=%.0f\n",
                options.physics.c_str(), sim.time(), wall, sim.time() / wall, 1e6 * wall / steps,
                sim.lidar(0).rays_cast(), sim.lidar(0).rays_cast() / wall, path,
                static_cast<unsigned long>(sim.collision_count()),
                std::hypot(t.x - options.spawn.x - (std::cos(options.spawn.yaw) * o.x -
                                                     std::sin(options.spawn.yaw) * o.y),
                           t.y - options.spawn.y - (std::sin(options.spawn.yaw) * o.x +
                                                     std::cos(options.spawn.yaw) * o.y)),
                turn_ratio, fan_rays_per_s, walk_rays_per_s);
    if (sim.camera_count() > 0) {
      std::string sizes;
      for (size_t c = 0; c < sim.camera_count(); ++c) {
        const minibot3d_sim::DepthCameraSpec& spec = sim.camera(c).spec();
        sizes += (c ? "," : "") + std::to_string(spec.width) + "x" + std::to_string(spec.height);
      }
      std::printf("  cameras=%s frames=%ld camera_rays=%ld camera_rays_per_sim_second=%.0f "
                  "camera_rays_per_wall_second_rendering=%.0f rendering_share_of_wall=%.2f\n",
                  sizes.c_str(), camera_frames, camera_rays, camera_rays / sim.time(),
                  camera_wall > 0 ? camera_rays / camera_wall : 0.0, camera_wall / wall);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sim_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
