// The cost terms of the dynamic-window local planner (trajectory_critic.h),
// after base_local_planner's TrajectoryPlanner scoring:
//   cost = path_distance_bias * path_dist + goal_distance_bias * goal_dist
//          + occdist_scale * occ_cost
// plus the legality checks that make a trajectory illegal outright.
//
//  PathDistCritic      path_dist: MapGrid distance (cells) from the rollout's
//                      end cell to the nearest plan cell; illegal if any
//                      rollout cell cannot reach the plan.
//  GoalDistCritic      goal_dist: MapGrid distance from the rollout's end to
//                      the local goal (MapGrid::FindLocalGoal); illegal if any
//                      rollout cell cannot reach it.
//  ObstacleCostCritic  occ_cost: the worst FootprintCost along the rollout.
//                      Within the inscribed band the costmap is flat (253),
//                      so there the score goes on rising, below 254, as the
//                      outline nears a lethal cell (a distance transform of
//                      the lethal cells): of two rollouts in the band the
//                      one keeping further from the wall is cheaper.
//                      Illegal if any pose after the start, on the rollout or
//                      on its braking tail (trajectory.h), is off the map or
//                      its outline touches a lethal (254) or unknown cell, as
//                      base_local_planner's CostmapModel decides.  The
//                      inscribed band (253: the outline within one inscribed
//                      radius of an obstacle) is a cost, not a wall, with a
//                      margin that grows with speed: with v the larger of
//                      the rollout's |command vx| and |start vx|, a rollout
//                      whose outline enters it must keep the outline at
//                      least band * (v - tight_speed) /
//                      (full_margin_speed - tight_speed) from the nearest
//                      lethal cell (band: the band's width), so at
//                      v <= tight_speed (turns on the spot of a robot at
//                      most creeping) only lethal cells count, and from
//                      full_margin_speed (min(full_margin_vel, max_vel_x))
//                      on the whole band is kept; if that is not above
//                      tight_speed, the whole band above tight_speed.  The
//                      robot slows down as far as the room it has asks,
//                      rather than to creeping
//                      speed as soon as a gap is narrower than the robot plus
//                      two inscribed radii, and keeps its whole margin at
//                      full speed, where slip and a late costmap matter
//                      most.  A robot already within a cell of a lethal cell
//                      (localization error) may touch lethal cells on poses
//                      within a quarter cell of its distance d to them, but
//                      never nearer than min(a quarter cell, d / 2), its
//                      centre ending no closer: it can edge away or slide
//                      along, not turn or creep into the wall.
//  OscillationCritic   TrajectoryPlanner's oscillation flags: after an
//                      in-place rotation one way and then the other, the
//                      first direction is forbidden; after switching between
//                      forward and backward, the previous direction is
//                      forbidden; both until the robot has moved
//                      oscillation_reset_dist.  Scores 0 or illegal.
#ifndef MINIBOT3D_NAVIGATION_DWA_CRITICS_H_
#define MINIBOT3D_NAVIGATION_DWA_CRITICS_H_

#include <limits>
#include <string>
#include <vector>

#include "minibot3d_navigation/costmap/footprint.h"
#include "minibot3d_navigation/dwa/map_grid.h"
#include "minibot3d_navigation/dwa/trajectory_critic.h"

namespace minibot3d_navigation {
namespace nav {
namespace dwa {

// Indices of the costmap cells covered by `footprint` at `pose` (interior,
// outline and centre), for MapGrid's robot cells.
void FootprintCells(const Costmap2D& costmap, const Footprint& footprint,
                    const Pose2& pose, std::vector<int>* cells);

class PathDistCritic : public TrajectoryCritic {
 public:
  explicit PathDistCritic(const Footprint& footprint)
      : footprint_(footprint) {}
  std::string name() const override { return "PathDist"; }
  bool Prepare(const Pose2& pose, const Twist2& velocity, const Path& plan,
               const Costmap2D& costmap) override;
  double Score(const Trajectory& traj) override;
  const MapGrid& grid() const { return grid_; }

 private:
  Footprint footprint_;
  MapGrid grid_;
  std::vector<int> robot_cells_;
  const Costmap2D* costmap_ = nullptr;
};

class GoalDistCritic : public TrajectoryCritic {
 public:
  explicit GoalDistCritic(const Footprint& footprint)
      : footprint_(footprint) {}
  std::string name() const override { return "GoalDist"; }
  bool Prepare(const Pose2& pose, const Twist2& velocity, const Path& plan,
               const Costmap2D& costmap) override;
  double Score(const Trajectory& traj) override;
  const MapGrid& grid() const { return grid_; }
  // The local goal cell's centre (valid after a successful Prepare).
  Point2 local_goal() const { return local_goal_; }
  // Goal distance (cells) of the point `lookahead` metres in front of
  // `pose`; impossible_distance() if off the map.
  double DistanceAhead(const Pose2& pose, double lookahead) const;

 private:
  Footprint footprint_;
  MapGrid grid_;
  std::vector<int> robot_cells_;
  const Costmap2D* costmap_ = nullptr;
  Point2 local_goal_;
};

class ObstacleCostCritic : public TrajectoryCritic {
 public:
  explicit ObstacleCostCritic(const Footprint& footprint)
      : footprint_(footprint) {}
  std::string name() const override { return "ObstacleCost"; }
  bool Prepare(const Pose2& pose, const Twist2& velocity, const Path& plan,
               const Costmap2D& costmap) override;
  double Score(const Trajectory& traj) override;
  // Prepare without a plan (for checking a single command).
  void SetCostmap(const Costmap2D& costmap);
  // Smallest distance travelled before a collision over the trajectories
  // rejected since Prepare (infinity if none).
  double nearest_collision_distance() const { return nearest_collision_; }
  // false (default): inside the inscribed band (253) the outline keeps the
  // speed's margin (RequiredClearance); true: only lethal cells (254)
  // collide, at any speed.
  void set_lethal_only(bool lethal_only) { lethal_only_ = lethal_only; }
  // The fastest |vx| at which the outline may come as near a lethal cell as
  // it likes (creeping), and the |vx| from which it keeps the whole inscribed
  // band; in between the margin grows linearly.
  void set_tight_speed(double tight_speed) { tight_speed_ = tight_speed; }
  void set_full_margin_speed(double speed) { full_margin_speed_ = speed; }
  // The clearance (m) the outline must keep from lethal cells at |vx| = speed
  // (0 up to tight_speed, the band's width from full_margin_speed); the band
  // width comes from the last Prepare/SetCostmap.
  double RequiredClearance(double speed) const;

 private:
  // Worst cost, or -1 with *collision_distance set (if non-null); in
  // *band_depth (0..1) how far into the inscribed band the outline gets.
  int Check(const Trajectory& traj, double* collision_distance, double* band_depth) const;
  // Smallest distance (m) from the outline at `pose` to a lethal cell.
  double Clearance(const Pose2& pose) const;
  // Distance (m) from the footprint polygon at `pose` (or, with `centre`,
  // from the pose's centre) to the nearest lethal cell centre within reach of
  // the footprint (negative inside the polygon; infinity if none).
  double ContinuousClearance(const Pose2& pose, bool centre) const;
  // ContinuousClearance of the rollouts' common start pose, remembered until
  // the pose or the costmap changes.
  double StartClearance(const Pose2& start) const;

  Footprint footprint_;
  const Costmap2D* costmap_ = nullptr;
  double nearest_collision_ = 0.0;
  bool lethal_only_ = false;
  double tight_speed_ = 0.0;
  double full_margin_speed_ = 0.0;
  // Distance (m, cell centres, 8-neighbour chamfer) from each cell to the
  // nearest lethal cell, and the inscribed band's width: the largest such
  // distance among cells of cost 253.
  std::vector<float> lethal_distance_;
  double band_width_ = 0.0;
  mutable std::vector<std::pair<int, int>> outline_;
  mutable Pose2 start_pose_;
  mutable double start_clearance_ = 0.0;
  mutable bool start_clearance_valid_ = false;
};

class OscillationCritic : public TrajectoryCritic {
 public:
  explicit OscillationCritic(double oscillation_reset_dist)
      : reset_dist_(oscillation_reset_dist) {}
  std::string name() const override { return "Oscillation"; }
  bool Prepare(const Pose2& pose, const Twist2& velocity, const Path& plan,
               const Costmap2D& costmap) override;
  double Score(const Trajectory& traj) override;
  void Debrief(const Trajectory& chosen) override;
  void Reset() override;

  bool forbid_positive_rotation() const { return forbid_pos_rot_; }
  bool forbid_negative_rotation() const { return forbid_neg_rot_; }
  bool forbid_forward() const { return forbid_forward_; }
  bool forbid_backward() const { return forbid_backward_; }

 private:
  double reset_dist_;
  Pose2 pose_;
  // In-place rotation memory (TrajectoryPlanner's rotating_*/stuck_*).
  bool rotated_pos_ = false, rotated_neg_ = false;
  bool forbid_pos_rot_ = false, forbid_neg_rot_ = false;
  Pose2 rotation_anchor_;
  // Direction memory: sign of the last non-zero vx commanded.
  int last_direction_ = 0;
  bool forbid_forward_ = false, forbid_backward_ = false;
  Pose2 direction_anchor_;
};

}  // namespace dwa
}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_DWA_CRITICS_H_
