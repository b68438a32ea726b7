#include "minibot3d_navigation/dwa/dwa_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace minibot3d_navigation {
namespace nav {
namespace dwa {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Radius searched for the nearest obstacle named in error messages.
constexpr double kDiagnoseRadius = 2.0;

std::string Fixed(double v, int digits = 2) {
  std::ostringstream os;
  os.precision(digits);
  os << std::fixed << v;
  return os.str();
}

std::string Xy(double x, double y) {
  return "(" + Fixed(x, 3) + ", " + Fixed(y, 3) + ")";
}

// The i-th of n forward speeds spanning the window (its top when n is 1).
double VxSample(const VelocityWindow& win, int n, int i) {
  return n == 1 ? win.max_vx : win.min_vx + (win.max_vx - win.min_vx) * i / (n - 1);
}

// The j-th of n turn rates spanning [lo, hi] (its middle when n is 1).
double VthSample(int n, int j, double lo, double hi) {
  return n == 1 ? 0.5 * (lo + hi) : lo + (hi - lo) * j / (n - 1);
}

bool SameGoal(const Pose2& a, const Pose2& b) {
  return std::fabs(a.x - b.x) < 1e-6 && std::fabs(a.y - b.y) < 1e-6 &&
         std::fabs(AngleDiff(a.yaw, b.yaw)) < 1e-6;
}

// Distance from point (px, py) in the robot frame to the footprint polygon
// (0 inside).
double FootprintDistance(const Footprint& fp, double px, double py) {
  if (minibot3d_common::PointInPolygon(fp, px, py)) return 0.0;
  double d = kInf;
  for (size_t i = 0, j = fp.size() - 1; i < fp.size(); j = i++) {
    d = std::min(d, minibot3d_common::PointSegmentDistance(Point2{px, py}, fp[i], fp[j]));
  }
  return d;
}

}  // namespace

const char* DwaModeName(DwaPlanner::Mode mode) {
  switch (mode) {
    case DwaPlanner::Mode::kNone:
      return "none";
    case DwaPlanner::Mode::kFollowPath:
      return "follow path";
    case DwaPlanner::Mode::kEscape:
      return "escape";
    case DwaPlanner::Mode::kRotateToPath:
      return "rotate to path";
    case DwaPlanner::Mode::kApproachGoal:
      return "approach goal";
    case DwaPlanner::Mode::kStopAtGoal:
      return "stop at goal";
    case DwaPlanner::Mode::kRotateToGoal:
      return "rotate to goal";
    case DwaPlanner::Mode::kAtGoal:
      return "at goal";
    case DwaPlanner::Mode::kYield:
      return "yield to a moving obstacle";
  }
  return "?";
}

namespace {
const DwaOptions& Validated(const DwaOptions& options) {
  ValidateDwaOptions(options);
  return options;
}
const Footprint& CheckedFootprint(const Footprint& footprint) {
  if (footprint.size() < 3) {
    throw std::invalid_argument(
        "DWA local planner: the footprint needs at least 3 points, got " +
        std::to_string(footprint.size()));
  }
  for (const Point2& p : footprint) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
      throw std::invalid_argument(
          "DWA local planner: footprint point is not finite");
    }
  }
  return footprint;
}
}  // namespace

DwaPlanner::DwaPlanner(const DwaOptions& options, const Footprint& footprint)
    : options_(Validated(options)),
      footprint_(CheckedFootprint(footprint)),
      generator_(options_),
      oscillation_critic_(options_.oscillation_reset_dist),
      path_critic_(footprint_),
      goal_critic_(footprint_),
      obstacle_critic_(footprint_),
      moving_critic_(footprint_, options_.moving_obstacle_horizon,
                     options_.moving_obstacle_margin, options_.moving_obstacle_deviation,
                     options_.personal_distance),
      critics_{&oscillation_critic_, &path_critic_, &goal_critic_,
               &obstacle_critic_, &moving_critic_} {
  oscillation_critic_.set_scale(0.0);
  obstacle_critic_.set_tight_speed(CreepSpeed());
  obstacle_critic_.set_full_margin_speed(std::min(options_.full_margin_vel, options_.max_vel_x));
}

void DwaPlanner::Reset() {
  latched_ = false;
  yield_cycles_ = 0;
  rotating_to_goal_ = false;
  rotating_to_path_ = false;
  escaping_ = false;
  spun_in_place_ = 0.0;
  for (TrajectoryCritic* c : critics_) c->Reset();
  best_.Clear();
  stats_ = CycleStats();
}

void DwaPlanner::GenerateBraking(const Pose2& pose, const Twist2& velocity,
                                 Trajectory* traj) const {
  generator_.Generate(pose, velocity, Twist2(), TrajectoryKind::kStop, traj);
  traj->command = generator_.BrakingCommand(velocity);
}

double DwaPlanner::CreepSpeed() const {
  return std::max(options_.min_vel_x, -options_.escape_vel);
}

bool DwaPlanner::Stopped(const Twist2& v) const {
  return std::fabs(v.vx) <= options_.trans_stopped_vel &&
         std::fabs(v.wz) <= options_.rot_stopped_vel;
}

void DwaPlanner::CheckInputs(const Pose2& pose, const Twist2& velocity,
                             const Path& plan,
                             const Costmap2D& costmap) const {
  if (plan.empty()) {
    throw ControlError("DWA local planner: the plan is empty, nothing to follow");
  }
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) ||
      !std::isfinite(pose.yaw)) {
    throw ControlError("DWA local planner: the robot pose is not finite (" +
                       Fixed(pose.x, 3) + ", " + Fixed(pose.y, 3) + ", " +
                       Fixed(pose.yaw, 3) + ")");
  }
  if (!std::isfinite(velocity.vx) || !std::isfinite(velocity.wz)) {
    throw ControlError("DWA local planner: the robot velocity is not finite");
  }
  if (costmap.size_x() <= 0 || costmap.size_y() <= 0) {
    throw ControlError("DWA local planner: the local costmap is empty");
  }
  int mx, my;
  if (!costmap.WorldToMap(pose.x, pose.y, &mx, &my)) {
    throw ControlError(
        "DWA local planner: the robot pose " + Xy(pose.x, pose.y) +
        " is off the local costmap [" + Fixed(costmap.origin_x(), 3) + ", " +
        Fixed(costmap.origin_x() + costmap.size_x_m(), 3) + "] x [" +
        Fixed(costmap.origin_y(), 3) + ", " +
        Fixed(costmap.origin_y() + costmap.size_y_m(), 3) +
        "]; is the local costmap a rolling window in the pose's frame?");
  }
}

void DwaPlanner::PrunePlan(const Pose2& pose, const Path& plan,
                           const Costmap2D& costmap) {
  size_t first = 0;
  if (options_.prune_plan) {
    // Closest pose on the first stretch of the plan that lies on the local
    // costmap; everything before it has been passed.
    double best = kInf;
    bool started = false;
    for (size_t i = 0; i < plan.size(); ++i) {
      int mx, my;
      if (costmap.WorldToMap(plan[i].x, plan[i].y, &mx, &my)) {
        started = true;
        const double dx = plan[i].x - pose.x, dy = plan[i].y - pose.y;
        const double d = dx * dx + dy * dy;
        if (d < best) {
          best = d;
          first = i;
        }
      } else if (started) {
        break;
      }
    }
  }
  pruned_.assign(plan.begin() + static_cast<std::ptrdiff_t>(first), plan.end());
}

Twist2 DwaPlanner::Brake(const Pose2& pose, const Twist2& velocity,
                          Mode mode, const Costmap2D& costmap) {
  GenerateBraking(pose, velocity, &best_);
  obstacle_critic_.SetCostmap(costmap);
  // Braking is the safest thing available whether or not it is clear, so
  // the cost is informative only.
  best_.cost = obstacle_critic_.Score(best_);
  stats_.mode = mode;
  return best_.command;
}

bool DwaPlanner::RotateTowards(const Pose2& pose, const Twist2& velocity,
                               double target_yaw, double tolerance,
                               const Costmap2D& costmap, Twist2* command) {
  const double diff = AngleDiff(target_yaw, pose.yaw);
  const double sign = diff >= 0.0 ? 1.0 : -1.0;
  const double adiff = std::fabs(diff);
  const double max_rot =
      diff >= 0.0 ? options_.max_vel_theta : -options_.min_vel_theta;
  const double acc = options_.acc_lim_theta;
  const double period = generator_.sim_period();
  // TrajectoryPlannerROS::rotateToGoal: proportional, at least the in-place
  // minimum, acceleration-limited, slow enough to stop at the target.
  double mag = std::clamp(adiff, options_.min_in_place_vel_theta, max_rot);
  const double current = std::max(0.0, sign * velocity.wz);
  mag = std::clamp(mag, current - acc * period, current + acc * period);
  mag = std::min(mag, std::sqrt(2.0 * acc * adiff));
  mag = std::clamp(mag, options_.min_in_place_vel_theta, max_rot);
  // Ours: holding `mag` for one period and then braking must not overshoot
  // the target by more than half the tolerance:
  //   mag * T + mag^2 / (2 acc) <= adiff + tolerance / 2.
  const double budget = adiff + 0.5 * tolerance;
  const double no_overshoot =
      acc * (-period + std::sqrt(period * period + 2.0 * budget / acc));
  mag = std::min(mag, no_overshoot);
  *command = Twist2();
  command->wz = sign * mag;

  generator_.Generate(pose, velocity, *command, TrajectoryKind::kInPlace,
                      &candidate_);
  // Only the part of the rollout up to the target angle matters (the robot
  // stops there); the braking tail covers the next control period.
  double turned = 0.0;
  size_t keep = 1;
  for (; keep < candidate_.poses.size(); ++keep) {
    turned += std::fabs(
        AngleDiff(candidate_.poses[keep].yaw, candidate_.poses[keep - 1].yaw));
    if (turned > budget) break;
  }
  candidate_.poses.resize(std::min(keep + 1, candidate_.poses.size()));
  obstacle_critic_.SetCostmap(costmap);
  candidate_.cost = obstacle_critic_.Score(candidate_);
  ++stats_.evaluated;
  if (candidate_.cost >= 0.0 && moving_critic_.Score(candidate_) < 0.0) {
    // A moving obstacle is about to touch: stand while it does (see FollowPath).
    ++stats_.rejected[4];
    GenerateBraking(pose, velocity, &best_);
    *command = best_.command;
    yielded_ = true;
    return true;
  }
  std::swap(best_, candidate_);
  if (best_.cost < 0.0) ++stats_.rejected[3];
  return best_.cost >= 0.0;
}

bool DwaPlanner::TurnIsClear(const Pose2& pose, double target_yaw, const Costmap2D& costmap) {
  // The turn on the spot from a standstill, pose by pose, scored as the
  // rotation itself would be (lethal cells only at turning speed).
  const double diff = AngleDiff(target_yaw, pose.yaw);
  const double step = EffectiveAngularSimGranularity(options_);
  const int n = std::max(1, static_cast<int>(std::ceil(std::fabs(diff) / step)));
  Trajectory& turn = candidate_;
  turn.Clear();
  turn.kind = TrajectoryKind::kInPlace;
  turn.command = Twist2();
  turn.command.wz = diff >= 0.0 ? options_.min_in_place_vel_theta
                                : -options_.min_in_place_vel_theta;
  turn.start_vx = 0.0;
  for (int i = 0; i <= n; ++i) {
    turn.poses.push_back({pose.x, pose.y, NormalizeAngle(pose.yaw + diff * i / n)});
  }
  obstacle_critic_.SetCostmap(costmap);
  return obstacle_critic_.Score(turn) >= 0.0;
}

double DwaPlanner::PathHeadingError(const Pose2& pose,
                                    const Costmap2D& costmap) const {
  // Bearing of the first plan pose at least heading_lookahead from the robot
  // (the plan's end if none is).  Measured from the robot, so a robot that
  // has strayed beside the plan is also turned back towards it.
  const double lookahead =
      std::max(options_.heading_lookahead, 2.0 * costmap.resolution());
  const Pose2* target = &pruned_.back();
  for (const Pose2& p : pruned_) {
    if (std::hypot(p.x - pose.x, p.y - pose.y) >= lookahead) {
      target = &p;
      break;
    }
  }
  int mx, my;
  if (!costmap.WorldToMap(target->x, target->y, &mx, &my)) {
    return std::numeric_limits<double>::quiet_NaN();  // FollowPath reports it
  }
  const double dx = target->x - pose.x, dy = target->y - pose.y;
  if (std::hypot(dx, dy) < 1e-6) return 0.0;
  return AngleDiff(std::atan2(dy, dx), pose.yaw);
}

double DwaPlanner::Evaluate(double bound) {
  ++stats_.evaluated;
  double cost = 0.0;
  for (size_t k = 0; k < critics_.size(); ++k) {
    const double s = critics_[k]->Score(candidate_);
    if (s < 0.0) {
      ++stats_.rejected[k];
      candidate_.cost = -1.0;
      return -1.0;
    }
    cost += critics_[k]->scale() * s;
    // Later critics only add (scores >= 0): stop once this cannot win.
    if (cost > bound && k + 1 < critics_.size()) {
      ++stats_.pruned;
      candidate_.cost = kInf;
      return kInf;
    }
  }
  candidate_.cost = cost;
  return cost;
}

void DwaPlanner::PrepareCritics(const Pose2& pose, const Twist2& velocity,
                                const Costmap2D& costmap) {
  const double res = options_.meter_scoring ? costmap.resolution() : 1.0;
  path_critic_.set_scale(options_.path_distance_bias * res);
  goal_critic_.set_scale(options_.goal_distance_bias * res);
  obstacle_critic_.set_scale(options_.occdist_scale * res);
  moving_critic_.set_scale(options_.moving_obstacle_scale * res);
  for (TrajectoryCritic* c : critics_) {
    if (!c->Prepare(pose, velocity, pruned_, costmap)) {
      throw ControlError("DWA local planner: " + c->failure());
    }
  }
}

void DwaPlanner::UpdateEscape(const Pose2& pose) {
  if (escaping_ &&
      (std::hypot(pose.x - escape_pose_.x, pose.y - escape_pose_.y) >
           options_.escape_reset_dist ||
       std::fabs(AngleDiff(pose.yaw, escape_pose_.yaw)) >
           options_.escape_reset_theta)) {
    escaping_ = false;
  }
}

Twist2 DwaPlanner::FollowPath(const Pose2& pose, const Twist2& velocity,
                               const Costmap2D& costmap) {
  PrepareCritics(pose, velocity, costmap);
  UpdateEscape(pose);
  const VelocityWindow win = generator_.Window(velocity);

  // Two passes: first the rule of ObstacleCostCritic (the outline off lethal
  // cells, and inside the inscribed band no nearer to them than the speed's
  // margin); then, only if nothing passed, a way out: any trajectory (arc or
  // turn on the spot) that touches no lethal cell, brakes in time, and ends
  // with the outline back out of the band.  A robot that drifted to the edge
  // of the band (slip, localization, a recovery turn) can so leave it instead
  // of freezing, but never creeps along inside it towards a wall.
  //
  // The way out is for a robot at creeping speed (at most
  // max(min_vel_x, |escape_vel|)), and is taken at that speed.  A robot
  // moving faster when nothing passes the first pass has been carried towards
  // an obstacle further than its rollouts predicted (wheel slip, a late
  // costmap): it brakes, if braking touches no lethal cell, and looks for the
  // way out once it has slowed down, rather than picking the best-scoring
  // fast arc through the band.
  const double creep = CreepSpeed();
  const bool fast = velocity.vx > creep + 1e-6 || velocity.vx < -creep - 1e-6;
  Choice choice;
  for (int pass = 0; pass < 2 && !choice.found; ++pass) {
    obstacle_critic_.set_lethal_only(pass == 1);
    if (pass == 1 && fast) {
      GenerateBraking(pose, velocity, &candidate_);
      if (Evaluate(kInf) >= 0.0) Take(&choice);
      break;
    }
    SearchPass(pass, pose, velocity, win, costmap, &choice);
  }
  obstacle_critic_.set_lethal_only(false);

  if (choice.found) {
    for (TrajectoryCritic* c : critics_) c->Debrief(best_);
    stats_.mode = Mode::kFollowPath;
    return best_.command;
  }
  if (stats_.rejected[4] > 0) {
    // A moving obstacle is in every way on: brake (zero once stopped) and
    // let it pass, if braking keeps off lethal cells and off the obstacle.
    obstacle_critic_.set_lethal_only(true);
    GenerateBraking(pose, velocity, &candidate_);
    ++stats_.evaluated;
    candidate_.cost = obstacle_critic_.Score(candidate_);
    const bool legal = candidate_.cost >= 0.0;
    obstacle_critic_.set_lethal_only(false);
    if (legal) {
      std::swap(best_, candidate_);
      stats_.mode = Mode::kYield;
      return best_.command;
    }
  }
  return EscapeOrFail(pose, velocity, costmap);
}

void DwaPlanner::Take(Choice* choice) {
  std::swap(best_, candidate_);
  choice->cost = best_.cost;
  choice->found = true;
}

bool DwaPlanner::ExitsBand(int pass, const Costmap2D& costmap) const {
  if (pass == 0) return true;
  const int c = FootprintCost(costmap, footprint_, candidate_.end());
  return c >= 0 && c < kInscribedInflatedObstacle;
}

// Among equally scored trajectories the faster wins (Fox et al.'s velocity
// term as a tie-break): costs move in whole cells, so a crawl at min_vel_x and
// an arc a few times faster that ends in the same cell score the same, and
// the crawl would otherwise win for being sampled first.
void DwaPlanner::TakeIfBetter(int pass, const Costmap2D& costmap, Choice* choice) {
  const bool better =
      candidate_.cost < choice->cost ||
      (choice->found && candidate_.cost == choice->cost &&
       std::fabs(candidate_.command.vx) > std::fabs(best_.command.vx));
  if (candidate_.cost >= 0.0 && better && ExitsBand(pass, costmap)) Take(choice);
}

void DwaPlanner::SearchPass(int pass, const Pose2& pose, const Twist2& velocity,
                            const VelocityWindow& win, const Costmap2D& costmap,
                            Choice* choice) {
  if (!escaping_) SampleArcs(pass, pose, velocity, win, costmap, choice);
  if (pass == 1 && options_.escape_vel < 0.0) {
    SampleEscapeArcs(pose, velocity, win, costmap, choice);
  }
  SampleRotations(pass, pose, velocity, win, costmap, choice);

  // Braking to a standstill: the command every admissible trajectory leaves
  // open (the dynamic window alone may not reach vx = 0), taken only when
  // nothing else is legal; as a competitor it would win against slow
  // rotations (lower obstacle cost) and make the robot stop-start.  Not while
  // escaping: there the escape trajectory itself is the fallback.
  if (!choice->found && !escaping_ &&
      (std::fabs(velocity.vx) > 1e-3 || std::fabs(velocity.wz) > 1e-3)) {
    GenerateBraking(pose, velocity, &candidate_);
    Evaluate(kInf);
    TakeIfBetter(pass, costmap, choice);
  }
}

void DwaPlanner::SampleArcs(int pass, const Pose2& pose, const Twist2& velocity,
                            const VelocityWindow& win, const Costmap2D& costmap,
                            Choice* choice) {
  const int nvx = options_.vx_samples;
  const int nth = options_.vtheta_samples;
  const double creep = CreepSpeed();
  for (int i = 0; i < nvx; ++i) {
    Twist2 cmd;
    cmd.vx = VxSample(win, nvx, i);
    if (pass == 1 && cmd.vx > creep + 1e-6) break;
    // The theta samples span the window, narrowed at this speed to the
    // arcs within max_centripetal_acc (none if the robot turns too fast
    // for this speed: it has to slow down first).
    double lo = win.min_vth, hi = win.max_vth;
    if (options_.max_centripetal_acc > 0.0 && std::fabs(cmd.vx) > 1e-9) {
      const double limit = options_.max_centripetal_acc / std::fabs(cmd.vx);
      lo = std::max(lo, -limit);
      hi = std::min(hi, limit);
    }
    // The straight command first, then the theta samples.
    for (int j = -1; j < nth; ++j) {
      if (j >= 0 && lo > hi) break;
      cmd.wz = j < 0 ? 0.0 : VthSample(nth, j, lo, hi);
      if (j >= 0 && cmd.wz == 0.0) continue;
      generator_.Generate(pose, velocity, cmd, TrajectoryKind::kSampled,
                          &candidate_);
      Evaluate(choice->cost);
      TakeIfBetter(pass, costmap, choice);
    }
  }
}

// The way out, backwards: arcs at escape_vel.  A robot that drifted against a
// wall at an angle can neither turn (its corners sweep into the wall) nor back
// straight out, but an arc backs its nose off.
void DwaPlanner::SampleEscapeArcs(const Pose2& pose, const Twist2& velocity,
                                  const VelocityWindow& win, const Costmap2D& costmap,
                                  Choice* choice) {
  const int nth = options_.vtheta_samples;
  for (int j = 0; j < nth; ++j) {
    Twist2 cmd;
    cmd.vx = options_.escape_vel;
    cmd.wz = VthSample(nth, j, win.min_vth, win.max_vth);
    generator_.Generate(pose, velocity, cmd, TrajectoryKind::kEscape, &candidate_);
    Evaluate(choice->cost);
    TakeIfBetter(1, costmap, choice);
  }
}

// In-place rotations (TrajectoryPlanner): taken if no worse than the best so
// far, preferring the one pointing the robot closest to the goal (goal distance
// heading_lookahead ahead of its end pose).  Unlike TrajectoryPlanner, a
// rotation must also point the robot closer to the goal than it is now, so a
// blocked robot does not turn just because it may; and never past a full
// circle on the spot.
void DwaPlanner::SampleRotations(int pass, const Pose2& pose, const Twist2& velocity,
                                 const VelocityWindow& win, const Costmap2D& costmap,
                                 Choice* choice) {
  const int nth = options_.vtheta_samples;
  const double dvth = nth > 1 ? (win.max_vth - win.min_vth) / (nth - 1) : 0.0;
  const double ahead_now =
      goal_critic_.DistanceAhead(pose, options_.heading_lookahead);
  double heading_dist = kInf;
  const bool spun_out = spun_in_place_ > 2.0 * kPi;
  double last_limited = 0.0;
  for (int j = 0; j < nth; ++j) {
    const double samp = VthSample(nth, j, win.min_vth, win.max_vth);
    if (!(samp > dvth || samp < -dvth)) continue;
    const double limited =
        samp > 0.0 ? std::max(samp, options_.min_in_place_vel_theta)
                   : std::min(samp, -options_.min_in_place_vel_theta);
    if (limited == last_limited) continue;  // same rollout as the last one
    last_limited = limited;
    if (spun_out) {
      ++stats_.rotations_refused;
      continue;
    }
    Twist2 cmd;
    cmd.wz = limited;
    generator_.Generate(pose, velocity, cmd, TrajectoryKind::kInPlace,
                        &candidate_);
    const double cost = Evaluate(choice->found ? choice->cost : kInf);
    if (cost >= 0.0 && cost < kInf && (!choice->found || cost <= choice->cost) &&
        ExitsBand(pass, costmap)) {
      ConsiderRotation(pass, costmap, ahead_now, &heading_dist, choice);
    }
  }
}

void DwaPlanner::ConsiderRotation(int pass, const Costmap2D& costmap, double ahead_now,
                                  double* heading_dist, Choice* choice) {
  // Never turn so far off the plan that the next cycle would turn back
  // (rotate-to-path), or the two would take turns.
  const double off_path = PathHeadingError(candidate_.end(), costmap);
  if (pass == 0 && options_.rotate_to_path_angle < kPi && std::isfinite(off_path) &&
      std::fabs(off_path) > options_.rotate_to_path_angle) {
    if (!choice->found) ++stats_.rotations_refused;
    return;
  }
  const double ahead =
      goal_critic_.DistanceAhead(candidate_.end(), options_.heading_lookahead);
  // In the second (stuck) pass any turn clear of lethal cells will do:
  // turning is the only way out when both ways ahead are blocked.
  if (pass == 0 && !(ahead < ahead_now)) {
    if (!choice->found) ++stats_.rotations_refused;
  } else if (ahead < *heading_dist) {
    Take(choice);
    *heading_dist = ahead;
  }
}

// Nothing legal.  A robot whose footprint already touches the inscribed band
// (or is escaping) backs up slowly, TrajectoryPlanner's escape, if that keeps
// it off lethal cells.  A robot that is clear but cannot go on is blocked, not
// stuck: backing up would only make it dither in front of the obstacle (or
// wander off along it), so the caller gets a ControlError (recovery,
// replanning).
Twist2 DwaPlanner::EscapeOrFail(const Pose2& pose, const Twist2& velocity,
                                const Costmap2D& costmap) {
  const int here = FootprintCost(costmap, footprint_, pose);
  // Stuck: the footprint is in the band already, or at its edge so that
  // every trajectory enters it at once (a collision after ~0 m of travel).
  const bool stuck = here < 0 || here >= kInscribedInflatedObstacle ||
                     obstacle_critic_.nearest_collision_distance() < 0.01;
  std::string escape_note;
  if (options_.escape_vel >= 0.0) {
    escape_note = "escaping is disabled (escape_vel = 0)";
  } else if (!stuck && !escaping_) {
    escape_note = "the footprint is clear of the inscribed band (cost " +
                  std::to_string(here) +
                  "), so the way ahead is blocked rather than the robot stuck: "
                  "not backing up";
  } else {
    Twist2 cmd;
    cmd.vx = options_.escape_vel;
    generator_.Generate(pose, velocity, cmd, TrajectoryKind::kEscape,
                        &candidate_);
    ++stats_.evaluated;
    candidate_.cost = obstacle_critic_.Score(candidate_);
    if (candidate_.cost >= 0.0 && moving_critic_.Score(candidate_) < 0.0) {
      // Backing up would meet a moving obstacle: stand and let it pass.
      ++stats_.rejected[4];
      GenerateBraking(pose, velocity, &best_);
      stats_.mode = Mode::kYield;
      return best_.command;
    }
    if (candidate_.cost >= 0.0) {
      std::swap(best_, candidate_);
      if (!escaping_) {
        escaping_ = true;
        escape_pose_ = pose;
      }
      for (TrajectoryCritic* c : critics_) c->Debrief(best_);
      stats_.mode = Mode::kEscape;
      return best_.command;
    }
    ++stats_.rejected[3];
    escape_note = "backing up at escape_vel " + Fixed(options_.escape_vel) +
                  " m/s collides too";
  }
  throw ControlError(Diagnose(pose, costmap) + "; " + escape_note);
}

std::string DwaPlanner::NearestObstacle(const Pose2& pose,
                                        const Costmap2D& costmap) const {
  std::ostringstream os;
  // Nearest lethal cell to the footprint, and where it is.
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  int mx0, my0, mx1, my1;
  costmap.WorldToMapNoBounds(pose.x - kDiagnoseRadius, pose.y - kDiagnoseRadius,
                             &mx0, &my0);
  costmap.WorldToMapNoBounds(pose.x + kDiagnoseRadius, pose.y + kDiagnoseRadius,
                             &mx1, &my1);
  mx0 = std::max(mx0, 0);
  my0 = std::max(my0, 0);
  mx1 = std::min(mx1, costmap.size_x() - 1);
  my1 = std::min(my1, costmap.size_y() - 1);
  double nearest = kInf, bx = 0.0, by = 0.0;
  for (int my = my0; my <= my1; ++my) {
    for (int mx = mx0; mx <= mx1; ++mx) {
      if (costmap.cost(mx, my) != kLethalObstacle) continue;
      double wx, wy;
      costmap.MapToWorld(mx, my, &wx, &wy);
      const double dx = wx - pose.x, dy = wy - pose.y;
      const double rx = c * dx + s * dy, ry = -s * dx + c * dy;
      const double d = FootprintDistance(footprint_, rx, ry);
      if (d < nearest) {
        nearest = d;
        bx = rx;
        by = ry;
      }
    }
  }
  if (std::isfinite(nearest)) {
    // Cell centre to cell edge.
    nearest = std::max(0.0, nearest - 0.5 * costmap.resolution());
    const double bearing = std::atan2(by, bx) * 180.0 / kPi;
    const char* where = std::fabs(bearing) <= 45.0    ? "ahead"
                        : std::fabs(bearing) >= 135.0 ? "behind"
                        : bearing > 0.0               ? "to the left"
                                                      : "to the right";
    os << "nearest obstacle " << Fixed(nearest) << " m " << where
       << " of the footprint (bearing " << Fixed(bearing, 0) << " deg)";
  } else {
    os << "no obstacle within " << Fixed(kDiagnoseRadius, 1)
       << " m (unknown space or the costmap edge blocks the rollouts?)";
  }
  return os.str();
}

std::string DwaPlanner::Diagnose(const Pose2& pose,
                                 const Costmap2D& costmap) const {
  std::ostringstream os;
  const int total = stats_.evaluated;
  const int collide = stats_.rejected[3];
  const int unhelpful = stats_.rotations_refused;
  os << "DWA local planner: no admissible command, all " << total
     << " trajectories rejected";
  if (collide == total) {
    os << " because they collide or cannot stop in time";
  } else if (collide + unhelpful == total) {
    os << " because they collide or cannot stop in time, except " << unhelpful
       << " in-place rotations that would not turn it towards the local goal "
          "(or turn it off the plan, or past a full circle on the spot)";
  } else {
    os << " (" << collide << " collide or cannot stop in time";
    if (unhelpful > 0) {
      os << ", " << unhelpful
         << " in-place rotations would not turn it towards the local goal";
    }
    if (stats_.rejected[1] > 0) {
      os << ", " << stats_.rejected[1]
         << " enter cells with no way to the plan";
    }
    if (stats_.rejected[2] > 0) {
      os << ", " << stats_.rejected[2]
         << " enter cells with no way to the local goal";
    }
    if (stats_.rejected[4] > 0) {
      os << ", " << stats_.rejected[4]
         << " come within " << Fixed(options_.moving_obstacle_margin)
         << " m of a moving obstacle's predicted position";
    }
    if (stats_.rejected[0] > 0) {
      os << ", " << stats_.rejected[0]
         << " would flip direction again before moving "
         << Fixed(options_.oscillation_reset_dist) << " m (oscillation)";
    }
    os << ")";
  }
  if (std::isfinite(obstacle_critic_.nearest_collision_distance())) {
    os << "; first collision after "
       << Fixed(obstacle_critic_.nearest_collision_distance()) << " m of travel";
  }
  os << "; " << NearestObstacle(pose, costmap);
  return os.str();
}

Twist2 DwaPlanner::ComputeVelocity(const Pose2& pose, const Twist2& velocity,
                                    const Path& plan,
                                    const Costmap2D& costmap) {
  yield_cycles_ = stats_.mode == Mode::kYield ? yield_cycles_ + 1 : 0;
  stats_ = CycleStats();
  best_.Clear();
  yielded_ = false;
  CheckInputs(pose, velocity, plan, costmap);
  // The moving obstacles' critic scores turns on the spot too (RotateTowards).
  moving_critic_.Prepare(pose, velocity, plan, costmap);
  moving_critic_.set_backing_out(yield_cycles_ * generator_.sim_period() >=
                                 options_.moving_obstacle_wait - 1e-9);
  // Rotation accumulated since the robot last moved oscillation_reset_dist.
  if (std::hypot(pose.x - spin_anchor_.x, pose.y - spin_anchor_.y) >
      options_.oscillation_reset_dist) {
    spin_anchor_ = pose;
    spun_in_place_ = 0.0;
  } else {
    spun_in_place_ += std::fabs(AngleDiff(pose.yaw, last_yaw_));
  }
  last_yaw_ = pose.yaw;
  PrunePlan(pose, plan, costmap);

  const Pose2& goal = plan.back();
  if (latched_ && !SameGoal(goal, latched_goal_)) latched_ = false;
  if (latched_ ||
      std::hypot(goal.x - pose.x, goal.y - pose.y) <= options_.xy_goal_tolerance) {
    if (options_.latch_xy_goal_tolerance) {
      latched_ = true;
      latched_goal_ = goal;
    }
    rotating_to_path_ = false;
    const double yaw_error = AngleDiff(goal.yaw, pose.yaw);
    if (std::fabs(yaw_error) <= options_.yaw_goal_tolerance) {
      rotating_to_goal_ = false;
      stats_.mode = Mode::kAtGoal;
      return Twist2();
    }
    // The failure's words, built only on failure.
    auto cannot_turn = [&]() {
      return "DWA local planner: cannot rotate in place to the goal yaw " +
             Fixed(goal.yaw * 180.0 / kPi, 1) + " deg (now " + Fixed(pose.yaw * 180.0 / kPi, 1) +
             " deg): turning, the footprint would touch an obstacle (" +
             NearestObstacle(pose, costmap);
    };
    // Where the robot reached the tolerance it may not be able to turn; the
    // goal itself may leave room: go on towards it until the turn is clear.
    if (!rotating_to_goal_ &&
        std::hypot(goal.x - pose.x, goal.y - pose.y) > costmap.resolution() &&
        !TurnIsClear(pose, goal.yaw, costmap)) {
      try {
        const Twist2 cmd = FollowPath(pose, velocity, costmap);
        stats_.mode = Mode::kApproachGoal;
        return cmd;
      } catch (const ControlError& e) {
        throw ControlError(cannot_turn() + ") and it cannot go on towards the goal: " + e.what());
      }
    }
    if (!rotating_to_goal_ && !Stopped(velocity)) {
      return Brake(pose, velocity, Mode::kStopAtGoal, costmap);
    }
    rotating_to_goal_ = true;
    stats_.mode = Mode::kRotateToGoal;
    Twist2 cmd;
    if (!RotateTowards(pose, velocity, goal.yaw, options_.yaw_goal_tolerance,
                       costmap, &cmd)) {
      throw ControlError(cannot_turn() + "); the goal is too close to obstacles to turn there");
    }
    if (yielded_) stats_.mode = Mode::kYield;
    return cmd;
  }
  rotating_to_goal_ = false;

  if (options_.rotate_to_path_angle < kPi) {
    const double error = PathHeadingError(pose, costmap);
    // A robot at creeping speed or stopped turns on the spot already at a
    // quarter of the angle: from there its dynamic window only reaches arcs
    // too wide for the turn, every forward arc ends off the plan and the
    // slowest ends nearest to it, so it would crawl along at min_vel_x
    // instead.  Turns until within an eighth of the angle.
    const bool slow = std::fabs(velocity.vx) <= CreepSpeed() + 1e-6;
    const double threshold =
        rotating_to_path_ ? 0.125 * options_.rotate_to_path_angle
        : slow            ? 0.25 * options_.rotate_to_path_angle
                          : options_.rotate_to_path_angle;
    if (std::isfinite(error) && std::fabs(error) > threshold) {
      rotating_to_path_ = true;
      if (std::fabs(velocity.vx) > options_.trans_stopped_vel) {
        return Brake(pose, velocity, Mode::kRotateToPath, costmap);
      }
      Twist2 cmd;
      if (RotateTowards(pose, velocity, pose.yaw + error,
                        0.125 * options_.rotate_to_path_angle, costmap, &cmd)) {
        stats_.mode = yielded_ ? Mode::kYield : Mode::kRotateToPath;
        return cmd;
      }
      // Turning on the spot collides here: let the sampled trajectories
      // find a way.
      stats_ = CycleStats();
    } else {
      rotating_to_path_ = false;
    }
  }
  return FollowPath(pose, velocity, costmap);
}

bool DwaPlanner::IsGoalReached(const Pose2& pose, const Twist2& velocity,
                               const Path& plan) {
  if (plan.empty()) return false;
  const Pose2& goal = plan.back();
  const bool xy_ok =
      std::hypot(goal.x - pose.x, goal.y - pose.y) <=
          options_.xy_goal_tolerance ||
      (latched_ && options_.latch_xy_goal_tolerance &&
       SameGoal(goal, latched_goal_));
  return xy_ok &&
         std::fabs(AngleDiff(goal.yaw, pose.yaw)) <=
             options_.yaw_goal_tolerance &&
         Stopped(velocity);
}

}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation
