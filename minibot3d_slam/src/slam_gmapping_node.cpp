// slam_gmapping: the ROS face of the RBPF SLAM core (rbpf_slam.h), a drop-in for ROS gmapping's
// node. It converts scans and the odom → base tf into core calls, and the core's map and pose into
// the latched map/map_metadata, ~entropy, the map → odom tf and the dynamic_map service. All SLAM
// lives in the core; the parameters keep gmapping's names.
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>

#include <geometry_msgs/TransformStamped.h>
#include <message_filters/subscriber.h>
#include <nav_msgs/GetMap.h>
#include <nav_msgs/MapMetaData.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>

#include "minibot3d_lockstep/participant.h"
#include <sensor_msgs/LaserScan.h>
#include <std_msgs/Float64.h>
#include <tf2/utils.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include "minibot3d_slam/gmapping_options.h"
#include "minibot3d_slam/rbpf_slam.h"

namespace minibot3d_slam {
namespace {

Pose2 ToPose2(const geometry_msgs::Transform& t) {
  return Pose2{t.translation.x, t.translation.y, tf2::getYaw(t.rotation)};
}

geometry_msgs::Quaternion YawQuaternion(double yaw) {
  geometry_msgs::Quaternion q;
  q.z = std::sin(yaw / 2);
  q.w = std::cos(yaw / 2);
  return q;
}

// The node's own parameters (the core's are in GmappingOptions).
struct NodeOptions {
  std::string base_frame = "base_link";
  std::string odom_frame = "odom";
  std::string map_frame = "map";
  double map_update_interval = 5.0;        // s between map publications
  double transform_publish_period = 0.05;  // s; 0 disables the map → odom broadcast
  int throttle_scans = 1;                  // process one scan in this many
  double tf_delay = 0.0;                   // unused by us; accepted for gmapping YAMLs
};

class SlamGmappingNode {
 public:
  SlamGmappingNode()
      : pnh_("~"),
        lockstep_(nh_, LockstepOptions()),
        tf_listener_(tf_buffer_, lockstep_.tf_node_handle(), !lockstep_.enabled()) {}

  // Woken by scans; the map -> odom broadcast is its periodic job.
  static minibot3d_lockstep::ParticipantOptions LockstepOptions() {
    minibot3d_lockstep::ParticipantOptions o;
    o.wake_topics = {"scan"};
    return o;
  }

  bool Spin() { return lockstep_.Spin(); }

  bool Init() {
    // gmapping's parameters, read into the core's options and validated in one place.
    GmappingOptions o;
    auto get_d = [&](const char* name, double* v) { pnh_.param(name, *v, *v); };
    auto get_i = [&](const char* name, int* v) { pnh_.param(name, *v, *v); };
    get_i("particles", &o.particles);
    get_d("resampleThreshold", &o.resampleThreshold);
    get_d("srr", &o.srr);
    get_d("srt", &o.srt);
    get_d("str", &o.str);
    get_d("stt", &o.stt);
    get_d("linearUpdate", &o.linearUpdate);
    get_d("angularUpdate", &o.angularUpdate);
    get_d("temporalUpdate", &o.temporalUpdate);
    get_d("sigma", &o.sigma);
    get_i("kernelSize", &o.kernelSize);
    get_d("lstep", &o.lstep);
    get_d("astep", &o.astep);
    get_i("iterations", &o.iterations);
    get_d("lsigma", &o.lsigma);
    get_d("ogain", &o.ogain);
    get_i("lskip", &o.lskip);
    get_d("minimumScore", &o.minimumScore);
    get_d("llsamplerange", &o.llsamplerange);
    get_d("llsamplestep", &o.llsamplestep);
    get_d("lasamplerange", &o.lasamplerange);
    get_d("lasamplestep", &o.lasamplestep);
    get_d("delta", &o.delta);
    get_d("maxUrange", &o.maxUrange);
    get_d("maxRange", &o.maxRange);
    get_i("clearMaxRange", &o.clearMaxRange);
    get_d("xmin", &o.xmin);
    get_d("ymin", &o.ymin);
    get_d("xmax", &o.xmax);
    get_d("ymax", &o.ymax);
    get_d("occ_thresh", &o.occ_thresh);
    get_i("subcellMatch", &o.subcellMatch);
    get_i("sampleProposal", &o.sampleProposal);
    get_i("loopClosure", &o.loopClosure);
    get_d("loopSearchWindow", &o.loopSearchWindow);
    get_d("loopDriftRate", &o.loopDriftRate);
    get_d("loopMaxSearchWindow", &o.loopMaxSearchWindow);
    get_i("loopCorridors", &o.loopCorridors);
    get_d("loopSearchAngle", &o.loopSearchAngle);
    get_d("loopMinScore", &o.loopMinScore);
    get_i("loopSubmapScans", &o.loopSubmapScans);
    get_d("loopMinTravel", &o.loopMinTravel);
    get_i("threads", &o.threads);
    int seed = 0;
    get_i("seed", &seed);
    o.seed = static_cast<unsigned>(seed);
    pnh_.param("base_frame", node_.base_frame, node_.base_frame);
    pnh_.param("odom_frame", node_.odom_frame, node_.odom_frame);
    pnh_.param("map_frame", node_.map_frame, node_.map_frame);
    pnh_.param("map_update_interval", node_.map_update_interval, node_.map_update_interval);
    pnh_.param("transform_publish_period", node_.transform_publish_period,
               node_.transform_publish_period);
    pnh_.param("throttle_scans", node_.throttle_scans, node_.throttle_scans);
    pnh_.param("tf_delay", node_.tf_delay, node_.tf_delay);
    std::string problems;
    if (node_.throttle_scans < 1) {
      problems += " throttle_scans must be >= 1 (got " + std::to_string(node_.throttle_scans) + ");";
    }
    if (node_.map_update_interval <= 0) {
      problems += " map_update_interval must be > 0 (got " +
                  std::to_string(node_.map_update_interval) + ");";
    }
    if (node_.transform_publish_period < 0) {
      problems += " transform_publish_period must be >= 0 (got " +
                  std::to_string(node_.transform_publish_period) + ");";
    }
    try {
      ValidateOptions(o);
    } catch (const std::invalid_argument& e) {
      problems += std::string(" ") + e.what();
    }
    if (!problems.empty()) {
      ROS_FATAL("slam_gmapping: bad parameters:%s", problems.c_str());
      return false;
    }
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
    scan.sensor_in_base = ToPose2(base_laser.transform);
    scan.ranges.resize(msg->ranges.size());
    scan.angles.resize(msg->ranges.size());
    for (std::size_t i = 0; i < msg->ranges.size(); ++i) {
      scan.ranges[i] = msg->ranges[i];
      const double a = msg->angle_min + i * msg->angle_increment;
      scan.angles[i] = upside_down ? -a : a;
    }
    if (upside_down) scan.sensor_in_base.yaw = -scan.sensor_in_base.yaw;  // see above
    const Pose2 odom = ToPose2(odom_base.transform);
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
    map_.header.stamp = stamp;
    map_.header.frame_id = node_.map_frame;
    map_.info.map_load_time = stamp;
    map_.info.resolution = grid.resolution;
    map_.info.width = grid.width;
    map_.info.height = grid.height;
    map_.info.origin.position.x = grid.origin_x;
    map_.info.origin.position.y = grid.origin_y;
    map_.info.origin.orientation = YawQuaternion(grid.origin_theta);
    map_.data.assign(grid.data.begin(), grid.data.end());
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
    t.transform.rotation = YawQuaternion(m.yaw);
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
  NodeOptions node_;
  std::unique_ptr<RbpfSlam> slam_;
  int published_closures_ = 0;  // loop closures already reflected in the published map
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
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
