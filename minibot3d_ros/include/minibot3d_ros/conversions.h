// Conversions between ROS messages / tf and the ROS-free cores' types (minibot3d_common's planar
// pose, minibot3d_map_io's occupancy grid), for every minibot3d node.
#ifndef MINIBOT3D_ROS_CONVERSIONS_H_
#define MINIBOT3D_ROS_CONVERSIONS_H_

#include <cmath>
#include <string>

#include <geometry_msgs/Quaternion.h>
#include <geometry_msgs/Transform.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/time.h>
#include <tf2/LinearMath/Quaternion.h>
#include <tf2/LinearMath/Transform.h>
#include <tf2/utils.h>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_map_io/map_io.h"

namespace minibot3d_ros {

using minibot3d_common::Pose2;

// A rotation by `yaw` about z.
inline geometry_msgs::Quaternion YawToQuaternion(double yaw) {
  geometry_msgs::Quaternion q;
  q.z = std::sin(yaw / 2.0);
  q.w = std::cos(yaw / 2.0);
  return q;
}

// The planar part of a transform (x, y and the yaw of its rotation).
inline Pose2 PoseFromTransform(const geometry_msgs::Transform& t) {
  return Pose2{t.translation.x, t.translation.y, tf2::getYaw(t.rotation)};
}

inline Pose2 PoseFromTf(const tf2::Transform& t) {
  return Pose2{t.getOrigin().x(), t.getOrigin().y(), tf2::getYaw(t.getRotation())};
}

inline tf2::Transform TfFromPose(const Pose2& p) {
  tf2::Quaternion q;
  q.setRPY(0, 0, p.yaw);
  return tf2::Transform(q, tf2::Vector3(p.x, p.y, 0.0));
}

// The message's cells, origin and resolution (the float32 resolution widened as it is).
inline minibot3d_map_io::OccupancyGrid GridFromMsg(const nav_msgs::OccupancyGrid& m) {
  minibot3d_map_io::OccupancyGrid g;
  g.resolution = m.info.resolution;
  g.origin_x = m.info.origin.position.x;
  g.origin_y = m.info.origin.position.y;
  g.origin_theta = tf2::getYaw(m.info.origin.orientation);
  g.width = static_cast<int>(m.info.width);
  g.height = static_cast<int>(m.info.height);
  g.data.assign(m.data.begin(), m.data.end());
  return g;
}

inline nav_msgs::OccupancyGrid GridToMsg(const minibot3d_map_io::OccupancyGrid& g,
                                         const std::string& frame_id, const ros::Time& stamp) {
  nav_msgs::OccupancyGrid m;
  m.header.frame_id = frame_id;
  m.header.stamp = stamp;
  m.info.map_load_time = stamp;
  m.info.resolution = static_cast<float>(g.resolution);
  m.info.width = static_cast<unsigned>(g.width);
  m.info.height = static_cast<unsigned>(g.height);
  m.info.origin.position.x = g.origin_x;
  m.info.origin.position.y = g.origin_y;
  m.info.origin.orientation = YawToQuaternion(g.origin_theta);
  m.data.assign(g.data.begin(), g.data.end());
  return m;
}

}  // namespace minibot3d_ros

#endif  // MINIBOT3D_ROS_CONVERSIONS_H_
