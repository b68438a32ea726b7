#include "parameter_pages.h"

#include "minibot3d_ros/frame_names.h"
#include "minibot3d_slam/gmapping_options.h"
#include "minibot3d_slam/map_consistency.h"
#include "minibot3d_slam/node_options.h"

namespace minibot3d_slam {

using minibot3d_common::ParameterPage;
using minibot3d_common::Section;

std::vector<ParameterPage> ParameterPages() {
  std::vector<ParameterPage> pages;
  pages.push_back(ParameterPage{
      "slam.md", "slam_gmapping",
      "Private parameters of the `slam_gmapping` node (`~name`), with ROS gmapping's names and "
      "defaults where gmapping has the parameter; `config/gmapping.yaml` (loaded by "
      "`minibot3d_slam/launch/slam_gmapping.launch`) sets the ones the shipped stacks change. "
      "`slam_offline` takes the same SLAM parameters from `--param-file YAML` and "
      "`--param NAME=VALUE`. A key the node does not know is reported once at start-up; a bad "
      "value stops the node with every offending parameter named.",
      {Section("SLAM",
               "The Rao-Blackwellized particle filter (Grisetti, Stachniss & Burgard, 2007): when "
               "a scan is processed, the odometry noise, the scan matcher, the map and the loop "
               "closure.",
               GmappingOptionTable()),
       Section("Node", "Frames, map publication and the map -> odom transform.",
               SlamGmappingNodeOptionTable()),
       minibot3d_ros::FrameOptionsSection("`base_frame`, `odom_frame` and `map_frame`")}});
  pages.push_back(ParameterPage{
      "map_server.md", "map_server",
      "Private parameter of the `map_server` node (`rosrun minibot3d_slam map_server MAP.yaml`), "
      "which serves a map in ROS map_server's format latched on `map` and `map_metadata` and "
      "through the `static_map` service. `map_saver` has no ROS parameters; it takes "
      "command-line arguments: `-f NAME` (writes NAME.pgm and NAME.yaml; default `map`), "
      "`--occ PERCENT` (cells at or above it are written occupied; default 65), `--free PERCENT` "
      "(cells from 0 to it are written free; default 25), `--timeout SECONDS` (wall time to wait "
      "for a map; default 30) and the remapping `map:=/topic`.",
      {Section("map_server", "", MapServerOptionTable()),
       minibot3d_ros::FrameOptionsSection("`frame_id`")}});
  pages.push_back(ParameterPage{
      "map_consistency.md", "map_consistency",
      "Parameters of `map_consistency LOG [TRAJECTORY] [--param NAME=VALUE ...] [--worst N]`, "
      "which scores how well a trajectory's scans of a CARMEN log agree where the robot came "
      "back: the share of endpoints lying where another pass of the robot saw free space, and "
      "the scans placed off the map (see [slam.md](../slam.md#map-consistency-without-ground-"
      "truth)). A bad value stops it with every offending parameter named.",
      {Section("map_consistency", "", ConsistencyOptionTable())}});
  return pages;
}

}  // namespace minibot3d_slam
