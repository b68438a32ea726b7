// The option tables and validation of the package's ROS nodes (node_options.h).
#include "minibot3d_slam/node_options.h"

namespace minibot3d_slam {

namespace options = minibot3d_common::options;
using options::Field;

const options::OptionTable<SlamGmappingNodeOptions>& SlamGmappingNodeOptionTable() {
  using N = SlamGmappingNodeOptions;
  static const options::OptionTable<N> table(
      "slam_gmapping",
      {Field("base_frame", &N::base_frame, "The robot's base frame (child of the odometry tf)."),
       Field("odom_frame", &N::odom_frame, "The odometry frame."),
       Field("map_frame", &N::map_frame,
             "The map frame: the map is published in it, and the transform map_frame -> "
             "odom_frame."),
       Field("map_update_interval", &N::map_update_interval,
             "Time (s, by the scans' stamps) after which a processed scan publishes the map "
             "again; the first map and a map corrected by a loop closure are published at once."),
       Field("transform_publish_period", &N::transform_publish_period,
             "Period (s) of the map -> odom broadcast, each post-dated by one period; 0 "
             "disables it."),
       Field("throttle_scans", &N::throttle_scans,
             "Use one scan in this many and drop the others (1: every scan)."),
       Field("tf_delay", &N::tf_delay,
             "Accepted for gmapping YAMLs and ignored: the map -> odom transform is post-dated "
             "by transform_publish_period (gmapping's default for tf_delay).")});
  return table;
}

void ValidateSlamGmappingNodeOptions(const SlamGmappingNodeOptions& o) {
  options::Problems p("slam_gmapping");
  p.NonEmpty("base_frame", o.base_frame);
  p.NonEmpty("odom_frame", o.odom_frame);
  p.NonEmpty("map_frame", o.map_frame);
  p.Positive("map_update_interval", o.map_update_interval);
  p.NonNegative("transform_publish_period", o.transform_publish_period);
  p.Check(o.throttle_scans >= 1, "throttle_scans", o.throttle_scans, ">= 1");
  p.ThrowIfAny();
}

const options::OptionTable<MapServerOptions>& MapServerOptionTable() {
  static const options::OptionTable<MapServerOptions> table(
      "map_server",
      {Field("frame_id", &MapServerOptions::frame_id,
             "Frame of the served map (the header.frame_id of map and static_map).")});
  return table;
}

void ValidateMapServerOptions(const MapServerOptions& o) {
  options::Problems p("map_server");
  p.NonEmpty("frame_id", o.frame_id);
  p.ThrowIfAny();
}

}  // namespace minibot3d_slam
