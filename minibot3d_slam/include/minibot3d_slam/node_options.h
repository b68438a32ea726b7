// Parameters of the package's ROS nodes beyond the SLAM core's (gmapping_options.h): the
// slam_gmapping node's own (frames, map publication, the map -> odom broadcast) and map_server's,
// with the names and defaults of ROS gmapping's slam_gmapping and ROS map_server. Their option
// tables read them by name and document them (docs/parameters/).
#ifndef MINIBOT3D_SLAM_NODE_OPTIONS_H_
#define MINIBOT3D_SLAM_NODE_OPTIONS_H_

#include <string>

#include "minibot3d_common/options.h"

namespace minibot3d_slam {

struct SlamGmappingNodeOptions {
  std::string base_frame = "base_link";
  std::string odom_frame = "odom";
  std::string map_frame = "map";
  double map_update_interval = 5.0;        // s between map publications
  double transform_publish_period = 0.05;  // s; 0 disables the map -> odom broadcast
  int throttle_scans = 1;                  // process one scan in this many
  // gmapping post-dates the map -> odom transform by tf_delay (default: transform_publish_period);
  // this node always by transform_publish_period. Read so that gmapping YAMLs load without a
  // warning.
  double tf_delay = 0.0;
};

const minibot3d_common::options::OptionTable<SlamGmappingNodeOptions>& SlamGmappingNodeOptionTable();

// Throws std::invalid_argument naming every bad value.
void ValidateSlamGmappingNodeOptions(const SlamGmappingNodeOptions& options);

struct MapServerOptions {
  std::string frame_id = "map";
};

const minibot3d_common::options::OptionTable<MapServerOptions>& MapServerOptionTable();

// Throws std::invalid_argument naming every bad value.
void ValidateMapServerOptions(const MapServerOptions& options);

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_NODE_OPTIONS_H_
