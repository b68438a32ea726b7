#include "minibot3d_navigation/move_base/move_base_options.h"

#include <cmath>

#include "minibot3d_common/options.h"

namespace options = minibot3d_common::options;

namespace minibot3d_navigation {
namespace nav {
namespace {

using options::Field;
using options::Num;
using O = MoveBaseOptions;

bool Finite(double v) { return std::isfinite(v); }

}  // namespace

const options::OptionTable<MoveBaseOptions>& MoveBaseOptionTable() {
  static const options::OptionTable<O> table(
      "move_base",
      {Field("base_global_planner", &O::base_global_planner,
             "Global planner: navfn/NavfnROS, global_planner/GlobalPlanner or astar (all "
             "minibot3d's A*), or ompl; its keys are read from ~NavfnROS/, ~GlobalPlanner/ and "
             "~OmplPlanner/."),
       Field("base_local_planner", &O::base_local_planner,
             "Local planner: base_local_planner/TrajectoryPlannerROS (keys in "
             "~TrajectoryPlannerROS/) or dwa_local_planner/DWAPlannerROS (keys in "
             "~DWAPlannerROS/); both run minibot3d's DWA."),
       Field("planner_frequency", &O::planner_frequency,
             "Rate (Hz) of replanning while following a plan; 0: plan once per goal, and again "
             "only when control fails."),
       Field("controller_frequency", &O::controller_frequency,
             "Rate (Hz) of the control loop (sim time): costmap updates, planning and velocity "
             "commands."),
       Field("planner_patience", &O::planner_patience,
             "Time (s) without a valid plan before the recovery behaviours run."),
       Field("controller_patience", &O::controller_patience,
             "Time (s) without a valid velocity command before the recovery behaviours run."),
       Field("max_planning_retries", &O::max_planning_retries,
             "Failed planning attempts before the recovery behaviours run; -1: only "
             "planner_patience counts."),
       Field("oscillation_timeout", &O::oscillation_timeout,
             "Time (s) the robot may take to move oscillation_distance before the recovery "
             "behaviours run; 0: no limit."),
       Field("oscillation_distance", &O::oscillation_distance,
             "Distance (m) the robot must move within oscillation_timeout not to count as "
             "oscillating."),
       Field("recovery_behavior_enabled", &O::recovery_behavior_enabled,
             "Run the recovery behaviours; false: a failure aborts the goal."),
       Field("clearing_rotation_allowed", &O::clearing_rotation_allowed,
             "The default recovery list includes the rotations on the spot (rotate_recovery)."),
       Field("conservative_reset_dist", &O::conservative_reset_dist,
             "Side (m) of the square round the robot that conservative_reset keeps while it "
             "clears the rest of the costmaps' obstacles."),
       Field("shutdown_costmaps", &O::shutdown_costmaps,
             "Accepted and not used: the costmaps always run."),
       Field("recovery_behaviors", &O::recovery_behaviors,
             "Recovery behaviours in order, by name (wait, back_out, conservative_reset, "
             "rotate_recovery, aggressive_reset; a {name, type} list as in move_base); empty: "
             "move_base's list, after back_out if back_out_distance > 0 and, first of all, wait "
             "if wait_duration > 0."),
       Field("back_out_distance", &O::back_out_distance,
             "Distance (m) the back_out recovery reverses along the way the robot came when "
             "the way ahead is blocked; 0: no back_out in the default list."),
       Field("back_out_vel", &O::back_out_vel, "Speed (m/s) of the back_out recovery."),
       Field("blocked_radius", &O::blocked_radius,
             "When control fails or the robot oscillates, a disc of this radius (m) round the "
             "plan point blocked_lookahead ahead is kept out of later plans for the goal; 0: "
             "off."),
       Field("blocked_lookahead", &O::blocked_lookahead,
             "Distance (m) along the plan ahead of the robot of the centre of a blocked disc."),
       Field("recovery_reset_distance", &O::recovery_reset_distance,
             "The recovery list starts again from its first behaviour once the robot is this far "
             "(m) from where the last recovery began; 0: never within a goal."),
       Field("wait_duration", &O::wait_duration,
             "Longest time (s) the wait recovery stands when the planner finds no path between "
             "a free start and a free goal (someone stands in the only doorway): it backs off "
             "until nothing is within 0.45 m in front of it, then checks twice a second whether "
             "a way the robot fits through at any heading exists again, and ends as soon as one "
             "does (the robot replans). While replanning finds no path the old plan is followed "
             "only to 0.45 m short of what shut the way. 0: neither; no wait in the default "
             "list.")});
  return table;
}

void ValidateMoveBaseOptions(const MoveBaseOptions& o) {
  options::Problems p("move_base");
  p.Require(Finite(o.planner_frequency) && o.planner_frequency >= 0.0,
            "planner_frequency=" + Num(o.planner_frequency) + " must be >= 0");
  p.Require(Finite(o.controller_frequency) && o.controller_frequency > 0.0,
            "controller_frequency=" + Num(o.controller_frequency) + " must be > 0");
  p.Require(Finite(o.planner_patience) && o.planner_patience >= 0.0,
            "planner_patience=" + Num(o.planner_patience) + " must be >= 0");
  p.Require(Finite(o.controller_patience) && o.controller_patience >= 0.0,
            "controller_patience=" + Num(o.controller_patience) + " must be >= 0");
  p.Require(o.max_planning_retries >= -1,
            "max_planning_retries=" + std::to_string(o.max_planning_retries) +
                " must be -1 (unlimited) or >= 0");
  p.Require(Finite(o.oscillation_timeout) && o.oscillation_timeout >= 0.0,
            "oscillation_timeout=" + Num(o.oscillation_timeout) + " must be >= 0 (0 = off)");
  p.Require(Finite(o.oscillation_distance) && o.oscillation_distance > 0.0,
            "oscillation_distance=" + Num(o.oscillation_distance) + " must be > 0");
  p.Require(Finite(o.conservative_reset_dist) && o.conservative_reset_dist >= 0.0,
            "conservative_reset_dist=" + Num(o.conservative_reset_dist) + " must be >= 0");
  for (const std::string& r : o.recovery_behaviors) {
    p.Require(r == "wait" || r == "back_out" || r == "conservative_reset" ||
                  r == "rotate_recovery" || r == "aggressive_reset",
              "recovery_behaviors entry '" + r +
                  "' is not one of wait, back_out, conservative_reset, rotate_recovery, "
                  "aggressive_reset");
  }
  p.Require(Finite(o.back_out_distance) && o.back_out_distance >= 0.0 &&
                o.back_out_distance <= 5.0,
            "back_out_distance=" + Num(o.back_out_distance) + " must be in [0, 5] m (0 = off)");
  p.Require(Finite(o.back_out_vel) && o.back_out_vel > 0.0 && o.back_out_vel <= 1.0,
            "back_out_vel=" + Num(o.back_out_vel) + " must be in (0, 1] m/s");
  p.Require(Finite(o.blocked_radius) && o.blocked_radius >= 0.0 && o.blocked_radius <= 2.0,
            "blocked_radius=" + Num(o.blocked_radius) + " must be in [0, 2] m (0 = off)");
  p.Require(Finite(o.blocked_lookahead) && o.blocked_lookahead >= 0.0 &&
                o.blocked_lookahead <= 3.0,
            "blocked_lookahead=" + Num(o.blocked_lookahead) + " must be in [0, 3] m");
  p.Require(Finite(o.recovery_reset_distance) && o.recovery_reset_distance >= 0.0,
            "recovery_reset_distance=" + Num(o.recovery_reset_distance) +
                " must be >= 0 (0 = never restart the list)");
  p.Require(Finite(o.wait_duration) && o.wait_duration >= 0.0 && o.wait_duration <= 3600.0,
            "wait_duration=" + Num(o.wait_duration) + " must be in [0, 3600] s (0 = off)");
  for (const std::string& r : o.recovery_behaviors) {
    p.Require(r != "wait" || o.wait_duration > 0.0,
              "recovery_behaviors lists wait but wait_duration=" + Num(o.wait_duration) +
                  ": set wait_duration > 0 (s) for it to wait at all");
  }
  p.ThrowIfAny();
}

void SetMoveBaseOption(const std::string& name, const std::string& text, MoveBaseOptions* o) {
  MoveBaseOptionTable().Set(name, text, o);
}
bool IsMoveBaseOptionName(const std::string& name) { return MoveBaseOptionTable().Has(name); }
std::vector<std::string> MoveBaseOptionNames() { return MoveBaseOptionTable().Names(); }

}  // namespace nav
}  // namespace minibot3d_navigation
