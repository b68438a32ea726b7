#include "minibot3d_navigation/dwa/trajectory.h"

#include <algorithm>
#include <cmath>

namespace minibot3d_navigation {
namespace nav {
namespace dwa {
namespace {

// Moves `v` towards `target` by at most `max_change`.
double Approach(double v, double target, double max_change) {
  if (target > v) return std::min(target, v + max_change);
  return std::max(target, v - max_change);
}

// Sub-steps used to reach the end of the first control period exactly.
constexpr int kPeriodSubsteps = 8;

}  // namespace

const char* TrajectoryKindName(TrajectoryKind kind) {
  switch (kind) {
    case TrajectoryKind::kSampled:
      return "sampled";
    case TrajectoryKind::kInPlace:
      return "in-place rotation";
    case TrajectoryKind::kStop:
      return "stop";
    case TrajectoryKind::kEscape:
      return "escape";
  }
  return "?";
}

TrajectoryGenerator::TrajectoryGenerator(const DwaOptions& options)
    : options_(options),
      sim_period_(1.0 / options.controller_frequency),
      angular_granularity_(EffectiveAngularSimGranularity(options)) {}

Pose2 TrajectoryGenerator::Step(const Pose2& p, double v, double w,
                                 double dt) {
  const double mid = p.yaw + 0.5 * w * dt;
  return {p.x + v * dt * std::cos(mid), p.y + v * dt * std::sin(mid),
          NormalizeAngle(p.yaw + w * dt)};
}

VelocityWindow TrajectoryGenerator::Window(const Twist2& current) const {
  const double horizon = options_.dwa ? sim_period_ : options_.sim_time;
  // Speed cap so that the rollout length v*sim_time is at least the stopping
  // distance v^2/(2a) (see trajectory.h).
  const double vx_cap =
      std::min(options_.max_vel_x, 2.0 * options_.acc_lim_x * options_.sim_time);
  const double vx_lo = std::min(options_.min_vel_x, vx_cap);
  const double vth_cap = 2.0 * options_.acc_lim_theta * options_.sim_time;
  const double vth_hi = std::min(options_.max_vel_theta, vth_cap);
  const double vth_lo = std::max(options_.min_vel_theta, -vth_cap);
  const double dv = options_.acc_lim_x * horizon;
  const double dw = options_.acc_lim_theta * horizon;
  VelocityWindow w;
  w.max_vx = std::clamp(current.vx + dv, vx_lo, vx_cap);
  w.min_vx = std::clamp(current.vx - dv, vx_lo, vx_cap);
  w.max_vth = std::clamp(current.wz + dw, vth_lo, vth_hi);
  w.min_vth = std::clamp(current.wz - dw, vth_lo, vth_hi);
  return w;
}

Twist2 TrajectoryGenerator::BrakingCommand(const Twist2& current) const {
  Twist2 cmd;
  cmd.vx = Approach(current.vx, 0.0, options_.acc_lim_x * sim_period_);
  cmd.wz =
      Approach(current.wz, 0.0, options_.acc_lim_theta * sim_period_);
  return cmd;
}

void TrajectoryGenerator::Generate(const Pose2& start, const Twist2& current,
                                   const Twist2& command, TrajectoryKind kind,
                                   Trajectory* traj) const {
  traj->Clear();
  traj->command = command;
  traj->kind = kind;
  traj->start_vx = current.vx;
  const double acc_x = options_.acc_lim_x;
  const double acc_th = options_.acc_lim_theta;
  const double t_sim = options_.sim_time;

  // Rollout: enough steps that consecutive poses are at most sim_granularity
  // / angular_sim_granularity apart (TrajectoryPlanner divides the angular
  // part by the speed, not the angle; we use the angle).
  const double vmag = std::max(std::fabs(current.vx), std::fabs(command.vx));
  const double wmag =
      std::max(std::fabs(current.wz), std::fabs(command.wz));
  int steps = static_cast<int>(std::max(vmag * t_sim / options_.sim_granularity,
                                        wmag * t_sim / angular_granularity_) +
                               0.5);
  steps = std::max(steps, 1);
  const double dt = t_sim / steps;
  traj->dt = dt;
  traj->poses.reserve(steps + 1);
  Pose2 p = start;
  double v = current.vx, w = current.wz;
  traj->poses.push_back(p);
  int i = 0;
  for (; i < steps && (v != command.vx || w != command.wz); ++i) {
    const double v_next = Approach(v, command.vx, acc_x * dt);
    const double w_next = Approach(w, command.wz, acc_th * dt);
    p = Step(p, 0.5 * (v + v_next), 0.5 * (w + w_next), dt);
    v = v_next;
    w = w_next;
    traj->poses.push_back(p);
  }
  if (i < steps) {
    // Constant command from here: the same Step, with the heading's cosine
    // and sine advanced by a fixed rotation instead of recomputed.
    const double dth = w * dt;
    const double cr = std::cos(dth), sr = std::sin(dth);
    const double mid = p.yaw + 0.5 * dth;
    double c = std::cos(mid), s = std::sin(mid);
    double yaw = p.yaw;
    for (; i < steps; ++i) {
      p.x += v * dt * c;
      p.y += v * dt * s;
      yaw += dth;
      p.yaw = NormalizeAngle(yaw);
      traj->poses.push_back(p);
      const double c2 = c * cr - s * sr;
      s = s * cr + c * sr;
      c = c2;
    }
  }

  // Braking tail: the exact state after one control period (validation
  // guarantees sim_time >= period), then full braking.
  const double period = sim_period_;
  const double sub_dt = period / kPeriodSubsteps;
  Pose2 q = start;
  double vq = current.vx, wq = current.wz;
  for (int i = 0; i < kPeriodSubsteps; ++i) {
    const double v_next = Approach(vq, command.vx, acc_x * sub_dt);
    const double w_next = Approach(wq, command.wz, acc_th * sub_dt);
    q = Step(q, 0.5 * (vq + v_next), 0.5 * (wq + w_next), sub_dt);
    traj->braking_start_distance += std::fabs(0.5 * (vq + v_next)) * sub_dt;
    vq = v_next;
    wq = w_next;
  }
  traj->braking_poses.push_back(q);
  traj->braking_t0 = period;
  const double t_stop = std::max(std::fabs(vq) / acc_x, std::fabs(wq) / acc_th);
  if (t_stop <= 0.0) return;
  const double dist = StoppingDistance(vq, acc_x);
  const double angle = StoppingDistance(wq, acc_th);
  const int tail_steps = std::max(
      1, static_cast<int>(std::ceil(std::max(dist / options_.sim_granularity,
                                             angle / angular_granularity_))));
  const double tdt = t_stop / tail_steps;
  traj->braking_dt = tdt;
  traj->braking_poses.reserve(tail_steps + 1);
  for (int i = 0; i < tail_steps; ++i) {
    const double v_next = Approach(vq, 0.0, acc_x * tdt);
    const double w_next = Approach(wq, 0.0, acc_th * tdt);
    q = Step(q, 0.5 * (vq + v_next), 0.5 * (wq + w_next), tdt);
    vq = v_next;
    wq = w_next;
    traj->braking_poses.push_back(q);
  }
}

}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation
