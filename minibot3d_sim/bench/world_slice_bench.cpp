// Rays per second of WorldSlice::CastRay on the shipped default world, and of Bullet's
// btCollisionWorld::rayTest on the same world for comparison. Same rays for both: 360-beam scans at
// the lidar height (0.11 m, 12 m range) from six poses spread over the apartment.
//
//   world_slice_bench [--benchmark_min_time=2]
// Reports items_per_second (= rays per second) and a rays_per_s counter.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>
#include <benchmark/benchmark.h>
#include <btBulletCollisionCommon.h>

#include "minibot3d_sim/bullet_world.h"
#include "minibot3d_sim/world_loader.h"
#include "minibot3d_sim/world_slice.h"

#ifndef MINIBOT3D_SIM_SOURCE_DIR
#error "MINIBOT3D_SIM_SOURCE_DIR must name the package source directory"
#endif

namespace minibot3d_sim {
namespace {

constexpr double kLidarHeight = 0.11;
constexpr double kMaxRange = 12.0;

const World& DefaultWorld() {
  static const World world = [] {
    WorldLoadOptions options;
    options.use_gazebo_model_path_env = false;
    return LoadWorld(std::string(MINIBOT3D_SIM_SOURCE_DIR) + "/worlds/default.world", options,
                     nullptr);
  }();
  return world;
}

struct Ray {
  Eigen::Vector2d origin, dir;
};

const std::vector<Ray>& Rays() {
  static const std::vector<Ray> rays = [] {
    const std::vector<Eigen::Vector2d> poses = {{-3.0, -1.5}, {0.0, 0.6},  {3.0, -1.0},
                                                {0.5, 2.0},   {-2.5, 2.2}, {3.7, 2.5}};
    std::vector<Ray> out;
    for (const Eigen::Vector2d& p : poses) {
      for (int k = 0; k < 360; ++k) {
        const double a = 2.0 * M_PI * k / 360.0;
        out.push_back(Ray{p, Eigen::Vector2d(std::cos(a), std::sin(a))});
      }
    }
    return out;
  }();
  return rays;
}

void SetRate(benchmark::State& state, std::size_t rays_per_iteration) {
  const double rays = static_cast<double>(state.iterations()) * rays_per_iteration;
  state.SetItemsProcessed(static_cast<int64_t>(rays));
  state.counters["rays_per_s"] = benchmark::Counter(rays, benchmark::Counter::kIsRate);
}

void BM_WorldSliceCastRay(benchmark::State& state) {
  const WorldSlice slice(DefaultWorld(), kLidarHeight, 0.25);
  const std::vector<Ray>& rays = Rays();
  for (auto _ : state) {
    double sum = 0.0;
    for (const Ray& r : rays) {
      const RayHit hit = slice.CastRay(r.origin, r.dir, kMaxRange);
      sum += std::isinf(hit.range) ? 0.0 : hit.range;
    }
    benchmark::DoNotOptimize(sum);
  }
  SetRate(state, rays.size());
}
BENCHMARK(BM_WorldSliceCastRay);

// Bullet on the same world; arg 0: default sub-simplex convex cast, 1: GJK convex cast (the
// accurate one).
void BM_BulletRayTest(benchmark::State& state) {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btCollisionWorld collision_world(&dispatcher, &broadphase, &config);
  const BulletWorldObjects objects(DefaultWorld(), &collision_world);
  collision_world.updateAabbs();
  const std::vector<Ray>& rays = Rays();
  const bool gjk = state.range(0) != 0;
  for (auto _ : state) {
    double sum = 0.0;
    for (const Ray& r : rays) {
      const btVector3 from(r.origin.x(), r.origin.y(), kLidarHeight);
      const btVector3 to(r.origin.x() + kMaxRange * r.dir.x(),
                         r.origin.y() + kMaxRange * r.dir.y(), kLidarHeight);
      btCollisionWorld::ClosestRayResultCallback cb(from, to);
      if (gjk) cb.m_flags |= btTriangleRaycastCallback::kF_UseGjkConvexCastRaytest;
      collision_world.rayTest(from, to, cb);
      sum += cb.hasHit() ? cb.m_closestHitFraction : 0.0;
    }
    benchmark::DoNotOptimize(sum);
  }
  SetRate(state, rays.size());
}
BENCHMARK(BM_BulletRayTest)->Arg(0)->Arg(1);

// Slice construction (done once per world and height).
void BM_WorldSliceBuild(benchmark::State& state) {
  for (auto _ : state) {
    const WorldSlice slice(DefaultWorld(), kLidarHeight, 0.25);
    benchmark::DoNotOptimize(slice.segments().data());
  }
}
BENCHMARK(BM_WorldSliceBuild)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace minibot3d_sim

BENCHMARK_MAIN();
