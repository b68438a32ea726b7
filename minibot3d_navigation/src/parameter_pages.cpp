#include "parameter_pages.h"

#include <string>

#include "minibot3d_navigation/amcl/amcl_options.h"
#include "minibot3d_navigation/costmap/costmap_options.h"
#include "minibot3d_navigation/dwa/dwa_options.h"
#include "minibot3d_navigation/explore/explore_node_options.h"
#include "minibot3d_navigation/explore/frontier_search.h"
#include "minibot3d_navigation/move_base/move_base_options.h"
#include "minibot3d_navigation/planner/planner_options.h"
#include "minibot3d_navigation/tracking/obstacle_tracker.h"
#include "minibot3d_ros/frame_names.h"

namespace minibot3d_navigation {
namespace {

using minibot3d_common::ParameterPage;
using minibot3d_common::ParameterSection;
using minibot3d_common::Section;

// What every node says about the keys of its namespaces.
constexpr char kReported[] =
    "A key no table knows is reported once at start-up; a bad value stops the node with every "
    "offending parameter named.";

ParameterPage AmclPage() {
  return ParameterPage{
      "amcl.md", "amcl",
      "Private parameters of the `amcl` node (`~name`), with ROS amcl's names and defaults where "
      "ROS amcl has the parameter; `config/amcl.yaml` sets the ones the shipped stacks change. " +
          std::string(kReported),
      {Section("Filter, models, confidence and global search",
               "The Monte Carlo localization filter (KLD-sampling, motion and laser models), "
               "what it must see before it claims a pose, and the map-wide search that seeds "
               "global localization.",
               amcl::AmclOptionTable()),
       Section("Node", "Frames, the map source and what the node publishes.",
               amcl::AmclNodeOptionTable()),
       minibot3d_ros::FrameOptionsSection(
           "`base_frame_id`, `odom_frame_id` and `global_frame_id`")}};
}

ParameterPage CostmapPage() {
  return ParameterPage{
      "costmap.md", "costmap",
      "Parameters of move_base's two costmaps, in `~global_costmap/` and `~local_costmap/` of the "
      "`move_base` node, with costmap_2d's names and defaults in its flat (pre-plugin) form. The "
      "shipped stacks load `config/costmap_common_params.yaml` into both namespaces, then "
      "`config/global_costmap_params.yaml` (`config/global_costmap_mapless_params.yaml` in "
      "mapless mode) and `config/local_costmap_params.yaml`. The frames take the robot's "
      "`frame_prefix` ([move_base](move_base.md#robot-frames)). " +
          std::string(kReported),
      {Section("Costmap", "The grid, its frames and rates, the robot's footprint and the layers.",
               nav::CostmapOptionTable()),
       Section("Sensors", "Where the obstacle layer's observations come from.",
               nav::CostmapSensorOptionTable()),
       Section("One observation source",
               "`~<costmap>/<name>/` for each name in observation_sources (`laser_scan_sensor` "
               "in the shipped file); `<name>` below stands for the source's name, and the "
               "ranges default to the costmap's.",
               nav::ObservationSourceOptionTable(),
               nav::DefaultObservationSource("<name>", nav::CostmapOptions()))}};
}

ParameterPage PlannerPage() {
  return ParameterPage{
      "planner.md", "Global planner",
      "Parameters of the global planner, in `~NavfnROS/`, `~GlobalPlanner/` and `~OmplPlanner/` "
      "of the `move_base` node (read in that order, so a later namespace wins), with navfn's and "
      "global_planner's names where they have the parameter; the OMPL planner's own start with "
      "`ompl_`. move_base's `base_global_planner` chooses the planner. "
      "`config/move_base_params.yaml` sets `NavfnROS/default_tolerance` and "
      "`NavfnROS/allow_unknown`. " +
          std::string(kReported),
      {Section("Planner", "", nav::GlobalPlannerOptionTable())}};
}

ParameterPage DwaPage() {
  std::string ignored;
  for (const std::string& name : nav::dwa::DwaIgnoredOptionNames()) {
    ignored += (ignored.empty() ? "`" : ", `") + name + "`";
  }
  return ParameterPage{
      "dwa.md", "DWA local planner",
      "Parameters of the DWA local planner, in `~TrajectoryPlannerROS/` of the `move_base` node "
      "(`~DWAPlannerROS/` when `base_local_planner` is dwa_local_planner/DWAPlannerROS), with "
      "base_local_planner's TrajectoryPlannerROS names and defaults. "
      "`config/trajectory_planner.yaml` sets the shipped values. " +
          std::string(kReported),
      {Section("Options", "", nav::dwa::DwaOptionTable()),
       Section("Other names",
               "Older TrajectoryPlannerROS names and DWAPlannerROS names that mean the same for "
               "a differential drive; read after the options above, so an alias given together "
               "with its option wins.",
               nav::dwa::DwaAliasOptionTable()),
       ParameterSection{"Accepted and ignored",
                        "Names of either planner for holonomic bases, for cost terms and "
                        "publishers this planner does not have, or for ROS plumbing: read "
                        "without effect and without a warning.",
                        ignored + "\n"}}};
}

ParameterPage MoveBasePage() {
  return ParameterPage{
      "move_base.md", "move_base",
      "Private parameters of the `move_base` node (`~name`), with ROS move_base's names and "
      "defaults. `config/move_base_params.yaml` sets the shipped values; "
      "`config/move_base_mapless_params.yaml` is loaded over it in mapless mode, and "
      "explore.launch sets `back_out_distance`. The frames are the costmaps': goals and plans "
      "are in the global costmap's `global_frame`. The sub-namespaces have their own pages: "
      "`~global_costmap/` and `~local_costmap/` ([costmap](costmap.md)), "
      "`~TrajectoryPlannerROS/` or `~DWAPlannerROS/` ([dwa](dwa.md)), `~NavfnROS/`, "
      "`~GlobalPlanner/` and `~OmplPlanner/` ([planner](planner.md)). " +
          std::string(kReported),
      {Section("Planners, rates and recoveries", "", nav::MoveBaseOptionTable()),
       Section("Moving obstacle tracker",
               "`~obstacle_tracker/`: clusters in the local costmap's observations tracked at "
               "constant velocity, whose predicted positions the DWA local planner avoids "
               "([dwa](dwa.md): `moving_obstacle_*`, `personal_distance`).",
               nav::ObstacleTrackerOptionTable()),
       minibot3d_ros::FrameOptionsSection(
           "both costmaps' `global_frame` and `robot_base_frame` and their sources' "
           "`sensor_frame`")}};
}

ParameterPage ExplorePage() {
  return ParameterPage{
      "explore.md", "explore",
      "Private parameters of the `explore` node (`~name`), with explore_lite's names where "
      "explore_lite has the parameter. A robot's config set gives `robot_base_frame`, "
      "`min_frontier_size`, `clearance` and `goal_clearance` in explore.yaml (minibot3d's: "
      "`config/explore.yaml`, loaded by explore.launch and make demo); no shipped YAML sets the "
      "others. " +
          std::string(kReported),
      {Section("Frontier search", "Which frontiers count, where a robot goes to see past them, "
               "and when a place is given up.",
               nav::ExploreOptionTable()),
       Section("Node", "Frames, the search rate and when a goal is replaced or cancelled.",
               nav::ExploreNodeOptionTable()),
       minibot3d_ros::FrameOptionsSection("`global_frame` and `robot_base_frame`")}};
}

}  // namespace

std::vector<ParameterPage> ParameterPages() {
  return {AmclPage(), CostmapPage(), PlannerPage(), DwaPage(), MoveBasePage(), ExplorePage()};
}

}  // namespace minibot3d_navigation
