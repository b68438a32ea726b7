#include "minibot3d_slam/bag_log.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <memory>
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
                 NormalizeAngle(p.yaw + a * NormalizeAngle(q.yaw - p.yaw))};
    return true;
  }
  // Forgets the poses before t, keeping the last one before it (for interpolation).
  void DropBefore(double t) {
    auto it = poses_.lower_bound(t);
    if (it == poses_.begin()) return;
    poses_.erase(poses_.begin(), std::prev(it));
  }
  void Clear() { poses_.clear(); }

 private:
  std::map<double, Pose2> poses_;
};

// The bag is read once in time order, all topics together. A scan waits in a queue until the
// transforms (or odometry) are known kLookahead seconds past its stamp, or the bag ends, and is
// then placed; transforms are kept for kCacheSeconds (static ones for good), odometry messages
// likewise. So the reader holds a window of the bag, not the bag.
class BagLogReader : public LogReader {
 public:
  static constexpr double kLookahead = 1.0;      // s of transforms past a scan before placing it
  static constexpr double kCacheSeconds = 30.0;  // s of transforms and odometry kept
  static constexpr std::size_t kMaxPending = 2000;  // scans waiting (transforms stopped coming)

  BagLogReader(const std::string& path, const BagLogOptions& options) : path_(path), options_(options) {
    try {
      bag_.open(path, rosbag::bagmode::Read);
      // What the bag holds, from its index (no message is read here).
      rosbag::View all(bag_);
      report_.lines = static_cast<int>(all.size());
      std::size_t scans = 0;
      for (const rosbag::ConnectionInfo* c : all.getConnections()) {
        const std::string& topic = c->topic;
        const std::size_t n = rosbag::View(bag_, rosbag::TopicQuery(topic)).size();
        if (topic == options.scan_topic) {
          scans = n;
        } else if (topic != "/tf" && topic != "/tf_static" &&
                   (options.odom_topic.empty() || topic != options.odom_topic)) {
          report_.skipped[topic] = static_cast<int>(n);
        }
      }
      if (scans == 0) {
        throw std::runtime_error(path + ": no message on the scan topic '" + options.scan_topic + "'");
      }
    } catch (const rosbag::BagException& e) {
      throw std::runtime_error(path + ": cannot open the bag: " + e.what());
    }
    Rewind();
    first_pass_ = true;
  }

  bool Next(LogScan* out) override {
    try {
      while (true) {
        const bool ended = it_ == view_->end();
        while (!pending_.empty() &&
               (ended || pending_.size() > kMaxPending ||
                latest_ >= pending_.front()->header.stamp.toSec() + kLookahead)) {
          const sensor_msgs::LaserScan::ConstPtr msg = pending_.front();
          pending_.pop_front();
          if (Place(*msg, out)) return true;
        }
        if (ended) break;
        Read(*it_);
        ++it_;
      }
    } catch (const rosbag::BagException& e) {
      throw std::runtime_error(path_ + ": cannot read on: " + e.what());
    }
    first_pass_ = false;
    return false;
  }

  void Rewind() override {
    view_ = std::make_unique<rosbag::View>(bag_);
    it_ = view_->begin();
    tf_ = std::make_unique<tf2::BufferCore>(ros::Duration(kCacheSeconds));
    odom_.Clear();
    pending_.clear();
    latest_ = -std::numeric_limits<double>::infinity();
    first_pass_ = false;
  }

 private:
  void Read(const rosbag::MessageInstance& m) {
    const std::string& topic = m.getTopic();
    if (topic == "/tf" || topic == "/tf_static") {
      auto msg = m.instantiate<tf2_msgs::TFMessage>();
      if (!msg) return;
      const bool fixed = topic == "/tf_static";
      for (const auto& t : msg->transforms) {
        tf_->setTransform(t, "bag", fixed);
        if (!fixed && options_.odom_topic.empty()) latest_ = std::max(latest_, t.header.stamp.toSec());
      }
    } else if (!options_.odom_topic.empty() && topic == options_.odom_topic) {
      auto msg = m.instantiate<nav_msgs::Odometry>();
      if (!msg) return;
      geometry_msgs::Transform t;
      t.translation.x = msg->pose.pose.position.x;
      t.translation.y = msg->pose.pose.position.y;
      t.rotation = msg->pose.pose.orientation;
      const double stamp = msg->header.stamp.toSec();
      odom_.Add(stamp, ToPose2(t));
      latest_ = std::max(latest_, stamp);
      odom_.DropBefore(stamp - kCacheSeconds);
    } else if (topic == options_.scan_topic) {
      auto msg = m.instantiate<sensor_msgs::LaserScan>();
      if (!msg) {
        if (first_pass_) ++report_.skipped["scan of another type"];
        return;
      }
      pending_.push_back(msg);
    }
  }

  // The scan placed with the odometry and the sensor pose at its time; false (counted in the
  // first pass) when it cannot be.
  bool Place(const sensor_msgs::LaserScan& msg, LogScan* s) {
    s->timestamp = msg.header.stamp.toSec();
    Pose2 base_pose;
    try {
      if (options_.odom_topic.empty()) {
        base_pose = ToPose2(tf_->lookupTransform(options_.odom_frame, options_.base_frame, msg.header.stamp).transform);
      } else if (!odom_.At(s->timestamp, &base_pose)) {
        throw tf2::ExtrapolationException("no odometry message around the scan");
      }
      s->scan.sensor_in_base =
          ToPose2(tf_->lookupTransform(options_.base_frame, msg.header.frame_id, msg.header.stamp).transform);
    } catch (const tf2::TransformException& e) {
      if (first_pass_) {
        ++report_.skipped["scan without tf"];
        if (report_.warnings.size() < 20) {
          report_.warnings.push_back(path_ + ": scan at " + std::to_string(s->timestamp) + " in frame '" +
                                     msg.header.frame_id + "' skipped: " + e.what());
        }
      }
      return false;
    }
    s->odom = base_pose;
    s->scan.time = s->timestamp;
    s->scan.range_min = msg.range_min;
    s->scan.range_max = msg.range_max;
    s->scan.ranges.resize(msg.ranges.size());
    s->scan.angles.resize(msg.ranges.size());
    for (std::size_t i = 0; i < msg.ranges.size(); ++i) {
      const double r = msg.ranges[i];
      // No-returns (REP 117: ±inf, NaN, or at range_max) become +inf, as in the CARMEN reader.
      s->scan.ranges[i] = (!std::isfinite(r) || r >= msg.range_max) ? std::numeric_limits<double>::infinity() : r;
      s->scan.angles[i] = msg.angle_min + i * msg.angle_increment;
    }
    return true;
  }

  std::string path_;
  BagLogOptions options_;
  rosbag::Bag bag_;
  std::unique_ptr<rosbag::View> view_;
  rosbag::View::iterator it_;
  std::unique_ptr<tf2::BufferCore> tf_;
  OdomTrack odom_;
  std::deque<sensor_msgs::LaserScan::ConstPtr> pending_;
  double latest_ = 0.0;  // newest odometry stamp read (odom transforms or odometry messages)
  bool first_pass_ = false;  // counts and reports unplaceable scans only once
};

}  // namespace

std::unique_ptr<LogReader> OpenBagLog(const std::string& path, const BagLogOptions& options) {
  return std::make_unique<BagLogReader>(path, options);
}

}  // namespace minibot3d_slam
