// minibot3d_sim node: the ROS face of the simulator core (simulator.h). It reads
// robot_description and ~parameters, converts cmd_vel in and scans/odometry/tf/joint states/clock
// out, offers reset/pause/unpause/step/set_pose services, and paces sim time against the wall clock
// (~real_time_factor; 0 = as fast as possible). All physics and sensing live in the core.
#include <cmath>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <ros/package.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <std_srvs/Empty.h>
#include <tf2_ros/transform_broadcaster.h>
#include <urdf/model.h>

#include "minibot3d_sim/Collision.h"
#include "minibot3d_sim/SetPose.h"
#include "minibot3d_sim/SimStatus.h"
#include "minibot3d_sim/Step.h"
#include "minibot3d_sim/robot_model.h"
#include "minibot3d_sim/simulator.h"
#include "minibot3d_sim/world_loader.h"

namespace minibot3d_sim {
namespace {

geometry_msgs::Quaternion YawToQuaternion(double yaw) {
  geometry_msgs::Quaternion q;
  q.z = std::sin(yaw / 2.0);
  q.w = std::cos(yaw / 2.0);
  return q;
}

nav_msgs::Odometry MakeOdometry(const ros::Time& stamp, const std::string& frame,
                                const std::string& child, const Pose2& pose, const Twist2& twist) {
  nav_msgs::Odometry m;
  m.header.stamp = stamp;
  m.header.frame_id = frame;
  m.child_frame_id = child;
  m.pose.pose.position.x = pose.x;
  m.pose.pose.position.y = pose.y;
  m.pose.pose.orientation = YawToQuaternion(pose.yaw);
  m.twist.twist.linear.x = twist.vx;
  m.twist.twist.linear.y = twist.vy;
  m.twist.twist.angular.z = twist.wz;
  return m;
}

// Parameters of the node (the core's own options are in SimulatorOptions).
struct NodeOptions {
  std::string world_path;
  double real_time_factor = 1.0;
  double clock_period = 0.005;  // s of sim time between /clock messages
  std::string world_frame = "world";
  bool publish_ground_truth = true;
  double floorplan_wall_height = 1.0;
  bool start_paused = false;
};

class SimNode {
 public:
  SimNode() : nh_(), pnh_("~") {}

  // Reads parameters, robot_description and the world; false (after a fatal message) if any is bad.
  bool Init() {
    SimulatorOptions sim;
    pnh_.param("physics", sim.physics, sim.physics);
    pnh_.param("physics_step", sim.physics_step, sim.physics_step);
    pnh_.param("cmd_timeout", sim.cmd_timeout, sim.cmd_timeout);
    pnh_.param("odom_wheel_separation_multiplier", sim.odom_wheel_separation_multiplier,
               sim.odom_wheel_separation_multiplier);
    pnh_.param("cmd_wheel_separation_multiplier", sim.cmd_wheel_separation_multiplier,
               sim.cmd_wheel_separation_multiplier);
    pnh_.param("x", sim.spawn.x, 0.0);
    pnh_.param("y", sim.spawn.y, 0.0);
    pnh_.param("yaw", sim.spawn.yaw, 0.0);
    int seed = 1;
    pnh_.param("seed", seed, seed);
    sim.seed = static_cast<unsigned>(seed);
    const std::string default_world = ros::package::getPath("minibot3d_sim") + "/worlds/default.world";
    pnh_.param("world", opts_.world_path, default_world);
    pnh_.param("real_time_factor", opts_.real_time_factor, opts_.real_time_factor);
    pnh_.param("clock_period", opts_.clock_period, opts_.clock_period);
    pnh_.param("world_frame", opts_.world_frame, opts_.world_frame);
    pnh_.param("publish_ground_truth", opts_.publish_ground_truth, opts_.publish_ground_truth);
    pnh_.param("floorplan_wall_height", opts_.floorplan_wall_height, opts_.floorplan_wall_height);
    pnh_.param("paused", opts_.start_paused, opts_.start_paused);
    if (!(opts_.real_time_factor >= 0.0) || !std::isfinite(opts_.real_time_factor)) {
      ROS_FATAL("minibot3d_sim: ~real_time_factor must be >= 0 (0: as fast as possible), got %g",
                opts_.real_time_factor);
      return false;
    }
    if (!(opts_.clock_period >= sim.physics_step) || opts_.clock_period > 0.1) {
      ROS_FATAL("minibot3d_sim: ~clock_period must be in [~physics_step = %g, 0.1] s, got %g",
                sim.physics_step, opts_.clock_period);
      return false;
    }
    try {
      ValidateOptions(sim);
    } catch (const std::invalid_argument& e) {
      ROS_FATAL("minibot3d_sim: parameter ~%s", e.what());
      return false;
    }

    std::string urdf_xml;
    if (!nh_.getParam("robot_description", urdf_xml)) {
      ROS_FATAL("minibot3d_sim: parameter robot_description is not set (load the robot's xacro, "
                "e.g. with minibot3d_gazebo.launch)");
      return false;
    }
    RobotModel robot;
    try {
      robot = ParseRobotModel(urdf_xml);
    } catch (const RobotModelError& e) {
      ROS_FATAL("minibot3d_sim: robot_description: %s", e.what());
      return false;
    }
    for (const auto& w : robot.warnings) ROS_WARN("minibot3d_sim: robot_description: %s", w.c_str());

    WorldLoadOptions load;
    load.floorplan_wall_height = opts_.floorplan_wall_height;
    std::vector<std::string> warnings;
    World world;
    try {
      world = LoadWorld(opts_.world_path, load, &warnings);
    } catch (const WorldError& e) {
      ROS_FATAL("minibot3d_sim: ~world: %s", e.what());
      return false;
    }
    for (const auto& w : warnings) ROS_WARN("minibot3d_sim: world: %s", w.c_str());

    try {
      sim_ = std::make_unique<Simulator>(robot, std::move(world), sim);
    } catch (const std::exception& e) {
      ROS_FATAL("minibot3d_sim: %s", e.what());
      return false;
    }
    std::string what;
    if (sim_->PoseCollides(sim.spawn, &what)) {
      ROS_FATAL("minibot3d_sim: the spawn pose ~x=%g ~y=%g ~yaw=%g overlaps '%s' in %s", sim.spawn.x,
                sim.spawn.y, sim.spawn.yaw, what.c_str(), opts_.world_path.c_str());
      return false;
    }

    // Joints robot_state_publisher needs besides the driven wheels (casters) are published at 0.
    urdf::Model model;
    model.initString(urdf_xml);
    for (const auto& w : robot.wheels) joint_state_.name.push_back(w.joint);
    for (const auto& j : model.joints_) {
      const bool movable = j.second->type != urdf::Joint::FIXED &&
                           j.second->type != urdf::Joint::FLOATING &&
                           j.second->type != urdf::Joint::PLANAR;
      bool wheel = false;
      for (const auto& w : robot.wheels) wheel |= w.joint == j.first;
      if (movable && !wheel) joint_state_.name.push_back(j.first);
    }
    joint_state_.position.assign(joint_state_.name.size(), 0.0);
    joint_state_.velocity.assign(joint_state_.name.size(), 0.0);

    const DriveSpec& d = robot.drive;
    odom_period_ = d.update_rate > 0 ? 1.0 / d.update_rate : sim.physics_step;
    clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
    scan_pub_ = nh_.advertise<sensor_msgs::LaserScan>(robot.lidar.topic, 5);
    odom_pub_ = nh_.advertise<nav_msgs::Odometry>(d.odometry_topic, 20);
    joint_pub_ = nh_.advertise<sensor_msgs::JointState>("joint_states", 20);
    if (opts_.publish_ground_truth) {
      truth_pub_ = nh_.advertise<nav_msgs::Odometry>("ground_truth/odom", 20);
    }
    collision_pub_ = pnh_.advertise<Collision>("collisions", 50);
    status_pub_ = pnh_.advertise<SimStatus>("status", 5, true);
    cmd_sub_ = nh_.subscribe(d.command_topic, 5, &SimNode::OnCommand, this,
                             ros::TransportHints().tcpNoDelay());
    services_.push_back(pnh_.advertiseService("reset", &SimNode::OnReset, this));
    services_.push_back(pnh_.advertiseService("pause", &SimNode::OnPause, this));
    services_.push_back(pnh_.advertiseService("unpause", &SimNode::OnUnpause, this));
    services_.push_back(pnh_.advertiseService("step", &SimNode::OnStep, this));
    services_.push_back(pnh_.advertiseService("set_pose", &SimNode::OnSetPose, this));
    paused_ = opts_.start_paused;

    scan_.header.frame_id = robot.lidar.frame_id;
    scan_.angle_min = robot.lidar.min_angle;
    scan_.angle_max = robot.lidar.max_angle;
    scan_.angle_increment = sim_->lidar().angle_increment();
    scan_.time_increment = 0.0;  // every beam of a simulated scan is taken at the same instant
    scan_.scan_time = 1.0 / robot.lidar.update_rate;
    scan_.range_min = robot.lidar.min_range;
    scan_.range_max = robot.lidar.max_range;
    ROS_INFO("minibot3d_sim: robot '%s', world %s (%zu shapes), physics %s at %g s, real-time "
             "factor %g, spawn (%g, %g, %g)", robot.name.c_str(), opts_.world_path.c_str(),
             sim_->world().shapes.size(), sim.physics.c_str(), sim.physics_step,
             opts_.real_time_factor, sim.spawn.x, sim.spawn.y, sim.spawn.yaw);
    return true;
  }

  void Run() {
    PublishClock();
    Publish(true);
    Anchor();
    const auto steps_per_clock =
        std::max<std::uint64_t>(1, std::llround(opts_.clock_period / sim_->physics_step()));
    while (ros::ok()) {
      if (paused_) {
        ros::WallDuration(0.005).sleep();
        ros::spinOnce();
        Anchor();
        continue;
      }
      StepOnce();
      if (sim_->steps() % steps_per_clock == 0) {
        PublishClock();
        ros::spinOnce();
        Pace();
      }
    }
    const double wall = (ros::WallTime::now() - run_wall_start_).toSec();
    ROS_INFO("minibot3d_sim: %.1f s simulated in %.1f s wall (real-time factor %.1f), %lu "
             "collisions", sim_->time(), wall, wall > 0 ? sim_->time() / wall : 0.0,
             static_cast<unsigned long>(sim_->collision_count()));
  }

 private:
  void StepOnce() {
    sim_->Step();
    Publish(false);
  }

  // Publishes whatever is due at the current sim time (everything when `all`).
  void Publish(bool all) {
    const double t = sim_->time();
    const ros::Time stamp(t);
    if (all || t + 1e-9 >= next_odom_) {
      next_odom_ = (std::floor(t / odom_period_ + 1e-6) + 1.0) * odom_period_;
      PublishOdometry(stamp);
    }
    if (sim_->ScanDue()) {
      sim_->TakeScan(&ranges_);
      scan_.header.stamp = stamp;
      scan_.ranges = ranges_;
      scan_pub_.publish(scan_);
    }
    for (const auto& e : sim_->TakeCollisionEvents()) {
      Collision c;
      c.header.stamp = ros::Time(e.time);
      c.header.frame_id = opts_.world_frame;
      c.position.x = e.contact.point.x();
      c.position.y = e.contact.point.y();
      c.position.z = e.contact.point.z();
      c.normal.x = e.contact.normal.x();
      c.normal.y = e.contact.normal.y();
      c.normal.z = e.contact.normal.z();
      c.depth = e.contact.depth;
      c.object = e.shape_name;
      c.count = ++published_collisions_;
      collision_pub_.publish(c);
      ROS_WARN_THROTTLE(1.0, "minibot3d_sim: collision #%lu with '%s' at (%.2f, %.2f), t=%.2f s",
                        static_cast<unsigned long>(c.count), c.object.c_str(), c.position.x,
                        c.position.y, e.time);
      PublishStatus(stamp);
    }
    if (all || t + 1e-9 >= next_status_) {
      next_status_ = std::floor(t + 1e-6) + 1.0;
      PublishStatus(stamp);
    }
  }

  void PublishOdometry(const ros::Time& stamp) {
    const RobotModel& robot = sim_->robot();
    const DriveSpec& d = robot.drive;
    const Pose2 o = sim_->odom_pose();
    nav_msgs::Odometry odom =
        MakeOdometry(stamp, d.odometry_frame, d.robot_base_frame, o, sim_->odom_twist());
    // Diagonal covariances from the plugin tags (x, y, yaw); the rest of the 6-DOF is fixed by
    // the floor, given a large variance as Gazebo's plugin does.
    for (auto* cov : {&odom.pose.covariance, &odom.twist.covariance}) {
      (*cov)[0] = d.covariance_x;
      (*cov)[7] = d.covariance_y;
      (*cov)[14] = 1e6;
      (*cov)[21] = 1e6;
      (*cov)[28] = 1e6;
      (*cov)[35] = d.covariance_yaw;
    }
    odom_pub_.publish(odom);
    if (d.broadcast_tf) {
      geometry_msgs::TransformStamped tf;
      tf.header = odom.header;
      tf.child_frame_id = odom.child_frame_id;
      tf.transform.translation.x = o.x;
      tf.transform.translation.y = o.y;
      tf.transform.rotation = odom.pose.pose.orientation;
      tf_.sendTransform(tf);
    }
    const auto q = sim_->wheel_positions();
    const auto w = sim_->wheel_velocities();
    joint_state_.header.stamp = stamp;
    for (int i = 0; i < 4; ++i) {
      joint_state_.position[i] = q[i];
      joint_state_.velocity[i] = w[i];
    }
    joint_pub_.publish(joint_state_);
    if (opts_.publish_ground_truth) {
      truth_pub_.publish(MakeOdometry(stamp, opts_.world_frame, d.robot_base_frame,
                                      sim_->true_pose(), sim_->true_twist()));
    }
  }

  void PublishClock() {
    rosgraph_msgs::Clock c;
    c.clock = ros::Time(sim_->time());
    clock_pub_.publish(c);
  }

  void PublishStatus(const ros::Time& stamp) {
    const ros::WallTime now = ros::WallTime::now();
    SimStatus s;
    s.header.stamp = stamp;
    s.physics = sim_->backend().name();
    s.sim_time = sim_->time();
    s.steps = sim_->steps();
    s.physics_step = sim_->physics_step();
    s.target_real_time_factor = opts_.real_time_factor;
    const double wall = (now - status_wall_).toSec();
    s.real_time_factor = wall > 0 ? (s.sim_time - status_sim_) / wall : 0.0;
    s.paused = paused_;
    s.collisions = sim_->collision_count();
    s.in_contact = sim_->in_contact();
    status_pub_.publish(s);
    status_wall_ = now;
    status_sim_ = s.sim_time;
  }

  // Restarts real-time pacing from the current instant (after start, pause or a rate change).
  void Anchor() {
    anchor_wall_ = ros::WallTime::now();
    anchor_sim_ = sim_->time();
    if (run_wall_start_.isZero()) run_wall_start_ = anchor_wall_;
  }

  void Pace() {
    if (opts_.real_time_factor <= 0) return;
    const ros::WallTime target =
        anchor_wall_ + ros::WallDuration((sim_->time() - anchor_sim_) / opts_.real_time_factor);
    const ros::WallTime now = ros::WallTime::now();
    if (target > now) {
      (target - now).sleep();
    } else if ((now - target).toSec() > 1.0) {
      // Far behind (the CPU cannot keep up): do not try to catch up in a burst.
      ROS_WARN_THROTTLE(10.0, "minibot3d_sim: running slower than ~real_time_factor %g",
                        opts_.real_time_factor);
      Anchor();
    }
  }

  void OnCommand(const ros::MessageEvent<const geometry_msgs::Twist>& event) {
    const geometry_msgs::Twist::ConstPtr& msg = event.getConstMessage();
    const double v = msg->linear.x, w = msg->angular.z;
    if (!std::isfinite(v) || !std::isfinite(w)) {
      ROS_WARN_THROTTLE(2.0, "minibot3d_sim: ignoring cmd_vel with non-finite linear.x=%g "
                        "angular.z=%g from %s", v, w,
                        event.getPublisherName().c_str());
      return;
    }
    sim_->SetCommand(v, w);
  }

  bool OnReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    sim_->Reset();
    ROS_INFO("minibot3d_sim: reset to the spawn pose");
    Publish(true);
    return true;
  }
  bool OnPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    paused_ = true;
    return true;
  }
  bool OnUnpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    paused_ = false;
    Anchor();
    return true;
  }
  bool OnStep(Step::Request& req, Step::Response& res) {
    for (std::uint32_t i = 0; i < req.steps; ++i) StepOnce();
    PublishClock();
    res.sim_time = sim_->time();
    Anchor();
    return true;
  }
  bool OnSetPose(SetPose::Request& req, SetPose::Response& res) {
    if (!std::isfinite(req.x) || !std::isfinite(req.y) || !std::isfinite(req.yaw)) {
      res.success = false;
      res.message = "x, y and yaw must be finite";
      return true;
    }
    std::string what;
    const Pose2 pose{req.x, req.y, req.yaw};
    if (sim_->PoseCollides(pose, &what)) {
      res.success = false;
      std::ostringstream msg;
      msg << "pose (" << req.x << ", " << req.y << ", " << req.yaw << ") overlaps '" << what << "'";
      res.message = msg.str();
      return true;
    }
    sim_->SetPose(pose);
    res.success = true;
    res.message = "teleported";
    Publish(true);
    return true;
  }

  ros::NodeHandle nh_, pnh_;
  NodeOptions opts_;
  std::unique_ptr<Simulator> sim_;
  ros::Publisher clock_pub_, scan_pub_, odom_pub_, joint_pub_, truth_pub_, collision_pub_,
      status_pub_;
  ros::Subscriber cmd_sub_;
  std::vector<ros::ServiceServer> services_;
  tf2_ros::TransformBroadcaster tf_;
  sensor_msgs::LaserScan scan_;
  sensor_msgs::JointState joint_state_;
  std::vector<float> ranges_;
  double odom_period_ = 0.01;
  double next_odom_ = 0.0;
  double next_status_ = 0.0;
  std::uint64_t published_collisions_ = 0;
  bool paused_ = false;
  ros::WallTime anchor_wall_, run_wall_start_, status_wall_;
  double anchor_sim_ = 0.0, status_sim_ = 0.0;
};

}  // namespace
}  // namespace minibot3d_sim

int main(int argc, char** argv) {
  ros::init(argc, argv, "minibot3d_sim");
  minibot3d_sim::SimNode node;
  if (!node.Init()) return 1;
  node.Run();
  return 0;
}
