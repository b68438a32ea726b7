// slam_gmapping: the ROS face of the RBPF SLAM core (rbpf_slam.h), a drop-in for ROS gmapping's
// node. It converts scans and the odom → base tf into core calls, and the core's map and pose into
// the latched map/map_metadata, ~entropy, the map → odom tf and the dynamic_map service. All SLAM
// lives in the core; the parameters keep gmapping's names (gmapping_options.h, node_options.h;
// docs/parameters/slam.md). Its frames take the robot's frame_prefix when several robots share
// one tf tree (minibot3d_ros/frames.h).
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>

#include <geometry_msgs/TransformStamped.h>
#include <message_filters/subscriber.h>
#include <nav_msgs/GetMap.h>
#include <nav_msgs/MapMetaData.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>

#include "minibot3d_lockstep/participant.h"
#include "minibot3d_lockstep/transform_listener.h"
#include <sensor_msgs/LaserScan.h>
#include <std_msgs/Float64.h>
#include <tf2/utils.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>
#include <tf2_ros/transform_broadcaster.h>

#include "minibot3d_ros/conversions.h"
#include "minibot3d_ros/frames.h"
#include "minibot3d_ros/params.h"
#include "minibot3d_slam/gmapping_options.h"
#include "minibot3d_slam/node_options.h"
#include "minibot3d_slam/rbpf_slam.h"

namespace minibot3d_slam {
namespace {

using minibot3d_ros::PoseFromTransform;
using minibot3d_ros::YawToQuaternion;

class SlamGmappingNode {
 public:
  SlamGmappingNode()
      : pnh_("~"),
        lockstep_(nh_, LockstepOptions()),
        tf_listener_(tf_buffer_, lockstep_) {}

  // Woken by scans; the map -> odom broadcast is its periodic job.
  static minibot3d_lockstep::ParticipantOptions LockstepOptions() {
    minibot3d_lockstep::ParticipantOptions o;
    o.wake_topics = {"scan"};
    return o;
  }

  bool Spin() { return lockstep_.Spin(); }

  bool Init() {
    // gmapping's parameters and the node's own, each through its option table.
    GmappingOptions o;
    minibot3d_ros::ParamReport report = minibot3d_ros::LoadTable(pnh_, GmappingOptionTable(), &o);
    report.Also(minibot3d_ros::LoadTable(pnh_, SlamGmappingNodeOptionTable(), &node_));
    minibot3d_ros::FrameOptions frames;
    report.Also(minibot3d_ros::LoadFrameOptions(pnh_, &frames));
    report.WarnUnknown("slam_gmapping");
    std::string problems;
    const auto check = [&problems](const auto& validate) {
      try {
        validate();
      } catch (const std::invalid_argument& e) {
        problems += std::string("\n  ") + e.what();
      }
    };
    check([&] { report.ThrowIfBad(); });
    check([&] { ValidateOptions(o); });
    check([&] { ValidateSlamGmappingNodeOptions(node_); });
    if (!problems.empty()) {
      ROS_FATAL("slam_gmapping: bad parameters:%s", problems.c_str());
      return false;
    }
    // The config's frames are the robot's own; on a tf tree shared by several robots they carry
    // its frame_prefix (and so does the map frame, unless shared_frames lists it).
    const minibot3d_ros::FrameNames names(frames);
    node_.base_frame = names.Resolve(node_.base_frame);
    node_.odom_frame = names.Resolve(node_.odom_frame);
    node_.map_frame = names.Resolve(node_.map_frame);
    options_ = o;
    slam_ = std::make_unique<RbpfSlam>(options_);

    map_pub_ = nh_.advertise<nav_msgs::OccupancyGrid>("map", 1, true);
    meta_pub_ = nh_.advertise<nav_msgs::MapMetaData>("map_metadata", 1, true);
    entropy_pub_ = pnh_.advertise<std_msgs::Float64>("entropy", 1, true);
    map_service_ = lockstep_.ServiceHandle(nh_).advertiseService(
        "dynamic_map", &SlamGmappingNode::OnDynamicMap, this);
    scan_sub_.subscribe(nh_, "scan", 5);
    scan_filter_ = std::make_unique<tf2_ros::MessageFilter<sensor_msgs::LaserScan>>(
        scan_sub_, tf_buffer_, node_.odom_frame, 10, nh_);
    scan_filter_->registerCallback(&SlamGmappingNode::OnScan, this);
    scan_filter_->registerFailureCallback(
        [this](const sensor_msgs::LaserScan::ConstPtr& scan,
               tf2_ros::filter_failure_reasons::FilterFailureReason reason) {
          OnScanDropped(scan, reason);
        });
    if (node_.transform_publish_period > 0 && lockstep_.enabled()) {
      // Lock-step: sim time stands still while a scan is processed, so no thread is needed.
      lockstep_.AddPeriodic(node_.transform_publish_period,
                            [this](const ros::Time&) { PublishTransform(ros::TimerEvent()); });
    } else if (node_.transform_publish_period > 0) {
      // The map → odom broadcast has its own queue and thread, so tf keeps flowing while a scan
      // is being processed (the filter update is slow); scans stay in order on the main queue.
      tf_nh_.setCallbackQueue(&tf_queue_);
      tf_timer_ = tf_nh_.createTimer(ros::Duration(node_.transform_publish_period),
                                     &SlamGmappingNode::PublishTransform, this);
      tf_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &tf_queue_);
      tf_spinner_->start();
    }
    ROS_INFO("slam_gmapping: %d particles, delta %g m, maxUrange %g m, frames %s/%s/%s",
             options_.particles, options_.delta, options_.maxUrange, node_.map_frame.c_str(),
             node_.odom_frame.c_str(), node_.base_frame.c_str());
    return true;
  }

 private:
  void OnScanDropped(const sensor_msgs::LaserScan::ConstPtr& scan,
                     tf2_ros::filter_failure_reasons::FilterFailureReason) {
    ReportFrameOnce(scan->header.frame_id,
                    "no transform from " + node_.odom_frame + " to scan frame '" +
                        scan->header.frame_id + "' at the scan's time; check that the odometry "
                        "tf and robot_state_publisher are running");
  }

  void ReportFrameOnce(const std::string& frame, const std::string& message) {
    if (reported_frames_.insert(frame).second) ROS_WARN("slam_gmapping: %s", message.c_str());
  }

  void OnScan(const sensor_msgs::LaserScan::ConstPtr& msg) {
    if (++scan_count_ % node_.throttle_scans != 0) return;
    geometry_msgs::TransformStamped odom_base, base_laser;
    try {
      odom_base = lockstep_.LookupTransform(tf_buffer_, node_.odom_frame, node_.base_frame,
                                            msg->header.stamp, 0.1);
      base_laser = lockstep_.LookupTransform(tf_buffer_, node_.base_frame, msg->header.frame_id,
                                             msg->header.stamp, 0.1);
    } catch (const tf2::TransformException& e) {
      ReportFrameOnce(msg->header.frame_id, std::string("cannot place scan frame '") +
                                                msg->header.frame_id + "' relative to " +
                                                node_.base_frame + " and " + node_.odom_frame +
                                                ": " + e.what());
      return;
    }
    // A laser mounted upside down has its z axis pointing down: its angles run clockwise.
    tf2::Quaternion q;
    tf2::fromMsg(base_laser.transform.rotation, q);
    const bool upside_down = (tf2::Matrix3x3(q) * tf2::Vector3(0, 0, 1)).z() < 0;
    LaserScan scan;
    scan.time = msg->header.stamp.toSec();
    scan.range_min = msg->range_min;
    scan.range_max = msg->range_max;
    scan.sensor_in_base = PoseFromTransform(base_laser.transform);
    scan.ranges.resize(msg->ranges.size());
    scan.angles.resize(msg->ranges.size());
    for (std::size_t i = 0; i < msg->ranges.size(); ++i) {
      scan.ranges[i] = msg->ranges[i];
      const double a = msg->angle_min + i * msg->angle_increment;
      scan.angles[i] = upside_down ? -a : a;
    }
    if (upside_down) scan.sensor_in_base.yaw = -scan.sensor_in_base.yaw;  // see above
    const Pose2 odom = PoseFromTransform(odom_base.transform);
    bool processed = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      processed = slam_->AddScan(scan, odom);
      map_to_odom_ = slam_->MapToOdom();
      have_pose_ = true;
    }
    if (processed) {
      std_msgs::Float64 entropy;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        entropy.data = slam_->Entropy();
      }
      entropy_pub_.publish(entropy);
      // A loop closure rewrites the map and the pose: publish the corrected map at once.
      int closures;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        closures = slam_->loop_closures();
      }
      const bool corrected = closures != published_closures_;
      published_closures_ = closures;
      if (corrected || !got_map_ ||
          (msg->header.stamp - last_map_update_).toSec() >= node_.map_update_interval) {
        PublishMap(msg->header.stamp);
        last_map_update_ = msg->header.stamp;
        got_map_ = true;
      }
    }
  }

  void PublishMap(const ros::Time& stamp) {
    GridMap grid;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      grid = slam_->Map();
    }
    std::lock_guard<std::mutex> lock(map_mutex_);
    map_ = minibot3d_ros::GridToMsg(grid, node_.map_frame, stamp);
    map_pub_.publish(map_);
    meta_pub_.publish(map_.info);
  }

  void PublishTransform(const ros::TimerEvent&) {
    Pose2 m;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!have_pose_) return;
      m = map_to_odom_;
    }
    // Stamped ahead like gmapping, so consumers can transform data up to one period old.
    const ros::Time stamp = ros::Time::now() + ros::Duration(node_.transform_publish_period);
    // On sim time several callbacks can run at one ros::Time::now(): /clock moves in steps, and a
    // roscpp timer that fell behind by less than a period fires again at once. A second map ->
    // odom at the same stamp makes every tf listener drop it with TF_REPEATED_DATA, so it is not
    // sent. Only the timer's thread (or the lock-step periodic job) gets here.
    if (stamp == last_tf_stamp_) return;
    last_tf_stamp_ = stamp;
    geometry_msgs::TransformStamped t;
    t.header.stamp = stamp;
    t.header.frame_id = node_.map_frame;
    t.child_frame_id = node_.odom_frame;
    t.transform.translation.x = m.x;
    t.transform.translation.y = m.y;
    t.transform.rotation = YawToQuaternion(m.yaw);
    tf_broadcaster_.sendTransform(t);
  }

  bool OnDynamicMap(nav_msgs::GetMap::Request&, nav_msgs::GetMap::Response& res) {
    std::lock_guard<std::mutex> lock(map_mutex_);
    if (!got_map_) return false;  // as gmapping: no map yet
    res.map = map_;
    return true;
  }

  ros::NodeHandle nh_, pnh_, tf_nh_;
  minibot3d_lockstep::Participant lockstep_;
  ros::CallbackQueue tf_queue_;
  std::unique_ptr<ros::AsyncSpinner> tf_spinner_;
  GmappingOptions options_;
  SlamGmappingNodeOptions node_;
  std::unique_ptr<RbpfSlam> slam_;
  int published_closures_ = 0;  // loop closures already reflected in the published map
  tf2_ros::Buffer tf_buffer_;
  minibot3d_lockstep::TransformListener tf_listener_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  message_filters::Subscriber<sensor_msgs::LaserScan> scan_sub_;
  std::unique_ptr<tf2_ros::MessageFilter<sensor_msgs::LaserScan>> scan_filter_;
  ros::Publisher map_pub_, meta_pub_, entropy_pub_;
  ros::ServiceServer map_service_;
  ros::Timer tf_timer_;
  ros::Time last_tf_stamp_;  // of the last map -> odom sent (PublishTransform's thread only)
  std::mutex mutex_;      // the core and map_to_odom_
  std::mutex map_mutex_;  // map_
  Pose2 map_to_odom_;
  bool have_pose_ = false;
  nav_msgs::OccupancyGrid map_;
  bool got_map_ = false;
  ros::Time last_map_update_;
  unsigned long scan_count_ = 0;
  std::set<std::string> reported_frames_;
};

}  // namespace
}  // namespace minibot3d_slam

int main(int argc, char** argv) {
  ros::init(argc, argv, "slam_gmapping");
  minibot3d_slam::SlamGmappingNode node;
  if (!node.Init()) return 1;
  return node.Spin() ? 0 : 1;
}
