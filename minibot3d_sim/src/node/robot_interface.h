// The ROS side of one simulated robot: its drive's command subscriber and odometry, joint states,
// static transforms, lasers, IMUs and ground truth, each on the topic and frame its Gazebo plugin
// names (relative names resolved in the plugin's robot namespace, as Gazebo's plugins resolve
// them).
#ifndef MINIBOT3D_SIM_SRC_NODE_ROBOT_INTERFACE_H_
#define MINIBOT3D_SIM_SRC_NODE_ROBOT_INTERFACE_H_

#include <string>
#include <vector>

#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include "minibot3d_sim/simulator.h"

namespace minibot3d_sim {

class RobotInterface {
 public:
  struct Options {
    bool lockstep = false;              // outgoing queues never drop in lock-step
    bool publish_ground_truth = true;   // ~ground_truth/odom in world_frame
    std::string world_frame = "world";
    // Put before each of the robot's frames (odometry, links, sensors), as gazebo_ros resolves
    // its plugins' frames with a tf_prefix: "NAME/" for robot NAME of several, "" for one.
    std::string frame_prefix;
  };
  // `urdf_xml` gives the fixed joints for /tf_static; commands go to `cmd_queue`.
  RobotInterface(SimRobot* robot, const std::string& urdf_xml, const Options& options,
                 ros::CallbackQueue* cmd_queue);

  // Publishes whatever is due at the current sim time (everything when `all`).
  void Publish(bool all);
  // Appends the robot's fixed joints, stamped now, to `msg`: the simulator publishes those of
  // all its robots as one latched /tf_static message (a latching publisher keeps only its last
  // message, so one message per robot would leave a late subscriber with the last robot's only).
  void AppendStaticTransforms(tf2_msgs::TFMessage* msg);

  // Resolves a plugin's topic in its namespace: absolute names stay, relative ones go under it.
  static std::string Resolve(const std::string& ns, const std::string& topic);

 private:
  struct CameraPublishers {
    ros::Publisher image, info, depth, depth_info, points;
    sensor_msgs::CameraInfo camera_info;
    double focal_length = 0.0;
    DepthFrame frame;
    std::vector<float> xyz;
  };
  void SetUpCamera(size_t i);
  void PublishCamera(size_t i, const ros::Time& stamp);
  void PublishOdometry(const ros::Time& stamp);
  void PublishJointStates(const ros::Time& stamp);
  void OnCommand(const ros::MessageEvent<const geometry_msgs::Twist>& event);
  // A frame of the robot with the prefix (the world frame as it is), without a leading slash.
  std::string Frame(const std::string& name) const;

  SimRobot* robot_;
  Options options_;
  ros::NodeHandle nh_;
  ros::Publisher odom_pub_, tf_pub_, joint_pub_, truth_pub_;
  std::vector<ros::Publisher> scan_pubs_, imu_pubs_, gt_pubs_;
  std::vector<CameraPublishers> cameras_;
  ros::Subscriber cmd_sub_;
  tf2_msgs::TFMessage static_tf_;
  std::vector<sensor_msgs::LaserScan> scans_;
  sensor_msgs::JointState joint_state_;
  std::vector<int> wheel_joint_index_;  // where each driven wheel sits in joint_state_
  std::vector<float> ranges_;
  double odom_period_ = 0.0, next_odom_ = 0.0;
  double joint_period_ = 0.0, next_joints_ = 0.0;
  bool joints_with_odometry_ = true;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_SRC_NODE_ROBOT_INTERFACE_H_
