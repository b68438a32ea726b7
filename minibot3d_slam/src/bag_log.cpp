#include "minibot3d_slam/bag_log.h"

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <vector>

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2/utils.h>
#include <tf2_msgs/TFMessage.h>

namespace minibot3d_slam {
namespace {

Pose2 ToPose2(const geometry_msgs::Transform& t) {
  return Pose2{t.translation.x, t.translation.y, tf2::getYaw(t.rotation)};
}

// Odometry poses by time, interpolated linearly (angles along the shorter arc).
class OdomTrack {
 public:
  void Add(double t, const Pose2& p) { poses_[t] = p; }
  bool At(double t, Pose2* out) const {
    if (poses_.empty()) return false;
    auto hi = poses_.lower_bound(t);
    if (hi == poses_.end()) return false;
    if (hi->first == t) {
      *out = hi->second;
      return true;
    }
    if (hi == poses_.begin()) return false;
    auto lo = std::prev(hi);
    const double a = (t - lo->first) / (hi->first - lo->first);
    const Pose2& p = lo->second;
    const Pose2& q = hi->second;
    *out = Pose2{p.x + a * (q.x - p.x), p.y + a * (q.y - p.y),
                 NormalizeAngle(p.theta + a * NormalizeAngle(q.theta - p.theta))};
    return true;
  }

 private:
  std::map<double, Pose2> poses_;
};

}  // namespace

CarmenLog ReadBagLog(const std::string& path, const BagLogOptions& options) {
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error(path + ": cannot open the bag: " + e.what());
  }
  CarmenLog log;
  // Pass 1: all transforms (and odometry messages) into a buffer covering the whole bag.
  rosbag::View all(bag);
  const double span = (all.getEndTime() - all.getBeginTime()).toSec() + 10.0;
  tf2::BufferCore tf(ros::Duration(std::max(span, 10.0)));
  OdomTrack odom;
  std::size_t scans = 0;
  for (const rosbag::MessageInstance& m : all) {
    ++log.lines;
    const std::string& topic = m.getTopic();
    if (topic == "/tf" || topic == "/tf_static") {
      auto msg = m.instantiate<tf2_msgs::TFMessage>();
      if (!msg) continue;
      for (const auto& t : msg->transforms) tf.setTransform(t, "bag", topic == "/tf_static");
    } else if (!options.odom_topic.empty() && topic == options.odom_topic) {
      auto msg = m.instantiate<nav_msgs::Odometry>();
      if (!msg) continue;
      geometry_msgs::Transform t;
      t.translation.x = msg->pose.pose.position.x;
      t.translation.y = msg->pose.pose.position.y;
      t.rotation = msg->pose.pose.orientation;
      odom.Add(msg->header.stamp.toSec(), ToPose2(t));
    } else if (topic == options.scan_topic) {
      ++scans;
    } else {
      ++log.skipped[topic];
    }
  }
  if (scans == 0) {
    throw std::runtime_error(path + ": no message on the scan topic '" + options.scan_topic + "'");
  }
  // Pass 2: the scans, placed with the odometry and the sensor pose at their time.
  rosbag::View scan_view(bag, rosbag::TopicQuery(options.scan_topic));
  for (const rosbag::MessageInstance& m : scan_view) {
    auto msg = m.instantiate<sensor_msgs::LaserScan>();
    if (!msg) {
      ++log.skipped["scan of another type"];
      continue;
    }
    LogScan s;
    s.timestamp = msg->header.stamp.toSec();
    Pose2 base_pose;
    try {
      if (options.odom_topic.empty()) {
        base_pose = ToPose2(tf.lookupTransform(options.odom_frame, options.base_frame,
                                               msg->header.stamp).transform);
      } else if (!odom.At(s.timestamp, &base_pose)) {
        throw tf2::ExtrapolationException("no odometry message around the scan");
      }
      s.scan.sensor_in_base = ToPose2(tf.lookupTransform(options.base_frame,
                                                         msg->header.frame_id,
                                                         msg->header.stamp).transform);
    } catch (const tf2::TransformException& e) {
      ++log.skipped["scan without tf"];
      if (log.warnings.size() < 20) {
        log.warnings.push_back("scan at " + std::to_string(s.timestamp) + " in frame '" +
                               msg->header.frame_id + "' skipped: " + e.what());
      }
      continue;
    }
    s.odom = base_pose;
    s.scan.time = s.timestamp;
    s.scan.range_min = msg->range_min;
    s.scan.range_max = msg->range_max;
    s.scan.ranges.resize(msg->ranges.size());
    s.scan.angles.resize(msg->ranges.size());
    for (std::size_t i = 0; i < msg->ranges.size(); ++i) {
      const double r = msg->ranges[i];
      // No-returns (REP 117: ±inf, NaN, or at range_max) become +inf, as in the CARMEN reader.
      s.scan.ranges[i] = (!std::isfinite(r) || r >= msg->range_max)
                             ? std::numeric_limits<double>::infinity()
                             : r;
      s.scan.angles[i] = msg->angle_min + i * msg->angle_increment;
    }
    log.scans.push_back(std::move(s));
  }
  return log;
}

}  // namespace minibot3d_slam
