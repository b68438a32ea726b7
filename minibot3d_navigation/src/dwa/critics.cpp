#include "minibot3d_navigation/dwa/critics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace minibot3d_navigation {
namespace nav {
namespace dwa {
namespace {

std::string Xy(double x, double y) {
  std::ostringstream os;
  os.precision(3);
  os << std::fixed << "(" << x << ", " << y << ")";
  return os.str();
}

// Why the critics have no target: no plan pose lies on the known local costmap.
std::string PlanOffCostmap(const Path& plan, const Pose2& pose) {
  return "none of the " + std::to_string(plan.size()) +
         " plan poses is on the known part of the local costmap (first pose " +
         Xy(plan.front().x, plan.front().y) + ", robot at " + Xy(pose.x, pose.y) + ")";
}

// Why the robot cannot get to `what` (the plan, the local goal).
std::string Unreachable(const std::string& what, const Pose2& pose) {
  return what + " cannot be reached from the robot at " + Xy(pose.x, pose.y) +
         " on the local costmap: lethal, inscribed or unknown cells separate them";
}

// Length of the polyline poses[0..index].
double ArcLength(const std::vector<Pose2>& poses, size_t index) {
  double len = 0.0;
  for (size_t i = 1; i <= index && i < poses.size(); ++i) {
    len += std::hypot(poses[i].x - poses[i - 1].x, poses[i].y - poses[i - 1].y);
  }
  return len;
}

// Distance (cells) of the rollout's end, or -1 if a rollout cell is off the
// map or cannot reach the grid's targets.
double ScoreOnGrid(const MapGrid& grid, const Costmap2D& costmap,
                   const Trajectory& traj) {
  const float impossible = grid.impossible_distance();
  float d = 0.0f;
  for (const Pose2& p : traj.poses) {
    int mx, my;
    if (!costmap.WorldToMap(p.x, p.y, &mx, &my)) return -1.0;
    d = grid.distance(mx, my);
    if (d >= impossible) return -1.0;
  }
  return d;
}

}  // namespace

void FootprintCells(const Costmap2D& costmap, const Footprint& footprint,
                    const Pose2& pose, std::vector<int>* cells) {
  cells->clear();
  const Footprint poly = TransformFootprint(footprint, pose);
  double x0 = pose.x, x1 = pose.x, y0 = pose.y, y1 = pose.y;
  for (const Point2& p : poly) {
    x0 = std::min(x0, p.x);
    x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y);
    y1 = std::max(y1, p.y);
  }
  int mx0, my0, mx1, my1;
  costmap.WorldToMapNoBounds(x0, y0, &mx0, &my0);
  costmap.WorldToMapNoBounds(x1, y1, &mx1, &my1);
  mx0 = std::max(mx0, 0);
  my0 = std::max(my0, 0);
  mx1 = std::min(mx1, costmap.size_x() - 1);
  my1 = std::min(my1, costmap.size_y() - 1);
  for (int my = my0; my <= my1; ++my) {
    for (int mx = mx0; mx <= mx1; ++mx) {
      double wx, wy;
      costmap.MapToWorld(mx, my, &wx, &wy);
      if (minibot3d_common::PointInPolygon(poly, wx, wy)) cells->push_back(costmap.Index(mx, my));
    }
  }
  std::vector<std::pair<int, int>> outline;
  PolygonOutlineCells(costmap, poly, &outline);
  for (const auto& c : outline) {
    if (costmap.InBounds(c.first, c.second)) {
      cells->push_back(costmap.Index(c.first, c.second));
    }
  }
  int cx, cy;
  if (costmap.WorldToMap(pose.x, pose.y, &cx, &cy)) {
    cells->push_back(costmap.Index(cx, cy));
  }
}

// --- PathDistCritic ---

bool PathDistCritic::Prepare(const Pose2& pose, const Twist2& /*velocity*/,
                             const Path& plan, const Costmap2D& costmap) {
  costmap_ = &costmap;
  failure_.clear();
  FootprintCells(costmap, footprint_, pose, &robot_cells_);
  if (grid_.SetTargetCells(costmap, plan, robot_cells_) == 0) {
    failure_ = PlanOffCostmap(plan, pose);
    return false;
  }
  int mx, my;
  if (costmap.WorldToMap(pose.x, pose.y, &mx, &my) && !grid_.Reachable(mx, my)) {
    failure_ = Unreachable("the plan", pose);
    return false;
  }
  return true;
}

double PathDistCritic::Score(const Trajectory& traj) {
  return ScoreOnGrid(grid_, *costmap_, traj);
}

// --- GoalDistCritic ---

bool GoalDistCritic::Prepare(const Pose2& pose, const Twist2& /*velocity*/,
                             const Path& plan, const Costmap2D& costmap) {
  costmap_ = &costmap;
  failure_.clear();
  int gx, gy, bx, by;
  bool in_obstacle = false;
  if (!MapGrid::FindLocalGoal(costmap, plan, &gx, &gy, &in_obstacle, &bx,
                              &by)) {
    failure_ = PlanOffCostmap(plan, pose);
    return false;
  }
  if (in_obstacle && bx >= 0) {
    gx = bx;
    gy = by;
    in_obstacle = false;
  }
  costmap.MapToWorld(gx, gy, &local_goal_.x, &local_goal_.y);
  if (in_obstacle) {
    failure_ = "the local goal " + Xy(local_goal_.x, local_goal_.y) +
               " is in an obstacle or its inscribed band (cost " +
               std::to_string(costmap.cost(gx, gy)) +
               ") and no free plan point comes before it";
    return false;
  }
  FootprintCells(costmap, footprint_, pose, &robot_cells_);
  grid_.SetTargetCell(costmap, gx, gy, robot_cells_);
  int mx, my;
  const bool on_map = costmap.WorldToMap(pose.x, pose.y, &mx, &my);
  if (on_map && !grid_.Reachable(mx, my) && bx >= 0 && (bx != gx || by != gy)) {
    // The goal lies beyond an obstacle that closes the way: head for the
    // free side of the obstacle instead (and stop there).
    gx = bx;
    gy = by;
    costmap.MapToWorld(gx, gy, &local_goal_.x, &local_goal_.y);
    grid_.SetTargetCell(costmap, gx, gy, robot_cells_);
  }
  if (on_map && !grid_.Reachable(mx, my)) {
    failure_ = Unreachable("the local goal " + Xy(local_goal_.x, local_goal_.y), pose);
    return false;
  }
  return true;
}

double GoalDistCritic::Score(const Trajectory& traj) {
  return ScoreOnGrid(grid_, *costmap_, traj);
}

double GoalDistCritic::DistanceAhead(const Pose2& pose,
                                     double lookahead) const {
  int mx, my;
  if (!costmap_->WorldToMap(pose.x + lookahead * std::cos(pose.yaw),
                            pose.y + lookahead * std::sin(pose.yaw), &mx,
                            &my)) {
    return grid_.impossible_distance();
  }
  return grid_.distance(mx, my);
}

// --- ObstacleCostCritic ---

bool ObstacleCostCritic::Prepare(const Pose2& /*pose*/,
                                 const Twist2& /*velocity*/,
                                 const Path& /*plan*/,
                                 const Costmap2D& costmap) {
  SetCostmap(costmap);
  return true;
}

void ObstacleCostCritic::SetCostmap(const Costmap2D& costmap) {
  costmap_ = &costmap;
  start_clearance_valid_ = false;
  nearest_collision_ = std::numeric_limits<double>::infinity();
  // Two-pass chamfer distance transform (Borgefors 1986) of the lethal cells.
  const int nx = costmap.size_x(), ny = costmap.size_y();
  const float res = static_cast<float>(costmap.resolution());
  const float big = 1e9f, diag = res * static_cast<float>(std::sqrt(2.0));
  lethal_distance_.assign(static_cast<size_t>(nx) * ny, big);
  const uint8_t* cost = costmap.data();
  for (int i = 0; i < nx * ny; ++i) {
    if (cost[i] == kLethalObstacle) lethal_distance_[i] = 0.0f;
  }
  auto relax = [&](int x, int y, int dx, int dy, float step) {
    const int xx = x + dx, yy = y + dy;
    if (xx < 0 || yy < 0 || xx >= nx || yy >= ny) return;
    float& d = lethal_distance_[static_cast<size_t>(y) * nx + x];
    d = std::min(d, lethal_distance_[static_cast<size_t>(yy) * nx + xx] + step);
  };
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      relax(x, y, -1, 0, res);
      relax(x, y, 0, -1, res);
      relax(x, y, -1, -1, diag);
      relax(x, y, 1, -1, diag);
    }
  }
  band_width_ = 0.0;
  for (int y = ny - 1; y >= 0; --y) {
    for (int x = nx - 1; x >= 0; --x) {
      relax(x, y, 1, 0, res);
      relax(x, y, 0, 1, res);
      relax(x, y, 1, 1, diag);
      relax(x, y, -1, 1, diag);
      const size_t i = static_cast<size_t>(y) * nx + x;
      if (cost[i] == kInscribedInflatedObstacle && lethal_distance_[i] < big) {
        band_width_ = std::max(band_width_, static_cast<double>(lethal_distance_[i]));
      }
    }
  }
}

double ObstacleCostCritic::StartClearance(const Pose2& start) const {
  // Every rollout of a cycle starts at the robot's pose: computed once per cycle.
  if (!start_clearance_valid_ || start.x != start_pose_.x || start.y != start_pose_.y ||
      start.yaw != start_pose_.yaw) {
    start_pose_ = start;
    start_clearance_ = ContinuousClearance(start, false);
    start_clearance_valid_ = true;
  }
  return start_clearance_;
}

double ObstacleCostCritic::ContinuousClearance(const Pose2& pose, bool centre) const {
  const Footprint poly = TransformFootprint(footprint_, pose);
  double reach = 0.0;
  for (const Point2& p : footprint_) reach = std::max(reach, std::hypot(p.x, p.y));
  reach += 2.0 * costmap_->resolution();
  int mx0, my0, mx1, my1;
  costmap_->WorldToMapNoBounds(pose.x - reach, pose.y - reach, &mx0, &my0);
  costmap_->WorldToMapNoBounds(pose.x + reach, pose.y + reach, &mx1, &my1);
  mx0 = std::max(mx0, 0);
  my0 = std::max(my0, 0);
  mx1 = std::min(mx1, costmap_->size_x() - 1);
  my1 = std::min(my1, costmap_->size_y() - 1);
  double nearest = std::numeric_limits<double>::infinity();
  for (int my = my0; my <= my1; ++my) {
    for (int mx = mx0; mx <= mx1; ++mx) {
      if (costmap_->cost(mx, my) != kLethalObstacle) continue;
      double wx, wy;
      costmap_->MapToWorld(mx, my, &wx, &wy);
      if (centre) {
        nearest = std::min(nearest, std::hypot(wx - pose.x, wy - pose.y));
        continue;
      }
      double d = std::numeric_limits<double>::infinity();
      for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        d = std::min(d, minibot3d_common::PointSegmentDistance(Point2{wx, wy}, poly[j], poly[i]));
      }
      nearest = std::min(nearest, minibot3d_common::PointInPolygon(poly, wx, wy) ? -d : d);
    }
  }
  return nearest;
}

double ObstacleCostCritic::Clearance(const Pose2& pose) const {
  PolygonOutlineCells(*costmap_, TransformFootprint(footprint_, pose), &outline_);
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& c : outline_) {
    if (!costmap_->InBounds(c.first, c.second)) continue;
    nearest = std::min(nearest, static_cast<double>(
                                    lethal_distance_[costmap_->Index(c.first, c.second)]));
  }
  return nearest;
}

double ObstacleCostCritic::RequiredClearance(double speed) const {
  if (speed <= tight_speed_ + 1e-9) return 0.0;
  if (full_margin_speed_ <= tight_speed_ + 1e-9 || speed >= full_margin_speed_) {
    return band_width_;
  }
  return band_width_ * (speed - tight_speed_) / (full_margin_speed_ - tight_speed_);
}

int ObstacleCostCritic::Check(const Trajectory& traj, double* collision_distance,
                              double* band_depth) const {
  // The outline must not touch a lethal or unknown cell. It may enter the
  // inscribed band (cost 253: within one inscribed radius of an obstacle)
  // keeping a margin that grows with speed: none at creeping speed, the whole
  // band from full_margin_speed on (RequiredClearance).  Through a gap the
  // robot fits through it slows down as far as the gap asks, and at speed
  // it keeps a margin of one inscribed radius for slip and for obstacles the
  // costmap shows late.  An escape (backing out of the band) and turns on the
  // spot only have to avoid lethal cells.
  const double speed = std::max(std::fabs(traj.command.vx), std::fabs(traj.start_vx));
  const double margin =
      traj.kind == TrajectoryKind::kEscape || lethal_only_ ? 0.0 : RequiredClearance(speed);
  const bool whole_band = margin > 0.0 && margin >= band_width_;
  const int limit = whole_band ? kInscribedInflatedObstacle : kLethalObstacle;
  // Inside the band, a pose nearer to a lethal cell than the margin is
  // rejected like a collision.
  auto too_close = [&](int c, const Pose2& pose) {
    return c == kInscribedInflatedObstacle && margin > 0.0 && !whole_band &&
           Clearance(pose) < margin - 1e-6;
  };
  // A robot already within a cell of a lethal cell (a few centimetres of
  // localization error or slip beside a wall it passed at a cell's distance)
  // has every move touch one in the cell grid.  There a pose may touch lethal
  // cells if its outline stays within a quarter cell of the start's distance
  // to their centres (turning away from a wall swings the rear corner towards
  // it first), never nearer than min(a quarter cell, half the start's
  // distance) (a fixed quarter-cell floor froze a robot that was already
  // nearer than that: every first step away was still under the floor), and
  // the rollout must end with its centre no nearer to them than at the start:
  // the robot slides along the wall or edges away, never turns or creeps into
  // it.  (A lethal cell centre inside the outline, a negative distance, still
  // leaves a floor above it: such a robot does not move.)
  const double res = costmap_->resolution();
  const double start_clearance = StartClearance(traj.poses.front());
  const bool near_lethal = start_clearance < res;
  const double floor = std::max(std::min(0.25 * res, 0.5 * start_clearance),
                                start_clearance - 0.25 * res);
  bool relaxed = false;
  auto cost_at = [&](const Pose2& pose) {
    int c = FootprintCost(*costmap_, footprint_, pose);
    if (c == kLethalObstacle && near_lethal && ContinuousClearance(pose, false) >= floor) {
      c = kInscribedInflatedObstacle;
      relaxed = true;
    }
    return c;
  };
  int worst = 0;
  double depth = 0.0;
  // The start pose is where the robot already is: not checked.
  for (size_t i = 1; i < traj.poses.size(); ++i) {
    const int c = cost_at(traj.poses[i]);
    if (c < 0 || c >= limit || too_close(c, traj.poses[i])) {
      if (collision_distance != nullptr) {
        *collision_distance = ArcLength(traj.poses, i);
      }
      return -1;
    }
    worst = std::max(worst, c);
    if (c == kInscribedInflatedObstacle && band_depth != nullptr && band_width_ > 0.0) {
      depth = std::max(depth, std::clamp(1.0 - Clearance(traj.poses[i]) / band_width_, 0.0,
                                         0.99));
    }
  }
  if (relaxed && ContinuousClearance(traj.poses.back(), true) <
                     ContinuousClearance(traj.poses.front(), true) - 1e-4) {
    if (collision_distance != nullptr) {
      *collision_distance = ArcLength(traj.poses, traj.poses.size() - 1);
    }
    return -1;
  }
  if (band_depth != nullptr) *band_depth = depth;
  for (size_t i = 0; i < traj.braking_poses.size(); ++i) {
    const int c = cost_at(traj.braking_poses[i]);
    if (c < 0 || c >= limit || too_close(c, traj.braking_poses[i])) {
      if (collision_distance != nullptr) {
        *collision_distance = traj.braking_start_distance +
                              ArcLength(traj.braking_poses, i);
      }
      return -1;
    }
  }
  return worst;
}

double ObstacleCostCritic::Score(const Trajectory& traj) {
  double distance = 0.0, band = 0.0;
  const int worst = Check(traj, &distance, &band);
  if (worst < 0) {
    nearest_collision_ = std::min(nearest_collision_, distance);
    return -1.0;
  }
  // Within the band every rollout's worst cost is 253: the closest approach
  // to a lethal cell orders them, below 254.
  return worst + band;
}

// --- OscillationCritic ---

bool OscillationCritic::Prepare(const Pose2& pose, const Twist2& /*velocity*/,
                                const Path& /*plan*/,
                                const Costmap2D& /*costmap*/) {
  pose_ = pose;
  if (std::hypot(pose.x - rotation_anchor_.x, pose.y - rotation_anchor_.y) >
      reset_dist_) {
    rotated_pos_ = rotated_neg_ = false;
    forbid_pos_rot_ = forbid_neg_rot_ = false;
  }
  if (std::hypot(pose.x - direction_anchor_.x, pose.y - direction_anchor_.y) >
      reset_dist_) {
    forbid_forward_ = forbid_backward_ = false;
  }
  return true;
}

double OscillationCritic::Score(const Trajectory& traj) {
  if (traj.kind == TrajectoryKind::kStop) return 0.0;
  const Twist2& c = traj.command;
  if (c.vx == 0.0) {
    if (c.wz > 0.0 && forbid_pos_rot_) return -1.0;
    if (c.wz < 0.0 && forbid_neg_rot_) return -1.0;
  }
  if (c.vx > 0.0 && forbid_forward_) return -1.0;
  if (c.vx < 0.0 && forbid_backward_) return -1.0;
  return 0.0;
}

void OscillationCritic::Debrief(const Trajectory& chosen) {
  if (chosen.kind == TrajectoryKind::kStop) return;
  const Twist2& c = chosen.command;
  if (!(c.vx > 0.0)) {
    if (c.wz < 0.0) {
      if (rotated_pos_) forbid_pos_rot_ = true;
      rotated_neg_ = true;
    } else if (c.wz > 0.0) {
      if (rotated_neg_) forbid_neg_rot_ = true;
      rotated_pos_ = true;
    }
    rotation_anchor_ = pose_;
  }
  const int dir = c.vx > 0.0 ? 1 : (c.vx < 0.0 ? -1 : 0);
  if (dir != 0) {
    // Backing out (escape) and then driving forward again is progress, not
    // oscillation: only forbid backing up again until the robot has moved
    // oscillation_reset_dist forwards.  Forbidding forward after an escape
    // could leave no legal command at all once the robot is clear.
    if (last_direction_ < 0 && dir > 0) {
      forbid_backward_ = true;
      direction_anchor_ = pose_;
    }
    last_direction_ = dir;
  }
}

void OscillationCritic::Reset() {
  rotated_pos_ = rotated_neg_ = false;
  forbid_pos_rot_ = forbid_neg_rot_ = false;
  last_direction_ = 0;
  forbid_forward_ = forbid_backward_ = false;
}

}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation
