// Rays per second of DepthCamera::Render on the shipped default world (the 10 m × 8 m apartment:
// boxes, cylinders, the mesh sculpture, the ground plane), from six poses around the apartment at
// 0.3 m, looking slightly down, at 320×240, 640×480 and 1920×1080 with 1 and 2 threads; with and
// without a moving body (a person-sized box) in the scene; and the cost of moving a body.
//
//   depth_camera_bench [--benchmark_min_time=2]
// Reports rays_per_s (pixels cast per wall-clock second) and fps (frames per wall-clock second).
#include <cmath>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "minibot3d_sim/depth_camera.h"
#include "minibot3d_sim/ray_scene.h"
#include "minibot3d_sim/world_loader.h"

#ifndef MINIBOT3D_SIM_SOURCE_DIR
#error "MINIBOT3D_SIM_SOURCE_DIR must name the package source directory"
#endif

namespace minibot3d_sim {
namespace {

const World& DefaultWorld() {
  static const World world = [] {
    WorldLoadOptions options;
    options.use_gazebo_model_path_env = false;
    return LoadWorld(std::string(MINIBOT3D_SIM_SOURCE_DIR) + "/worlds/default.world", options,
                     nullptr);
  }();
  return world;
}

const std::vector<Eigen::Isometry3d>& Poses() {
  static const std::vector<Eigen::Isometry3d> poses = [] {
    const double xyyaw[][3] = {{-3.0, -1.5, 0.0}, {0.0, 0.6, 3.1},  {3.0, -1.0, 1.6},
                               {0.5, 2.0, -0.8},  {-2.5, 2.2, 0.4}, {3.7, 2.5, -2.4}};
    std::vector<Eigen::Isometry3d> out;
    for (const auto& p : xyyaw) {
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.translation() = Eigen::Vector3d(p[0], p[1], 0.3);
      pose.linear() = (Eigen::AngleAxisd(p[2], Eigen::Vector3d::UnitZ()) *
                       Eigen::AngleAxisd(0.15, Eigen::Vector3d::UnitY()))
                          .toRotationMatrix();
      out.push_back(pose);
    }
    return out;
  }();
  return poses;
}

// Args: width, height, threads, with a body (0/1).
void BM_DepthCameraRender(benchmark::State& state) {
  RayScene scene(DefaultWorld());
  if (state.range(3) != 0) {
    Shape torso;
    torso.type = ShapeType::kBox;
    torso.name = "torso";
    torso.pose.translation() = Eigen::Vector3d(0, 0, 0.85);
    torso.size = Eigen::Vector3d(0.3, 0.5, 1.7);
    const int person = scene.AddBody({torso}, "person");
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(-1.5, -1.2, 0.0);
    scene.SetBodyPose(person, pose);
    scene.Commit();
  }
  DepthCameraSpec spec;
  spec.width = static_cast<int>(state.range(0));
  spec.height = static_cast<int>(state.range(1));
  spec.horizontal_fov = 1.047;
  spec.near_clip = 0.05;
  spec.far_clip = 10.0;
  spec.threads = static_cast<int>(state.range(2));
  DepthCamera camera(spec);
  DepthFrame frame;
  const std::vector<Eigen::Isometry3d>& poses = Poses();
  std::size_t i = 0;
  for (auto _ : state) {
    camera.Render(scene, poses[i++ % poses.size()], &frame);
    benchmark::DoNotOptimize(frame.depth.data());
  }
  const double frames = static_cast<double>(state.iterations());
  state.counters["rays_per_s"] =
      benchmark::Counter(frames * spec.width * spec.height, benchmark::Counter::kIsRate);
  state.counters["fps"] = benchmark::Counter(frames, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DepthCameraRender)
    ->ArgNames({"w", "h", "threads", "body"})
    ->Args({320, 240, 1, 0})
    ->Args({320, 240, 2, 0})
    ->Args({320, 240, 2, 1})
    ->Args({640, 480, 1, 0})
    ->Args({640, 480, 1, 1})
    ->Args({640, 480, 2, 0})
    ->Args({1920, 1080, 1, 0})
    ->Args({1920, 1080, 2, 0})
    ->Args({1920, 1080, 2, 1})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// Moving one body and committing: what a simulator pays per step for each thing that walks.
void BM_CommitBodyPose(benchmark::State& state) {
  RayScene scene(DefaultWorld());
  Shape torso;
  torso.type = ShapeType::kBox;
  torso.name = "torso";
  torso.size = Eigen::Vector3d(0.3, 0.5, 1.7);
  const int person = scene.AddBody({torso}, "person");
  scene.Commit();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  double x = 0.0;
  for (auto _ : state) {
    x += 1e-3;
    pose.translation() = Eigen::Vector3d(x, 0.0, 0.85);
    scene.SetBodyPose(person, pose);
    scene.Commit();
  }
}
BENCHMARK(BM_CommitBodyPose)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace minibot3d_sim

BENCHMARK_MAIN();
