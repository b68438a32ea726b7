// Parameters of the explore node's loop (frames, rates, when a goal is given up or replaced),
// with explore_lite's names where explore_lite has the parameter.  The frontier search's own
// parameters are ExploreOptions (frontier_search.h); both live in the node's private namespace.
#ifndef MINIBOT3D_NAVIGATION_EXPLORE_EXPLORE_NODE_OPTIONS_H_
#define MINIBOT3D_NAVIGATION_EXPLORE_EXPLORE_NODE_OPTIONS_H_

#include <string>

#include "minibot3d_common/options.h"

namespace minibot3d_navigation {
namespace nav {

struct ExploreNodeOptions {
  std::string global_frame = "map";  // the map's frame, in which goals are sent
  std::string robot_base_frame = "base_link";
  double planner_frequency = 0.5;  // Hz (sim time) of the frontier search
  // s without getting 0.1 m closer to the goal or moving 0.5 m before it is cancelled (3x that
  // without getting closer, moving or not).
  double progress_timeout = 20.0;
  // m: a frontier replaces the current goal only when it is this much nearer.
  double switch_margin = 1.0;
};

const minibot3d_common::options::OptionTable<ExploreNodeOptions>& ExploreNodeOptionTable();

// Throws std::invalid_argument naming every bad value.
void ValidateExploreNodeOptions(const ExploreNodeOptions& options);

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_EXPLORE_EXPLORE_NODE_OPTIONS_H_
