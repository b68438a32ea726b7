#include "robot_interface.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <geometry_msgs/TransformStamped.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <urdf/model.h>

#include "minibot3d_ros/conversions.h"

namespace minibot3d_sim {
namespace {

nav_msgs::Odometry MakeOdometry(const ros::Time& stamp, const std::string& frame,
                                const std::string& child, const Pose2& pose, const Twist2& twist) {
  nav_msgs::Odometry m;
  m.header.stamp = stamp;
  m.header.frame_id = frame;
  m.child_frame_id = child;
  m.pose.pose.position.x = pose.x;
  m.pose.pose.position.y = pose.y;
  m.pose.pose.orientation = minibot3d_ros::YawToQuaternion(pose.yaw);
  m.twist.twist.linear.x = twist.vx;
  m.twist.twist.linear.y = twist.vy;
  m.twist.twist.angular.z = twist.wz;
  return m;
}

// tf frame names have no leading slash.
std::string Bare(const std::string& name) {
  return !name.empty() && name[0] == '/' ? name.substr(1) : name;
}

geometry_msgs::Quaternion ToMsg(const Eigen::Quaterniond& q) {
  geometry_msgs::Quaternion m;
  m.x = q.x();
  m.y = q.y();
  m.z = q.z();
  m.w = q.w();
  return m;
}

}  // namespace

std::string RobotInterface::Frame(const std::string& name) const {
  const std::string bare = Bare(name);
  if (options_.frame_prefix.empty() || bare.empty() || bare == options_.world_frame) return bare;
  return options_.frame_prefix + bare;
}

std::string RobotInterface::Resolve(const std::string& ns, const std::string& topic) {
  if (!topic.empty() && topic[0] == '/') return topic;
  std::string prefix = ns.empty() ? "/" : ns;
  if (prefix[0] != '/') prefix = "/" + prefix;
  if (prefix.back() != '/') prefix += "/";
  return prefix + topic;
}

RobotInterface::RobotInterface(SimRobot* sim_robot, const std::string& urdf_xml,
                               const Options& options, ros::CallbackQueue* cmd_queue)
    : robot_(sim_robot), options_(options) {
  const RobotModel& robot = robot_->model();
  const DriveInterface& d = robot_->drive().interface();
  // Joint states: the driven wheels first (their positions and speeds), then every other movable
  // joint robot_state_publisher needs (casters, ...) at 0.
  for (const auto& w : robot.wheels) joint_state_.name.push_back(w.joint);
  for (const auto& j : robot.joints) {
    bool wheel = false;
    for (const auto& w : robot.wheels) wheel |= w.joint == j.name;
    if (!wheel) joint_state_.name.push_back(j.name);
  }
  joint_state_.position.assign(joint_state_.name.size(), 0.0);
  joint_state_.velocity.assign(joint_state_.name.size(), 0.0);
  // The robot's fixed joints, for tf_static: published by the simulator too (see
  // AppendStaticTransforms), so they are there when sim time starts.
  urdf::Model model;
  model.initString(urdf_xml);
  for (const auto& j : model.joints_) {
    if (j.second->type != urdf::Joint::FIXED) continue;
    const urdf::Pose& o = j.second->parent_to_joint_origin_transform;
    geometry_msgs::TransformStamped t;
    t.header.frame_id = Frame(j.second->parent_link_name);
    t.child_frame_id = Frame(j.second->child_link_name);
    t.transform.translation.x = o.position.x;
    t.transform.translation.y = o.position.y;
    t.transform.translation.z = o.position.z;
    t.transform.rotation.x = o.rotation.x;
    t.transform.rotation.y = o.rotation.y;
    t.transform.rotation.z = o.rotation.z;
    t.transform.rotation.w = o.rotation.w;
    static_tf_.transforms.push_back(t);
  }

  odom_period_ = d.odometry_rate > 0 ? 1.0 / d.odometry_rate : robot_->physics_step();
  // Joint states go out with the odometry unless the drive publishes them at a rate of its own.
  joints_with_odometry_ = d.joint_state_topic.empty();
  joint_period_ = d.joint_state_rate > 0 ? 1.0 / d.joint_state_rate : odom_period_;
  // In lock-step a participant counts on receiving every message the simulator queued to it, so
  // outgoing queues must not drop: roscpp drops the oldest message when a subscriber's socket is
  // backed up past the queue size. Free-running keeps small queues.
  const auto q = [this](int free_running) { return options_.lockstep ? 100000 : free_running; };
  const std::string& ns = d.robot_namespace;
  if (!d.odometry_topic.empty()) {
    odom_pub_ = nh_.advertise<nav_msgs::Odometry>(Resolve(ns, d.odometry_topic), q(20));
  }
  tf_pub_ = nh_.advertise<tf2_msgs::TFMessage>("/tf", q(100));
  joint_pub_ = nh_.advertise<sensor_msgs::JointState>(Resolve(ns, "joint_states"), q(20));
  if (options_.publish_ground_truth) {
    truth_pub_ = nh_.advertise<nav_msgs::Odometry>(Resolve(ns, "ground_truth/odom"), q(20));
  }
  for (size_t i = 0; i < robot.lasers.size(); ++i) {
    const LaserSpec& l = robot.lasers[i];
    scan_pubs_.push_back(nh_.advertise<sensor_msgs::LaserScan>(Resolve(l.robot_namespace, l.topic), q(5)));
    sensor_msgs::LaserScan scan;
    scan.header.frame_id = Frame(l.frame_id);
    scan.angle_min = l.min_angle;
    scan.angle_max = l.max_angle;
    scan.angle_increment = robot_->lidar(i).angle_increment();
    scan.time_increment = 0.0;  // every beam of a simulated scan is taken at the same instant
    scan.scan_time = l.update_rate > 0 ? 1.0 / l.update_rate : robot_->physics_step();
    scan.range_min = l.min_range;
    scan.range_max = l.max_range;
    scans_.push_back(scan);
  }
  for (const auto& imu : robot.imus) {
    imu_pubs_.push_back(nh_.advertise<sensor_msgs::Imu>(Resolve(imu.robot_namespace, imu.topic), q(20)));
  }
  for (const auto& g : robot.ground_truths) {
    gt_pubs_.push_back(
        nh_.advertise<nav_msgs::Odometry>(Resolve(g.robot_namespace, g.options.topic_name), q(20)));
  }
  cameras_.resize(robot.cameras.size());
  for (size_t i = 0; i < robot.cameras.size(); ++i) SetUpCamera(i);
  // Commands have their own queue: in lock-step they are applied once every participant's
  // messages have arrived, never in the middle of a round.
  ros::NodeHandle cmd_nh(nh_);
  cmd_nh.setCallbackQueue(cmd_queue);
  cmd_sub_ = cmd_nh.subscribe(Resolve(ns, d.command_topic), 5, &RobotInterface::OnCommand, this,
                              ros::TransportHints().tcpNoDelay());
}

void RobotInterface::OnCommand(const ros::MessageEvent<const geometry_msgs::Twist>& event) {
  const geometry_msgs::Twist::ConstPtr& msg = event.getConstMessage();
  const double vx = msg->linear.x, vy = msg->linear.y, w = msg->angular.z;
  if (!std::isfinite(vx) || !std::isfinite(vy) || !std::isfinite(w)) {
    ROS_WARN_THROTTLE(2.0, "minibot3d_sim: ignoring cmd_vel with non-finite linear.x=%g "
                      "linear.y=%g angular.z=%g from %s", vx, vy, w,
                      event.getPublisherName().c_str());
    return;
  }
  robot_->Command(Twist2{vx, vy, w});
}

void RobotInterface::Publish(bool all) {
  const double t = robot_->time();
  const ros::Time stamp(t);
  if (all || t + 1e-9 >= next_odom_) {
    next_odom_ = (std::floor(t / odom_period_ + 1e-6) + 1.0) * odom_period_;
    PublishOdometry(stamp);
  }
  if (!joints_with_odometry_ && (all || t + 1e-9 >= next_joints_)) {
    next_joints_ = (std::floor(t / joint_period_ + 1e-6) + 1.0) * joint_period_;
    PublishJointStates(stamp);
  }
  for (size_t i = 0; i < scan_pubs_.size(); ++i) {
    if (!robot_->ScanDue(i)) continue;
    robot_->TakeScan(i, &ranges_);
    scans_[i].header.stamp = stamp;
    scans_[i].ranges = ranges_;
    scan_pubs_[i].publish(scans_[i]);
  }
  for (size_t i = 0; i < imu_pubs_.size(); ++i) {
    if (!robot_->ImuDue(i)) continue;
    const ImuReading r = robot_->TakeImu(i);
    sensor_msgs::Imu m;
    m.header.stamp = stamp;
    m.header.frame_id = Frame(robot_->model().imus[i].frame_id);
    m.orientation = ToMsg(r.orientation);
    m.angular_velocity.x = r.angular_velocity.x();
    m.angular_velocity.y = r.angular_velocity.y();
    m.angular_velocity.z = r.angular_velocity.z();
    m.linear_acceleration.x = r.linear_acceleration.x();
    m.linear_acceleration.y = r.linear_acceleration.y();
    m.linear_acceleration.z = r.linear_acceleration.z();
    for (int k : {0, 4, 8}) {
      m.orientation_covariance[k] = r.variance;
      m.angular_velocity_covariance[k] = r.variance;
      m.linear_acceleration_covariance[k] = r.variance;
    }
    imu_pubs_[i].publish(m);
  }
  for (size_t i = 0; i < cameras_.size(); ++i) {
    if (robot_->CameraDue(i)) PublishCamera(i, stamp);
  }
  for (size_t i = 0; i < gt_pubs_.size(); ++i) {
    if (!robot_->GroundTruthDue(i)) continue;
    const GroundTruthReading r = robot_->TakeGroundTruth(i);
    const GroundTruthSpec& g = robot_->model().ground_truths[i];
    nav_msgs::Odometry m;
    m.header.stamp = stamp;
    m.header.frame_id = Frame(g.options.frame_name);
    m.child_frame_id = Frame(g.options.body_name);
    m.pose.pose.position.x = r.pose.translation().x();
    m.pose.pose.position.y = r.pose.translation().y();
    m.pose.pose.position.z = r.pose.translation().z();
    m.pose.pose.orientation = ToMsg(Eigen::Quaterniond(r.pose.linear()));
    m.twist.twist.linear.x = r.linear.x();
    m.twist.twist.linear.y = r.linear.y();
    m.twist.twist.linear.z = r.linear.z();
    m.twist.twist.angular.x = r.angular.x();
    m.twist.twist.angular.y = r.angular.y();
    m.twist.twist.angular.z = r.angular.z();
    for (int k = 0; k < 6; ++k) {
      m.pose.covariance[7 * k] = r.variance;
      m.twist.covariance[7 * k] = r.variance;
    }
    gt_pubs_[i].publish(m);
  }
}

// Topics below <robotNamespace>/<cameraName>/, CameraInfo as gazebo_ros_camera_utils fills it.
void RobotInterface::SetUpCamera(size_t i) {
  const CameraSpec& c = robot_->model().cameras[i];
  CameraPublishers& p = cameras_[i];
  const auto q = [this](int free_running) { return options_.lockstep ? 100000 : free_running; };
  const std::string ns = Resolve(c.robot_namespace, c.ros.camera_name);
  p.image = nh_.advertise<sensor_msgs::Image>(Resolve(ns, c.ros.image_topic_name), q(2));
  p.info = nh_.advertise<sensor_msgs::CameraInfo>(Resolve(ns, c.ros.camera_info_topic_name), q(2));
  if (c.depth) {
    p.depth = nh_.advertise<sensor_msgs::Image>(Resolve(ns, c.ros.depth_image_topic_name), q(2));
    p.depth_info = nh_.advertise<sensor_msgs::CameraInfo>(
        Resolve(ns, c.ros.depth_image_camera_info_topic_name), q(2));
    p.points = nh_.advertise<sensor_msgs::PointCloud2>(Resolve(ns, c.ros.point_cloud_topic_name), q(2));
  }
  const CameraIntrinsics k = robot_->camera(i).Intrinsics();
  const double f = c.ros.focal_length > 0 ? c.ros.focal_length : k.fx;
  const double cx = c.ros.cx > 0 ? c.ros.cx : k.cx, cy = c.ros.cy > 0 ? c.ros.cy : k.cy;
  p.focal_length = robot_->camera(i).focal_length();
  sensor_msgs::CameraInfo& info = p.camera_info;
  info.header.frame_id = Frame(c.ros.frame_name);
  info.width = c.sensor.width;
  info.height = c.sensor.height;
  info.distortion_model = "plumb_bob";
  info.D = {c.ros.distortion_k1, c.ros.distortion_k2, c.ros.distortion_t1, c.ros.distortion_t2,
            c.ros.distortion_k3};
  info.K = {f, 0, cx, 0, f, cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {f, 0, cx, -f * c.ros.hack_baseline, 0, f, cy, 0, 0, 0, 1, 0};
}

// Renders only when someone listens, as Gazebo's camera plugins do.
void RobotInterface::PublishCamera(size_t i, const ros::Time& stamp) {
  CameraPublishers& p = cameras_[i];
  const CameraSpec& c = robot_->model().cameras[i];
  const bool image = p.image.getNumSubscribers() > 0;
  const bool depth = p.depth && p.depth.getNumSubscribers() > 0;
  const bool points = p.points && p.points.getNumSubscribers() > 0;
  p.camera_info.header.stamp = stamp;
  if (p.info.getNumSubscribers() > 0) p.info.publish(p.camera_info);
  if (p.depth_info && p.depth_info.getNumSubscribers() > 0) p.depth_info.publish(p.camera_info);
  if (!image && !depth && !points) {
    robot_->SkipFrame(i);
    return;
  }
  robot_->TakeFrame(i, &p.frame);
  const DepthFrame& f = p.frame;
  const int w = f.width, h = f.height;
  if (image) {
    sensor_msgs::Image m;
    m.header.stamp = stamp;
    m.header.frame_id = Frame(c.ros.frame_name);
    m.width = w;
    m.height = h;
    m.encoding = c.sensor.format == "L8" ? "mono8" : c.sensor.format == "B8G8R8" ? "bgr8" : "rgb8";
    m.step = w * f.channels;
    m.data = f.rgb;
    p.image.publish(m);
  }
  // The plugins' cut-offs: NaN below pointCloudCutoff and above pointCloudCutoffMax (if >= 0).
  const double lo = c.ros.point_cloud_cutoff, hi = c.ros.point_cloud_cutoff_max;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  if (depth) {
    sensor_msgs::Image m;
    m.header.stamp = stamp;
    m.header.frame_id = Frame(c.ros.frame_name);
    m.width = w;
    m.height = h;
    m.encoding = "32FC1";
    m.is_bigendian = 0;
    m.step = 4 * w;
    m.data.resize(static_cast<size_t>(4) * w * h);
    float* out = reinterpret_cast<float*>(m.data.data());
    for (size_t k = 0; k < f.depth.size(); ++k) {
      const float d = f.depth[k];
      out[k] = (d <= lo || (hi >= 0.0 && d >= hi)) ? nan : d;
    }
    p.depth.publish(m);
  }
  if (points) {
    PointsFromDepth(f, p.focal_length, lo, hi, &p.xyz);
    sensor_msgs::PointCloud2 cloud;
    cloud.header.stamp = stamp;
    cloud.header.frame_id = Frame(c.ros.frame_name);
    cloud.height = h;
    cloud.width = w;
    sensor_msgs::PointCloud2Modifier mod(cloud);
    mod.setPointCloud2FieldsByString(2, "xyz", "rgb");
    mod.resize(static_cast<size_t>(w) * h);
    cloud.height = h;
    cloud.width = w;
    cloud.row_step = cloud.point_step * w;
    cloud.is_dense = false;
    sensor_msgs::PointCloud2Iterator<float> x(cloud, "x");
    sensor_msgs::PointCloud2Iterator<std::uint8_t> rgb(cloud, "rgb");
    for (size_t k = 0; k < static_cast<size_t>(w) * h; ++k, ++x, ++rgb) {
      x[0] = p.xyz[3 * k];
      x[1] = p.xyz[3 * k + 1];
      x[2] = p.xyz[3 * k + 2];
      // Packed as PCL does: bytes B, G, R in the float's first three.
      if (f.channels == 3) {
        const bool bgr = c.sensor.format == "B8G8R8";
        const std::uint8_t* px = &f.rgb[3 * k];
        rgb[0] = bgr ? px[0] : px[2];
        rgb[1] = px[1];
        rgb[2] = bgr ? px[2] : px[0];
      } else {
        rgb[0] = rgb[1] = rgb[2] = f.rgb[k];
      }
    }
    p.points.publish(cloud);
  }
}

void RobotInterface::PublishOdometry(const ros::Time& stamp) {
  const DriveInterface& d = robot_->drive().interface();
  const Pose2 o = robot_->odom_pose();
  if (odom_pub_) {
    nav_msgs::Odometry odom = MakeOdometry(stamp, Frame(d.odometry_frame), Frame(d.base_frame), o,
                                           robot_->odom_twist());
    std::copy(d.pose_covariance.begin(), d.pose_covariance.end(), odom.pose.covariance.begin());
    std::copy(d.twist_covariance.begin(), d.twist_covariance.end(), odom.twist.covariance.begin());
    odom_pub_.publish(odom);
    if (d.odometry_tf) {
      geometry_msgs::TransformStamped tf;
      tf.header = odom.header;
      tf.child_frame_id = odom.child_frame_id;
      tf.transform.translation.x = o.x;
      tf.transform.translation.y = o.y;
      tf.transform.rotation = odom.pose.pose.orientation;
      tf2_msgs::TFMessage m;
      m.transforms.push_back(tf);
      tf_pub_.publish(m);
    }
  }
  if (joints_with_odometry_) PublishJointStates(stamp);
  if (options_.publish_ground_truth) {
    truth_pub_.publish(MakeOdometry(stamp, Bare(options_.world_frame), Frame(d.base_frame),
                                    robot_->true_pose(), robot_->true_twist()));
  }
}

void RobotInterface::PublishJointStates(const ros::Time& stamp) {
  const auto& q = robot_->wheel_positions();
  const auto& w = robot_->wheel_velocities();
  joint_state_.header.stamp = stamp;
  for (size_t i = 0; i < q.size(); ++i) {
    joint_state_.position[i] = q[i];
    joint_state_.velocity[i] = w[i];
  }
  joint_pub_.publish(joint_state_);
}

// robot_state_publisher publishes the same transforms, but only once its own sim-time timer
// has fired: under lock-step that is after participants need them (base_link -> laser for the
// first scan). Identical static transforms from two publishers are harmless to tf2.
void RobotInterface::AppendStaticTransforms(tf2_msgs::TFMessage* msg) {
  for (auto& t : static_tf_.transforms) {
    t.header.stamp = ros::Time(robot_->time());
    msg->transforms.push_back(t);
  }
}

}  // namespace minibot3d_sim
