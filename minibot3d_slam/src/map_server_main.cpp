// map_server: serves a map in map_server's format (NAME.yaml + image) as ROS map_server does:
// latched `map` (nav_msgs/OccupancyGrid) and `map_metadata` (nav_msgs/MapMetaData), and the
// service `static_map` (nav_msgs/GetMap). Loading and all its checks live in
// minibot3d_map_io.
//
//   rosrun minibot3d_slam map_server MAP.yaml [_frame_id:=map]
#include <nav_msgs/GetMap.h>
#include <nav_msgs/MapMetaData.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>

#include <cstdio>
#include <stdexcept>
#include <string>

#include "minibot3d_ros/conversions.h"
#include "minibot3d_ros/frames.h"
#include "minibot3d_ros/params.h"
#include "minibot3d_slam/map_files.h"
#include "minibot3d_slam/node_options.h"
#include "minibot3d_slam/types.h"

namespace {

constexpr char kUsage[] =
    "Usage: map_server MAP.yaml [_frame_id:=map]\n"
    "  Publishes the map latched on 'map' and 'map_metadata' and serves 'static_map'.\n"
    "  Exit codes: 1 the map cannot be loaded, 2 bad arguments or parameters.\n";

class MapServer {
 public:
  explicit MapServer(const nav_msgs::OccupancyGrid& map) {
    response_.map = map;
    ros::NodeHandle nh;
    service_ = nh.advertiseService("static_map", &MapServer::OnStaticMap, this);
    metadata_pub_ = nh.advertise<nav_msgs::MapMetaData>("map_metadata", 1, /*latch=*/true);
    map_pub_ = nh.advertise<nav_msgs::OccupancyGrid>("map", 1, /*latch=*/true);
    metadata_pub_.publish(response_.map.info);
    map_pub_.publish(response_.map);
  }

 private:
  bool OnStaticMap(nav_msgs::GetMap::Request&, nav_msgs::GetMap::Response& res) {
    res = response_;
    return true;
  }

  nav_msgs::GetMap::Response response_;
  ros::ServiceServer service_;
  ros::Publisher metadata_pub_;
  ros::Publisher map_pub_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "map_server");
  if (argc == 2 && (std::string(argv[1]) == "-h" || std::string(argv[1]) == "--help")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (argc != 2) {
    std::fprintf(stderr, "map_server: expected one argument, the map YAML\n%s", kUsage);
    return 2;
  }
  const std::string yaml_path = argv[1];
  minibot3d_slam::GridMap map;
  try {
    map = minibot3d_map_io::LoadMap(yaml_path);
  } catch (const minibot3d_map_io::MapIoError& e) {
    std::fprintf(stderr, "map_server: %s\n", e.what());
    return 1;
  }

  minibot3d_slam::MapServerOptions options;
  minibot3d_ros::ParamReport report =
      minibot3d_ros::LoadTable(ros::NodeHandle("~"), minibot3d_slam::MapServerOptionTable(), &options);
  minibot3d_ros::FrameOptions frames;
  report.Also(minibot3d_ros::LoadFrameOptions(ros::NodeHandle("~"), &frames));
  report.WarnUnknown("map_server");
  try {
    report.ThrowIfBad();
    minibot3d_slam::ValidateMapServerOptions(options);
  } catch (const std::invalid_argument& e) {
    // Before the node has started rosconsole may not print: stderr, as the errors above.
    std::fprintf(stderr, "map_server: %s\n", e.what());
    return 2;
  }
  // A map of one robot among several (shared_frames without map) is in that robot's map frame.
  options.frame_id = minibot3d_ros::FrameNames(frames).Resolve(options.frame_id);
  // Stamped (and map_load_time) when it is loaded, as ROS map_server does.
  MapServer server(minibot3d_ros::GridToMsg(map, options.frame_id, ros::Time::now()));
  ROS_INFO("Serving %s: %d x %d cells @ %g m/cell, origin (%g, %g, %g), frame '%s'",
           yaml_path.c_str(), map.width, map.height, map.resolution, map.origin_x, map.origin_y,
           map.origin_theta, options.frame_id.c_str());
  ros::spin();
  return 0;
}
