#include "minibot3d_lockstep/transform_listener.h"

#include <boost/bind/bind.hpp>
#include <ros/console.h>
#include <tf2/exceptions.h>

namespace minibot3d_lockstep {

TransformListener::TransformListener(tf2_ros::Buffer& buffer, Participant& participant)
    : buffer_(buffer) {
  if (!participant.enabled()) {
    plain_ = std::make_unique<tf2_ros::TransformListener>(buffer, participant.tf_node_handle(),
                                                          /*spin_thread=*/true);
    return;
  }
  ros::NodeHandle& nh = participant.tf_node_handle();
  // Queue size 0: unbounded. The topics are tf2_ros's.
  tf_sub_ = nh.subscribe<tf2_msgs::TFMessage>(
      "/tf", 0, boost::bind(&TransformListener::OnTf, this, boost::placeholders::_1, false));
  static_sub_ = nh.subscribe<tf2_msgs::TFMessage>(
      "/tf_static", 0, boost::bind(&TransformListener::OnTf, this, boost::placeholders::_1, true));
}

void TransformListener::OnTf(const ros::MessageEvent<tf2_msgs::TFMessage const>& event,
                             bool is_static) {
  // As tf2_ros::TransformListener: a clock that went back (a simulation restarted) empties the
  // buffer; each transform is set with its publisher as the authority.
  const ros::Time now = ros::Time::now();
  if (now < last_update_) {
    ROS_WARN_STREAM("Detected jump back in time of " << (last_update_ - now).toSec()
                                                     << "s. Clearing TF buffer.");
    buffer_.clear();
  }
  last_update_ = now;
  const std::string& authority = event.getPublisherName();
  for (const auto& t : event.getConstMessage()->transforms) {
    try {
      buffer_.setTransform(t, authority, is_static);
    } catch (const tf2::TransformException& e) {
      ROS_ERROR_THROTTLE(5.0, "tf from %s: cannot set the transform %s -> %s: %s",
                         authority.c_str(), t.header.frame_id.c_str(), t.child_frame_id.c_str(),
                         e.what());
    }
  }
}

}  // namespace minibot3d_lockstep
