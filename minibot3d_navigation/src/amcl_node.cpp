// amcl: ROS 1 node wrapping the ROS-free AMCL core (minibot3d_amcl), a
// drop-in for the navigation stack's amcl: same parameters (private
// namespace), topics (scan, map, initialpose -> amcl_pose, particlecloud, tf
// map -> odom) and services (global_localization, request_nomotion_update,
// uses static_map).  Beyond amcl: amcl_pose's covariance is the filter's
// claim (it covers every mode and stays large until the filter is confident,
// amcl_filter.h), amcl/confidence says why (std_msgs/Float32MultiArray, one
// labelled dimension: explained_fraction, modes, confident, evidence_updates,
// beams_used, constraint), and global_localization runs the map-wide search, whose
// candidate poses (best first) are published latched on
// amcl/search_candidates (geometry_msgs/PoseArray; scores in the log).
// Its frame parameters take the robot's frame_prefix when several robots
// share one tf tree (minibot3d_ros/frames.h). All estimation logic lives in
// the core; this file only converts messages and transforms.
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <message_filters/subscriber.h>
#include <nav_msgs/GetMap.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <std_msgs/Float32MultiArray.h>
#include <std_srvs/Empty.h>
#include <tf2/LinearMath/Matrix3x3.h>
#include <tf2/LinearMath/Quaternion.h>
#include <tf2/LinearMath/Transform.h>
#include <tf2/utils.h>
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>
#include <tf2_ros/transform_broadcaster.h>

#include "minibot3d_lockstep/participant.h"
#include "minibot3d_lockstep/transform_listener.h"
#include "minibot3d_navigation/amcl/amcl_filter.h"
#include "minibot3d_navigation/amcl/amcl_options.h"
#include "minibot3d_ros/conversions.h"
#include "minibot3d_ros/frames.h"
#include "minibot3d_ros/params.h"

namespace amcl = minibot3d_navigation::amcl;

namespace {

using minibot3d_ros::GridFromMsg;
using minibot3d_ros::PoseFromTf;
using minibot3d_ros::TfFromPose;

class AmclNode {
 public:
  AmclNode()
      : pnh_("~"),
        lockstep_(nh_, LockstepOptions()),
        tf_listener_(tf_buffer_, lockstep_) {}

  // Woken by scans, pose resets and maps; amcl has no periodic work of its own.
  static minibot3d_lockstep::ParticipantOptions LockstepOptions() {
    minibot3d_lockstep::ParticipantOptions o;
    o.wake_topics = {"scan", "initialpose", "map"};
    return o;
  }

  bool Spin() { return lockstep_.Spin(); }

  // Reads and validates the parameters (every bad one named); false (after ROS_FATAL) on error.
  bool Configure() {
    minibot3d_ros::ParamReport report = minibot3d_ros::LoadTable(pnh_, amcl::AmclOptionTable(), &options_);
    report.Also(minibot3d_ros::LoadTable(pnh_, amcl::AmclNodeOptionTable(), &node_));
    minibot3d_ros::FrameOptions frames;
    report.Also(minibot3d_ros::LoadFrameOptions(pnh_, &frames));
    try {
      report.ThrowIfBad();
      amcl::ValidateAmclOptions(options_);
      amcl::ValidateAmclNodeOptions(node_);
    } catch (const std::invalid_argument& e) {
      ROS_FATAL("amcl: %s", e.what());
      return false;
    }
    report.WarnUnknown("amcl");
    // The config's frames are the robot's own; on a tf tree shared by several robots they carry
    // its frame_prefix (the map, shared, does not).
    const minibot3d_ros::FrameNames names(frames);
    node_.base_frame_id = names.Resolve(node_.base_frame_id);
    node_.odom_frame_id = names.Resolve(node_.odom_frame_id);
    node_.global_frame_id = names.Resolve(node_.global_frame_id);
    if (!names.prefix().empty()) {
      ROS_INFO("amcl: frames %s -> %s -> %s (frame_prefix %s)", node_.global_frame_id.c_str(),
               node_.odom_frame_id.c_str(), node_.base_frame_id.c_str(), names.prefix().c_str());
    }
    transform_tolerance_ = ros::Duration(node_.transform_tolerance);
    return true;
  }

  void Start() {
    pose_pub_ = nh_.advertise<geometry_msgs::PoseWithCovarianceStamped>("amcl_pose", 2, true);
    cloud_pub_ = nh_.advertise<geometry_msgs::PoseArray>("particlecloud", 2, true);
    confidence_pub_ = nh_.advertise<std_msgs::Float32MultiArray>("amcl/confidence", 2, true);
    candidates_pub_ = nh_.advertise<geometry_msgs::PoseArray>("amcl/search_candidates", 1, true);
    // Other participants call these while they work: answered between ticks too.
    ros::NodeHandle snh = lockstep_.ServiceHandle(nh_);
    global_srv_ = snh.advertiseService("global_localization", &AmclNode::OnGlobal, this);
    nomotion_srv_ =
        snh.advertiseService("request_nomotion_update", &AmclNode::OnNoMotion, this);
    initial_sub_ = nh_.subscribe("initialpose", 2, &AmclNode::OnInitialPose, this);
    scan_sub_.subscribe(nh_, "scan", 100);
    scan_filter_.reset(new tf2_ros::MessageFilter<sensor_msgs::LaserScan>(
        scan_sub_, tf_buffer_, node_.odom_frame_id, 100, nh_));
    scan_filter_->registerCallback(&AmclNode::OnScan, this);
    scan_filter_->registerFailureCallback(
        [](const sensor_msgs::LaserScan::ConstPtr& s,
           tf2_ros::filter_failure_reasons::FilterFailureReason) {
          ROS_WARN_THROTTLE(5.0, "amcl: no transform yet from scan frame '%s' at %.3f",
                            s->header.frame_id.c_str(), s->header.stamp.toSec());
        });
    if (node_.save_pose_rate > 0.0) {
      save_timer_ = nh_.createWallTimer(ros::WallDuration(1.0 / node_.save_pose_rate),
                                        &AmclNode::SavePose, this);
    }
    if (node_.use_map_topic) {
      map_sub_ = nh_.subscribe("map", 1, &AmclNode::OnMap, this);
      ROS_INFO("amcl: waiting for a map on %s", map_sub_.getTopic().c_str());
    } else {
      RequestMap();
    }
  }

 private:
  void RequestMap() {
    nav_msgs::GetMap srv;
    while (ros::ok()) {
      if (ros::service::waitForService("static_map", ros::Duration(1.0)) &&
          ros::service::call("static_map", srv)) {
        break;
      }
      ROS_WARN_THROTTLE(5.0, "amcl: request for map failed; trying again (static_map service)");
    }
    if (!ros::ok()) return;
    HandleMap(srv.response.map);
  }

  void OnMap(const nav_msgs::OccupancyGrid::ConstPtr& msg) {
    if (node_.first_map_only && filter_) return;
    HandleMap(*msg);
  }

  void HandleMap(const nav_msgs::OccupancyGrid& msg) {
    if (!msg.header.frame_id.empty() && msg.header.frame_id != node_.global_frame_id) {
      ROS_WARN("amcl: map frame '%s' differs from global_frame_id '%s'",
               msg.header.frame_id.c_str(), node_.global_frame_id.c_str());
    }
    const amcl::OccupancyGrid grid = GridFromMsg(msg);
    try {
      if (!filter_) {
        filter_.reset(new amcl::AmclFilter(options_, grid,
                                           amcl::AmclFilter::Initialization::kFromOptions));
      } else {
        filter_->SetMap(grid);
      }
    } catch (const std::invalid_argument& e) {
      if (!filter_) {
        ROS_FATAL("amcl: cannot initialise on the map: %s", e.what());
        ros::shutdown();
        std::exit(1);
      }
      ROS_ERROR("amcl: new map rejected, keeping the old one: %s", e.what());
      return;
    }
    ROS_INFO("amcl: map %dx%d @ %.3f m; %zu particles", grid.width, grid.height,
             grid.resolution, filter_->particles().size());
    if (filter_->global_search() == nullptr) {
      ROS_WARN("amcl: global localization will spread particles uniformly, no map-wide search: %s",
               filter_->global_search_fallback().c_str());
    }
    have_odom_tf_ = false;
    filter_->RequestNoMotionUpdate();
  }

  // Laser pose in the base frame, cached per frame id.  Handles lasers mounted
  // upside down (z axis pointing down): the bearings are then mirrored.
  bool LaserPose(const std::string& frame, amcl::Pose2* pose, bool* flipped) {
    auto it = laser_poses_.find(frame);
    if (it == laser_poses_.end()) {
      geometry_msgs::TransformStamped t;
      try {
        t = tf_buffer_.lookupTransform(node_.base_frame_id, frame, ros::Time(0));
      } catch (const tf2::TransformException& e) {
        ROS_WARN_THROTTLE(5.0, "amcl: no transform from base frame '%s' to scan frame '%s': %s",
                          node_.base_frame_id.c_str(), frame.c_str(), e.what());
        return false;
      }
      tf2::Transform tr;
      tf2::fromMsg(t.transform, tr);
      const tf2::Matrix3x3& r = tr.getBasis();
      LaserMount m;
      m.flipped = r[2][2] < 0.0;
      // Yaw of the laser's x axis projected onto the base plane.
      m.pose = {tr.getOrigin().x(), tr.getOrigin().y(), std::atan2(r[1][0], r[0][0])};
      it = laser_poses_.emplace(frame, m).first;
    }
    *pose = it->second.pose;
    *flipped = it->second.flipped;
    return true;
  }

  void OnScan(const sensor_msgs::LaserScan::ConstPtr& msg) {
    if (!filter_) return;
    // Global localization is about where the robot is now: a scan taken before the request
    // (still queued for its transform) may show another place (the robot was carried).
    if (msg->header.stamp < global_request_stamp_) return;
    amcl::LaserScan scan;
    bool flipped = false;
    if (!LaserPose(msg->header.frame_id, &scan.sensor_in_base, &flipped)) return;
    geometry_msgs::TransformStamped odom_base;
    try {
      odom_base = tf_buffer_.lookupTransform(node_.odom_frame_id, node_.base_frame_id, msg->header.stamp);
    } catch (const tf2::TransformException& e) {
      ROS_WARN_THROTTLE(5.0, "amcl: no odometry (%s <- %s) at the scan time: %s",
                        node_.odom_frame_id.c_str(), node_.base_frame_id.c_str(), e.what());
      return;
    }
    tf2::Transform ob;
    tf2::fromMsg(odom_base.transform, ob);
    const amcl::Pose2 odom_pose = PoseFromTf(ob);
    scan.ranges.assign(msg->ranges.begin(), msg->ranges.end());
    scan.angles = amcl::MakeBeamAngles(msg->angle_min, msg->angle_increment,
                                       static_cast<int>(msg->ranges.size()));
    if (flipped) {
      for (double& a : scan.angles) a = -a;
    }
    scan.range_min = msg->range_min;
    scan.range_max = msg->range_max;

    const amcl::UpdateResult r = filter_->Update(odom_pose, scan);
    ReportSearch(msg->header.stamp);
    switch (r.status) {
      case amcl::UpdateStatus::kUpdated:
      case amcl::UpdateStatus::kMotionOnly:
        if (r.status == amcl::UpdateStatus::kMotionOnly) {
          ROS_WARN_THROTTLE(5.0, "amcl: motion-only update: %s", r.message.c_str());
        }
        PublishPose(msg->header.stamp);
        PublishCloud(msg->header.stamp, r.resampled);
        break;
      case amcl::UpdateStatus::kSkippedNoMotion:
        break;
      default:
        ROS_WARN_THROTTLE(5.0, "amcl: %s: %s", amcl::UpdateStatusName(r.status),
                          r.message.c_str());
        break;
    }
    if (filter_->has_odom_reference()) {
      // map <- odom = (map <- base) * (odom <- base)^-1, base at the last update.
      map_odom_ = TfFromPose(filter_->estimate().mean) *
                  TfFromPose(filter_->odom_reference()).inverse();
      have_odom_tf_ = true;
    }
    if (have_odom_tf_ && node_.tf_broadcast) {
      geometry_msgs::TransformStamped t;
      t.header.stamp = msg->header.stamp + transform_tolerance_;
      t.header.frame_id = node_.global_frame_id;
      t.child_frame_id = node_.odom_frame_id;
      t.transform = tf2::toMsg(map_odom_);
      tf_broadcaster_.sendTransform(t);
    }
  }

  void PublishPose(const ros::Time& stamp) {
    const amcl::PoseEstimate& e = filter_->estimate();
    geometry_msgs::PoseWithCovarianceStamped p;
    p.header.stamp = stamp;
    p.header.frame_id = node_.global_frame_id;
    p.pose.pose.position.x = e.mean.x;
    p.pose.pose.position.y = e.mean.y;
    tf2::Quaternion q;
    q.setRPY(0, 0, e.mean.yaw);
    p.pose.pose.orientation = tf2::toMsg(q);
    const int idx[3] = {0, 1, 5};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        p.pose.covariance[idx[i] * 6 + idx[j]] = e.claim_covariance(i, j);
    pose_pub_.publish(p);
    last_pose_ = p;
    have_last_pose_ = true;
    PublishConfidence();
    ReportClaim(stamp);
  }

  // Logs each change of the claim: the pose users start to trust (or stop trusting).
  void ReportClaim(const ros::Time& stamp) {
    const amcl::Confidence& c = filter_->confidence();
    if (c.confident == claimed_) return;
    claimed_ = c.confident;
    const amcl::PoseEstimate& e = filter_->estimate();
    if (c.confident) {
      ROS_INFO("amcl: confident at (%.2f, %.2f, %.3f) at %.3f: %d explained one-mode updates, "
               "%.0f%% of %d beams explained, constraint %.2f in the weakest direction",
               e.mean.x, e.mean.y, e.mean.yaw, stamp.toSec(), c.evidence_updates,
               100.0 * c.explained_fraction, c.beams_used, c.constraint);
    } else {
      ROS_INFO("amcl: no longer confident at (%.2f, %.2f, %.3f) at %.3f: %d mode(s), %.0f%% of "
               "%d beams explained", e.mean.x, e.mean.y, e.mean.yaw, stamp.toSec(), c.modes,
               100.0 * c.explained_fraction, c.beams_used);
    }
  }

  void PublishConfidence() {
    const amcl::Confidence& c = filter_->confidence();
    std_msgs::Float32MultiArray m;
    m.layout.dim.resize(1);
    m.layout.dim[0].label =
        "explained_fraction,modes,confident,evidence_updates,beams_used,constraint";
    m.layout.dim[0].size = 6;
    m.layout.dim[0].stride = 6;
    m.data = {static_cast<float>(c.explained_fraction), static_cast<float>(c.modes),
              c.confident ? 1.0f : 0.0f, static_cast<float>(c.evidence_updates),
              static_cast<float>(c.beams_used), static_cast<float>(c.constraint)};
    confidence_pub_.publish(m);
  }

  // Logs a map-wide search the last update ran and publishes its candidates.
  void ReportSearch(const ros::Time& stamp) {
    const amcl::SearchReport& s = filter_->last_search();
    if (s.count == reported_searches_) return;
    reported_searches_ = s.count;
    std::ostringstream os;
    geometry_msgs::PoseArray a;
    a.header.stamp = stamp;
    a.header.frame_id = node_.global_frame_id;
    for (const amcl::SearchCandidate& c : s.candidates) {
      os << " (" << c.pose.x << ", " << c.pose.y << ", " << c.pose.yaw << ": " << c.score << ")";
      a.poses.push_back(PoseMsg(c.pose));
    }
    candidates_pub_.publish(a);
    ROS_INFO("amcl: map-wide search (%s) in %.3f s CPU (%.3f s wall): %zu candidate(s)%s",
             s.challenge ? "look-alikes before a claim"
             : s.found_by_injection ? "a place found by random draws explains the scan"
             : s.relocalization ? "no hypothesis explains the scan" : "global localization",
             s.cpu_seconds, s.seconds, s.candidates.size(), os.str().c_str());
    if (s.cpu_seconds > options_.global_search_budget) {
      ROS_WARN("amcl: the map-wide search took %.2f s CPU, over global_search_budget=%.2f s",
               s.cpu_seconds, options_.global_search_budget);
    }
  }

  void PublishCloud(const ros::Time& stamp, bool force) {
    // Throttled on sim time (the scan's stamp), as ROS amcl does: the same clouds in every run.
    if (!force && node_.gui_publish_rate > 0.0 && !last_cloud_.isZero() && stamp >= last_cloud_ &&
        (stamp - last_cloud_).toSec() < 1.0 / node_.gui_publish_rate) {
      return;
    }
    last_cloud_ = stamp;
    geometry_msgs::PoseArray a;
    a.header.stamp = stamp;
    a.header.frame_id = node_.global_frame_id;
    a.poses.resize(filter_->particles().size());
    for (size_t k = 0; k < a.poses.size(); ++k) {
      a.poses[k] = PoseMsg(filter_->particles()[k].pose);
    }
    cloud_pub_.publish(a);
  }

  static geometry_msgs::Pose PoseMsg(const amcl::Pose2& p) {
    geometry_msgs::Pose m;
    m.position.x = p.x;
    m.position.y = p.y;
    tf2::Quaternion q;
    q.setRPY(0, 0, p.yaw);
    m.orientation = tf2::toMsg(q);
    return m;
  }

  void OnInitialPose(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& msg) {
    if (!filter_) {
      ROS_WARN("amcl: initial pose received before the map: ignored");
      return;
    }
    tf2::Transform pose;
    tf2::fromMsg(msg->pose.pose, pose);
    const std::string frame = msg->header.frame_id.empty() ? node_.global_frame_id : msg->header.frame_id;
    double rot = 0.0;
    if (frame != node_.global_frame_id) {
      try {
        geometry_msgs::TransformStamped t =
            lockstep_.LookupTransform(tf_buffer_, node_.global_frame_id, frame, msg->header.stamp, 0.5);
        tf2::Transform tr;
        tf2::fromMsg(t.transform, tr);
        pose = tr * pose;
        rot = tf2::getYaw(tr.getRotation());
      } catch (const tf2::TransformException& e) {
        ROS_WARN("amcl: initial pose in frame '%s' cannot be transformed into '%s': %s",
                 frame.c_str(), node_.global_frame_id.c_str(), e.what());
        return;
      }
    }
    const amcl::Pose2 mean = PoseFromTf(pose);
    Eigen::Matrix3d cov;
    const int idx[3] = {0, 1, 5};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) cov(i, j) = msg->pose.covariance[idx[i] * 6 + idx[j]];
    if (rot != 0.0) {  // rotate the x/y block into the global frame
      Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
      R(0, 0) = std::cos(rot); R(0, 1) = -std::sin(rot);
      R(1, 0) = std::sin(rot); R(1, 1) = std::cos(rot);
      cov = R * cov * R.transpose();
    }
    cov = 0.5 * (cov + cov.transpose());
    try {
      filter_->SetPose(mean, cov);
    } catch (const std::invalid_argument& e) {
      ROS_WARN("amcl: initial pose (%.3f, %.3f, %.3f) rejected, filter unchanged: %s", mean.x,
               mean.y, mean.yaw, e.what());
      return;
    }
    ROS_INFO("amcl: initial pose set to (%.3f, %.3f, %.3f)", mean.x, mean.y, mean.yaw);
    filter_->RequestNoMotionUpdate();
    PublishPose(msg->header.stamp.isZero() ? ros::Time::now() : msg->header.stamp);
  }

  bool OnGlobal(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    if (!filter_) return false;
    filter_->GlobalLocalization();
    filter_->RequestNoMotionUpdate();
    global_request_stamp_ = ros::Time::now();
    if (filter_->global_search() != nullptr) {
      ROS_INFO("amcl: global localization: the next scan is searched for over the whole map");
    } else {
      ROS_WARN("amcl: global localization: %zu particles over free space, no map-wide search: %s",
               filter_->particles().size(), filter_->global_search_fallback().c_str());
    }
    return true;
  }

  bool OnNoMotion(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    if (filter_) filter_->RequestNoMotionUpdate();
    return true;
  }

  // amcl's save_pose_rate: the last estimate goes to ~initial_pose_* and
  // ~initial_cov_* so a restart resumes from it.
  void SavePose(const ros::WallTimerEvent&) {
    if (!filter_ || !have_last_pose_) return;
    const amcl::PoseEstimate& e = filter_->estimate();
    pnh_.setParam("initial_pose_x", e.mean.x);
    pnh_.setParam("initial_pose_y", e.mean.y);
    pnh_.setParam("initial_pose_a", e.mean.yaw);
    pnh_.setParam("initial_cov_xx", e.claim_covariance(0, 0));
    pnh_.setParam("initial_cov_yy", e.claim_covariance(1, 1));
    pnh_.setParam("initial_cov_aa", e.claim_covariance(2, 2));
  }

  struct LaserMount {
    amcl::Pose2 pose;
    bool flipped = false;
  };

  ros::NodeHandle nh_;
  ros::NodeHandle pnh_;
  minibot3d_lockstep::Participant lockstep_;
  tf2_ros::Buffer tf_buffer_;
  minibot3d_lockstep::TransformListener tf_listener_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;

  amcl::AmclOptions options_;
  amcl::AmclNodeOptions node_;
  ros::Duration transform_tolerance_;

  std::unique_ptr<amcl::AmclFilter> filter_;
  std::map<std::string, LaserMount> laser_poses_;
  tf2::Transform map_odom_;
  bool have_odom_tf_ = false;
  geometry_msgs::PoseWithCovarianceStamped last_pose_;
  bool have_last_pose_ = false;
  bool claimed_ = false;  // the last published claim was confident
  ros::Time last_cloud_;

  int reported_searches_ = 0;
  ros::Time global_request_stamp_;  // scans older than the last global_localization are dropped
  ros::Publisher pose_pub_, cloud_pub_, confidence_pub_, candidates_pub_;
  ros::Subscriber initial_sub_, map_sub_;
  ros::ServiceServer global_srv_, nomotion_srv_;
  ros::WallTimer save_timer_;
  message_filters::Subscriber<sensor_msgs::LaserScan> scan_sub_;
  std::unique_ptr<tf2_ros::MessageFilter<sensor_msgs::LaserScan>> scan_filter_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "amcl");
  AmclNode node;
  if (!node.Configure()) return 1;
  node.Start();
  return node.Spin() ? 0 : 1;
}
