// Google Benchmark for the DWA local planner: one ComputeVelocity (plan
// pruning, path and goal distance grids, every rollout with its braking
// tail, scoring) on a 6 m x 6 m, 5 cm local costmap (120 x 120 cells) of a
// room corner with a doorway, a table, chair legs and a bin, inflated as
// costmap_2d does (inscribed 0.125 m, inflation 0.55 m, scaling 10).  The
// robot cruises at 0.4 m/s along a plan that turns through the doorway.
// Target: <= 5 ms per control cycle (20 Hz leaves 50 ms).  Report the
// median (--benchmark_repetitions, aggregates only by default).
#include <algorithm>
#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "minibot3d_navigation/dwa/dwa_planner.h"
#include "dwa_test_scenes.h"

namespace minibot3d_navigation {
namespace nav {
namespace dwa {
namespace {

using testing::AddBox;
using testing::Inflate;
using testing::kFootprint;

Costmap2D BenchCostmap() {
  // Local window with origin (0, 0); the robot is at its centre (3, 3).
  Costmap2D map(120, 120, 0.05, 0.0, 0.0);
  AddBox(&map, 0.0, 0.0, 6.0, 0.1);      // room walls
  AddBox(&map, 0.0, 0.0, 0.1, 6.0);
  AddBox(&map, 0.0, 4.45, 3.6, 4.55);    // wall with a doorway 3.6 .. 4.5
  AddBox(&map, 4.5, 4.45, 6.0, 4.55);
  AddBox(&map, 1.0, 1.0, 1.8, 1.6);      // table
  for (double x : {4.2, 4.6}) {          // chair legs
    for (double y : {1.8, 2.2}) AddBox(&map, x, y, x + 0.04, y + 0.04);
  }
  AddBox(&map, 5.3, 3.2, 5.6, 3.5);      // bin
  AddBox(&map, 2.0, 3.6, 2.1, 3.7);      // clutter
  Inflate(&map, 0.125, 0.55, 10.0);
  return map;
}

Path BenchPlan() {
  Path plan;
  // From behind the robot straight ahead, then left through the doorway and
  // on beyond the local window.
  for (double x = 2.5; x < 4.05; x += 0.05) plan.push_back({x, 3.0, 0.0});
  for (double y = 3.0; y < 8.0; y += 0.05) plan.push_back({4.05, y, kPi / 2});
  return plan;
}

// state.range(0): sim_time in tenths of a second; state.range(1) = 1 zeroes
// the path and goal biases so that no trajectory is cut short by the
// branch-and-bound on the partial cost (worst case: every rollout checked
// for collisions over its whole length).
void BM_ComputeVelocity(benchmark::State& state) {
  DwaOptions o;
  o.max_vel_x = 0.5;
  o.min_vel_x = 0.1;
  o.vx_samples = 20;
  o.vtheta_samples = 40;
  o.sim_time = state.range(0) / 10.0;
  o.sim_granularity = 0.025;
  if (state.range(1) == 1) {
    o.path_distance_bias = 0.0;
    o.goal_distance_bias = 0.0;
  }
  DwaPlanner planner(o, kFootprint);
  const Costmap2D map = BenchCostmap();
  const Path plan = BenchPlan();
  const Pose2 pose{3.0, 3.0, 0.1};
  Twist2 vel;
  vel.vx = 0.4;
  vel.wz = 0.1;
  Twist2 cmd;
  for (auto _ : state) {
    cmd = planner.ComputeVelocity(pose, vel, plan, map);
    benchmark::DoNotOptimize(cmd);
  }
  state.counters["trajectories"] = planner.last_stats().evaluated;
  state.counters["pruned"] = planner.last_stats().pruned;
  state.counters["cmd_vx"] = cmd.vx;
  state.counters["cmd_vth"] = cmd.wz;
}
BENCHMARK(BM_ComputeVelocity)
    ->ArgNames({"sim_time_ds", "unpruned"})
    ->Args({17, 0})
    ->Args({10, 0})
    ->Args({17, 1})
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(9)
    ->ReportAggregatesOnly(true);

}  // namespace
}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation

BENCHMARK_MAIN();
