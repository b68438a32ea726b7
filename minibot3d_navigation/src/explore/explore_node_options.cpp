#include "minibot3d_navigation/explore/explore_node_options.h"

namespace options = minibot3d_common::options;

namespace minibot3d_navigation {
namespace nav {

const options::OptionTable<ExploreNodeOptions>& ExploreNodeOptionTable() {
  using options::Field;
  using N = ExploreNodeOptions;
  static const options::OptionTable<N> table(
      "explore",
      {Field("global_frame", &N::global_frame,
             "Frame of the map (SLAM's map frame); goals are sent to move_base in it."),
       Field("robot_base_frame", &N::robot_base_frame, "The robot's base frame (explore_lite)."),
       Field("planner_frequency", &N::planner_frequency,
             "Rate (Hz, sim time) at which frontiers are searched and a goal is chosen "
             "(explore_lite)."),
       Field("progress_timeout", &N::progress_timeout,
             "Time (s) the robot may neither get 0.1 m closer to its goal nor move 0.5 m before "
             "the goal is cancelled and counted as failed (explore_lite); moving, it may go three "
             "times as long without getting closer."),
       Field("switch_margin", &N::switch_margin,
             "A frontier replaces the current goal only when its path is this much (m) shorter "
             "than the straight line to the current goal.")});
  return table;
}

void ValidateExploreNodeOptions(const ExploreNodeOptions& o) {
  options::Problems p("explore");
  p.Require(!options::Trim(o.global_frame).empty(), "global_frame must not be empty");
  p.Require(!options::Trim(o.robot_base_frame).empty(), "robot_base_frame must not be empty");
  p.Positive("planner_frequency", o.planner_frequency);
  p.Positive("progress_timeout", o.progress_timeout);
  p.Finite("switch_margin", o.switch_margin);
  p.ThrowIfAny();
}

}  // namespace nav
}  // namespace minibot3d_navigation
