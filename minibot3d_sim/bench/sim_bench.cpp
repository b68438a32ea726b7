// sim_bench: real-time factor of the simulator core (physics + lidar + odometry, no ROS) driving a
// square route in a world, and the lidar's rays per second.
//
//   sim_bench URDF_FILE WORLD_FILE [--physics bullet|kinematic|bullet_naive] [--seconds S]
//             [--x X --y Y --yaw YAW] [--side M]
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
#include "minibot3d_sim/world_loader.h"

using minibot3d_sim::Pose2;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: sim_bench URDF_FILE WORLD_FILE [--physics NAME] [--seconds S] "
                         "[--x X --y Y --yaw YAW] [--side M]\n");
    return 2;
  }
  const std::string urdf_path = argv[1], world_path = argv[2];
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
    const auto robot = minibot3d_sim::ParseRobotModel(xml.str());
    minibot3d_sim::WorldLoadOptions load;
    auto world = minibot3d_sim::LoadWorld(world_path, load, nullptr);
    minibot3d_sim::Simulator sim(robot, std::move(world), options);

    std::vector<Pose2> corners;
    for (int k = 1; k <= 4; ++k) {
      const double a = options.spawn.yaw;
      const double cx[5] = {0, side, side, 0, 0}, cy[5] = {0, 0, side, side, 0};
      corners.push_back(Pose2{options.spawn.x + std::cos(a) * cx[k] - std::sin(a) * cy[k],
                              options.spawn.y + std::sin(a) * cx[k] + std::cos(a) * cy[k], 0});
    }
    size_t target = 0;
    std::vector<float> ranges;
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
      if (sim.ScanDue()) sim.TakeScan(&ranges);
      sim.Step();
      const Pose2 p = sim.true_pose();
      path += std::hypot(p.x - last.x, p.y - last.y);
      last = p;
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const Pose2 t = sim.true_pose(), o = sim.odom_pose();
    std::printf("physics=%s sim_seconds=%.1f wall_seconds=%.3f real_time_factor=%.0f "
                "us_per_step=%.2f rays=%ld rays_per_wall_second=%.0f path_m=%.2f "
                "collisions=%lu odom_drift_m=%.3f\n",
                options.physics.c_str(), sim.time(), wall, sim.time() / wall, 1e6 * wall / steps,
                sim.lidar().rays_cast(), sim.lidar().rays_cast() / wall, path,
                static_cast<unsigned long>(sim.collision_count()),
                std::hypot(t.x - options.spawn.x - (std::cos(options.spawn.yaw) * o.x -
                                                     std::sin(options.spawn.yaw) * o.y),
                           t.y - options.spawn.y - (std::sin(options.spawn.yaw) * o.x +
                                                     std::cos(options.spawn.yaw) * o.y)));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sim_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
