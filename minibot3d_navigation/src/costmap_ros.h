// Costmap2DROS equivalent: a LayeredCostmap (ROS-free core) fed from ROS.
//
// Reads the costmap_2d parameters of namespace ~<name> (global_costmap /
// local_costmap) through the option tables of costmap_options.h, subscribes
// the static map (static_map: true) and every observation source
// (observation_sources: "a b", each ~<name>/a: {topic, sensor_frame,
// data_type: LaserScan, marking, clearing, obstacle_range, raytrace_range,
// inf_is_valid}), and publishes the costmap as an
// OccupancyGrid on ~<name>/costmap with costmap_2d's value translation.
// Scans are converted once, through a tf2 MessageFilter so they wait for
// their transform into the costmap's frame.  All updates run in the caller's
// thread (Update), so no locks are needed with a single-threaded spinner.
#ifndef MINIBOT3D_NAVIGATION_SRC_COSTMAP_ROS_H_
#define MINIBOT3D_NAVIGATION_SRC_COSTMAP_ROS_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <message_filters/subscriber.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>

#include "minibot3d_navigation/costmap/costmap_options.h"
#include "minibot3d_navigation/costmap/layered_costmap.h"
#include "minibot3d_ros/frames.h"

namespace minibot3d_navigation {

class CostmapRos {
 public:
  CostmapRos(const std::string& name, tf2_ros::Buffer* tf);

  // Reads and validates ~name/ parameters, the frames resolved with `frames`
  // (global_frame, robot_base_frame and the sources' sensor_frame); throws
  // std::invalid_argument listing every problem (naming the parameter).
  void Configure(const minibot3d_ros::FrameNames& frames);
  // Subscribes the map and the observation sources, advertises the costmap.
  void Start();

  // Robot pose in the costmap's frame (latest tf); false with *why filled
  // (throttled warnings are the caller's business). *clocks_disagree, if
  // given, says the node and tf run on different clocks (wall vs sim time:
  // transform_age.h), which no tf publisher can fix.
  bool RobotPose(nav::Pose2* pose, std::string* why, bool* clocks_disagree = nullptr) const;
  // Updates the costmap at `robot` if update_frequency says so (or force),
  // and publishes at publish_frequency.
  void Update(const ros::Time& now, const nav::Pose2& robot, bool force = false);
  // Forgets obstacles (clear_costmaps service).
  void Reset();
  void ClearExceptAround(const nav::Pose2& robot, double reset_distance);
  // Called with every observation the obstacle layer takes (its stamp, s; in the costmap's
  // frame), after the layer has it.
  using ObservationCallback = std::function<void(double stamp, const nav::Observation&)>;
  void set_observation_callback(ObservationCallback callback) {
    observation_callback_ = std::move(callback);
  }

  bool ready() const { return !options_.static_map || have_map_; }
  const std::string& name() const { return name_; }
  const nav::CostmapOptions& options() const { return options_; }
  const nav::Footprint& footprint() const { return footprint_; }
  const nav::Costmap2D& costmap() const { return layered_->costmap(); }
  nav::LayeredCostmap& layered() { return *layered_; }

 private:
  struct Source {
    std::string name;
    nav::ObservationSourceOptions options;
    std::unique_ptr<message_filters::Subscriber<sensor_msgs::LaserScan>> sub;
    std::unique_ptr<tf2_ros::MessageFilter<sensor_msgs::LaserScan>> filter;
    std::unique_ptr<message_filters::Subscriber<sensor_msgs::PointCloud2>> cloud_sub;
    std::unique_ptr<tf2_ros::MessageFilter<sensor_msgs::PointCloud2>> cloud_filter;
    std::vector<double> xyz;  // scratch
  };
  void OnScan(const sensor_msgs::LaserScan::ConstPtr& scan, Source* source);
  void OnCloud(const sensor_msgs::PointCloud2::ConstPtr& cloud, Source* source);
  void OnMap(const nav_msgs::OccupancyGrid::ConstPtr& map);
  void Publish(const ros::Time& now);

  std::string name_;
  tf2_ros::Buffer* tf_;
  ros::NodeHandle nh_;   // ~name
  ros::NodeHandle gnh_;  // for topics
  nav::CostmapOptions options_;
  nav::Footprint footprint_;
  std::unique_ptr<nav::LayeredCostmap> layered_;
  std::vector<std::unique_ptr<Source>> sources_;
  ros::Subscriber map_sub_;
  ros::Publisher costmap_pub_, footprint_pub_;
  ObservationCallback observation_callback_;
  bool have_map_ = false;
  ros::Time next_update_, next_publish_;
};

}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_SRC_COSTMAP_ROS_H_
