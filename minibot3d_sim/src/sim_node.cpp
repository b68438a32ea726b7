// minibot3d_sim node: the ROS face of the simulator core (simulator.h). It reads
// robot_description and ~parameters, converts cmd_vel in and scans/odometry/tf/joint states/clock
// out, offers reset/pause/unpause/step/set_pose services, and paces sim time against the wall clock
// (~real_time_factor; 0 = as fast as possible). All physics and sensing live in the core.
//
// With /use_lockstep true the node also runs the lock-step loop (minibot3d_lockstep/coordinator.h):
// sim time advances one ~lockstep_quantum at a time, and at each quantum every participant that
// has work (a wake time, mail, or it just joined) is ticked in turn, and the simulator waits for
// its acknowledgement and for the messages it sent before going on.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <ros/callback_queue.h>
#include <ros/package.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <std_srvs/Empty.h>
#include <tf2_msgs/TFMessage.h>
#include <urdf/model.h>

#include "minibot3d_lockstep/Ack.h"
#include "minibot3d_lockstep/Participants.h"
#include "minibot3d_lockstep/Register.h"
#include "minibot3d_lockstep/Tick.h"
#include "minibot3d_lockstep/Unregister.h"
#include "minibot3d_lockstep/coordinator.h"
#include "minibot3d_lockstep/link_counts.h"
#include "minibot3d_lockstep/participant.h"
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
  double clock_period = 0.005;  // s of sim time between /clock messages (free-running)
  double pub_clock_frequency = 1000.0;  // at most this many /clock messages per wall second
  bool lockstep = false;
  minibot3d_lockstep::CoordinatorOptions lockstep_options;
  std::vector<std::string> lockstep_participants;  // waited for before time starts
  double lockstep_start_timeout = 60.0;  // wall s to wait for them (a loaded machine starts slowly)
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
    pnh_.param("pub_clock_frequency", opts_.pub_clock_frequency, opts_.pub_clock_frequency);
    opts_.lockstep = minibot3d_lockstep::LockstepEnabled();
    pnh_.param("lockstep_quantum", opts_.lockstep_options.quantum, opts_.lockstep_options.quantum);
    pnh_.param("lockstep_timeout", opts_.lockstep_options.timeout, opts_.lockstep_options.timeout);
    pnh_.param("lockstep_start_timeout", opts_.lockstep_start_timeout,
               opts_.lockstep_start_timeout);
    if (!(opts_.lockstep_start_timeout > 0.0) || !std::isfinite(opts_.lockstep_start_timeout)) {
      ROS_FATAL("minibot3d_sim: ~lockstep_start_timeout must be > 0 wall s, got %g",
                opts_.lockstep_start_timeout);
      return false;
    }
    if (pnh_.hasParam("lockstep_participants")) {
      std::string names;
      if (!pnh_.getParam("lockstep_participants", opts_.lockstep_participants)) {
        if (!pnh_.getParam("lockstep_participants", names)) {
          ROS_FATAL("minibot3d_sim: ~lockstep_participants must be a list of node names or a "
                    "space-separated string of them");
          return false;
        }
        std::istringstream in(names);
        for (std::string n; in >> n;) opts_.lockstep_participants.push_back(n);
      }
      for (auto& n : opts_.lockstep_participants) n = ros::names::resolve(n, false);
    }
    if (!(opts_.pub_clock_frequency > 0.0) || !std::isfinite(opts_.pub_clock_frequency)) {
      ROS_FATAL("minibot3d_sim: ~pub_clock_frequency must be > 0 Hz (wall), got %g",
                opts_.pub_clock_frequency);
      return false;
    }
    try {
      minibot3d_lockstep::ValidateOptions(opts_.lockstep_options);
    } catch (const std::invalid_argument& e) {
      ROS_FATAL("minibot3d_sim: parameter ~%s", e.what());
      return false;
    }
    if (opts_.lockstep) {
      const double q = opts_.lockstep_options.quantum / sim.physics_step;
      if (std::fabs(q - std::round(q)) > 1e-6) {
        ROS_FATAL("minibot3d_sim: ~lockstep_quantum (%g s) must be a whole number of "
                  "~physics_step (%g s)", opts_.lockstep_options.quantum, sim.physics_step);
        return false;
      }
    }
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
    // The robot's fixed joints, for tf_static: published by the simulator too (see
    // PublishStaticTransforms), so they are there when sim time starts.
    for (const auto& j : model.joints_) {
      if (j.second->type != urdf::Joint::FIXED) continue;
      const urdf::Pose& o = j.second->parent_to_joint_origin_transform;
      geometry_msgs::TransformStamped t;
      t.header.frame_id = j.second->parent_link_name;
      t.child_frame_id = j.second->child_link_name;
      t.transform.translation.x = o.position.x;
      t.transform.translation.y = o.position.y;
      t.transform.translation.z = o.position.z;
      t.transform.rotation.x = o.rotation.x;
      t.transform.rotation.y = o.rotation.y;
      t.transform.rotation.z = o.rotation.z;
      t.transform.rotation.w = o.rotation.w;
      static_tf_.transforms.push_back(t);
    }
    joint_state_.velocity.assign(joint_state_.name.size(), 0.0);

    const DriveSpec& d = robot.drive;
    odom_period_ = d.update_rate > 0 ? 1.0 / d.update_rate : sim.physics_step;
    // In lock-step a participant counts on receiving every message the simulator queued to it, so
    // outgoing queues must not drop: roscpp drops the oldest message when a subscriber's socket is
    // backed up past the queue size (a subscriber that reads slowly while no participant has work
    // and the simulator runs ahead). Free-running keeps today's small queues.
    const auto q = [this](int free_running) { return opts_.lockstep ? 100000 : free_running; };
    // Latched: a node that starts while sim time is held (lock-step, or paused) gets the current
    // time at once; roscpp nodes wait for a first /clock (actionlib's clients, for one).
    clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", q(10), true);
    scan_pub_ = nh_.advertise<sensor_msgs::LaserScan>(robot.lidar.topic, q(5));
    odom_pub_ = nh_.advertise<nav_msgs::Odometry>(d.odometry_topic, q(20));
    tf_pub_ = nh_.advertise<tf2_msgs::TFMessage>("/tf", q(100));
    tf_static_pub_ = nh_.advertise<tf2_msgs::TFMessage>("/tf_static", 1, true);
    joint_pub_ = nh_.advertise<sensor_msgs::JointState>("joint_states", q(20));
    if (opts_.publish_ground_truth) {
      truth_pub_ = nh_.advertise<nav_msgs::Odometry>("ground_truth/odom", q(20));
    }
    collision_pub_ = pnh_.advertise<Collision>("collisions", q(50));
    status_pub_ = pnh_.advertise<SimStatus>("status", q(5), true);
    // Commands have their own queue: in lock-step they are applied once every participant's
    // messages have arrived, never in the middle of a round.
    ros::NodeHandle cmd_nh(nh_);
    cmd_nh.setCallbackQueue(&cmd_queue_);
    cmd_sub_ = cmd_nh.subscribe(d.command_topic, 5, &SimNode::OnCommand, this,
                                ros::TransportHints().tcpNoDelay());
    if (opts_.lockstep) {
      coordinator_ = std::make_unique<minibot3d_lockstep::Coordinator>(
          opts_.lockstep_options, ros::this_node::getName());
      ack_sub_ = nh_.subscribe(minibot3d_lockstep::kAckTopic, 100, &SimNode::OnAck, this,
                               ros::TransportHints().tcpNoDelay());
      participants_pub_ = nh_.advertise<minibot3d_lockstep::Participants>(
          minibot3d_lockstep::kParticipantsTopic, q(1), true);
      services_.push_back(nh_.advertiseService(minibot3d_lockstep::kRegisterService,
                                               &SimNode::OnRegister, this));
      services_.push_back(nh_.advertiseService(minibot3d_lockstep::kUnregisterService,
                                               &SimNode::OnUnregister, this));
      PublishParticipants();
    }
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
             "factor %g, spawn (%g, %g, %g)%s", robot.name.c_str(), opts_.world_path.c_str(),
             sim_->world().shapes.size(), sim.physics.c_str(), sim.physics_step,
             opts_.real_time_factor, sim.spawn.x, sim.spawn.y, sim.spawn.yaw,
             opts_.lockstep ? ", lock-step" : "");
    return true;
  }

  void Run() {
    if (opts_.lockstep) {
      RunLockstep();
    } else {
      PublishClock();
      PublishStaticTransforms();
      Publish(true);
      Anchor();
      RunFree();
    }
    const double wall = (ros::WallTime::now() - run_wall_start_).toSec();
    ROS_INFO("minibot3d_sim: %.1f s simulated in %.1f s wall (real-time factor %.1f), %lu "
             "collisions", sim_->time(), wall, wall > 0 ? sim_->time() / wall : 0.0,
             static_cast<unsigned long>(sim_->collision_count()));
  }

 private:
  // Today's behaviour: sim time runs on; nodes take messages as they come.
  void RunFree() {
    const auto steps_per_clock =
        std::max<std::uint64_t>(1, std::llround(opts_.clock_period / sim_->physics_step()));
    while (ros::ok()) {
      if (paused_) {
        ros::WallDuration(0.005).sleep();
        ros::spinOnce();
        cmd_queue_.callAvailable();
        Anchor();
        continue;
      }
      StepOnce();
      if (sim_->steps() % steps_per_clock == 0) {
        MaybePublishClock();
        ros::spinOnce();
        cmd_queue_.callAvailable();
        Pace();
      }
    }
  }

  // Lock-step: a round at the current time, then one quantum of physics, and again.
  void RunLockstep() {
    const auto steps_per_quantum = std::max<std::uint64_t>(
        1, std::llround(opts_.lockstep_options.quantum / sim_->physics_step()));
    // roscpp takes sim time 0 for "no clock yet" (ros::Time::isValid): nodes such as
    // robot_state_publisher wait for a later time before publishing, latched tf_static included.
    // One physics step with nothing published but the clock gets time going.
    sim_->Step();
    PublishClock();
    // Nothing else is published before the participants a launch file names have joined and made
    // their connections (in their first round): the first messages reach all of them alike.
    WaitForExpectedParticipants();
    WaitForOwnConnections();
    // The first sensor messages go out before the first round: robot_state_publisher answers
    // the first joint states with the latched tf_static that participants wait for.
    PublishStaticTransforms();
    Publish(true);
    coordinator_->SetSent(ros::this_node::getName(), minibot3d_lockstep::SentCounts());
    Round();
    coordinator_->SetSent(ros::this_node::getName(), minibot3d_lockstep::SentCounts());
    Anchor();
    while (ros::ok()) {
      if (paused_) {
        ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.005));
        Anchor();
        continue;
      }
      Round();
      for (std::uint64_t i = 0; i < steps_per_quantum && ros::ok(); ++i) StepOnce();
      coordinator_->SetSent(ros::this_node::getName(), minibot3d_lockstep::SentCounts());
      Pace();
      // Non-participants (rviz, a user's script) still see time go by, throttled in wall time.
      MaybePublishClock();
    }
  }

  // Time does not start until the participants a launch file names have joined (each joins at a
  // sim time that then does not depend on how fast its process started).
  void WaitForExpectedParticipants() {
    const ros::WallTime start = ros::WallTime::now();
    ros::WallTime last_note = start;
    while (ros::ok()) {
      ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.01));
      std::vector<std::string> missing;
      for (const auto& n : opts_.lockstep_participants) {
        if (!coordinator_->Has(n)) missing.push_back(n);
      }
      if (missing.empty()) return;
      const ros::WallTime now = ros::WallTime::now();
      if ((now - start).toSec() > opts_.lockstep_start_timeout) {
        ROS_WARN("minibot3d_sim: lock-step: starting time without %s, which did not register "
                 "within ~lockstep_start_timeout %g s", Join(missing).c_str(),
                 opts_.lockstep_start_timeout);
        return;
      }
      if ((now - last_note).toSec() > 2.0) {
        last_note = now;
        ROS_INFO("minibot3d_sim: lock-step: waiting for %s to register before starting time",
                 Join(missing).c_str());
      }
    }
  }

  // Every subscriber the master lists for the simulator's topics is connected, so the first
  // messages reach every node that has asked for them, however fast each process started.
  void WaitForOwnConnections() {
    const ros::WallTime start = ros::WallTime::now();
    while (ros::ok()) {
      const auto missing = minibot3d_lockstep::MissingConnections();
      if (missing.empty()) return;
      if ((ros::WallTime::now() - start).toSec() > opts_.lockstep_options.timeout) {
        ROS_WARN("minibot3d_sim: lock-step: starting without connections: %s",
                 Join(missing).c_str());
        return;
      }
      ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.005));
    }
  }

  static std::string Join(const std::vector<std::string>& names) {
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
    return s;
  }

  // Ticks every participant that has work at the current time, one after the other in name
  // order, waiting for each to acknowledge; then waits for what they sent the simulator.
  void Round() {
    ros::getGlobalCallbackQueue()->callAvailable();
    DropDead();
    const double t = sim_->time();
    bool clock_sent = false;
    for (const std::string& name : coordinator_->Due(t)) {
      auto it = ticks_.find(name);
      if (it == ticks_.end()) continue;
      if (!WaitReady(name)) continue;
      if (!clock_sent) {
        PublishClock(true);  // before the first tick: participants wait for their clock to show t
        clock_sent = true;
      }
      minibot3d_lockstep::Tick tick;
      tick.seq = ++tick_seq_;
      tick.stamp = ros::Time(t);
      for (const auto& l : coordinator_->Expected(name)) {
        minibot3d_lockstep::Link link;
        link.topic = l.topic;
        link.peer = l.peer;
        link.count = l.count;
        tick.expected.push_back(link);
      }
      coordinator_->MarkTicked(name, tick.seq, t, ros::WallTime::now().toSec());
      it->second.pub.publish(tick);
      WaitForAck(name);
      // What it sent the simulator is queued before the next participant works: commands from
      // two participants on one topic (cmd_vel) are applied in tick order, not arrival order.
      WaitForDeliveryToSim();
    }
    cmd_queue_.callAvailable();
  }

  // A joined participant is ticked once its tick subscription is connected.
  bool WaitReady(const std::string& name) {
    const ros::WallTime start = ros::WallTime::now();
    while (ros::ok()) {
      auto it = ticks_.find(name);
      if (it == ticks_.end()) return false;
      if (it->second.pub.getNumSubscribers() > 0) {
        it->second.connected = true;
        return true;
      }
      if ((ros::WallTime::now() - start).toSec() > opts_.lockstep_options.timeout) {
        Drop(name, "never subscribed to its tick topic");
        return false;
      }
      ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.001));
    }
    return false;
  }

  void WaitForAck(const std::string& name) {
    ros::WallTime last_note = ros::WallTime::now();
    while (ros::ok() && coordinator_->Has(name)) {
      const auto waiting = coordinator_->Waiting();
      if (std::find(waiting.begin(), waiting.end(), name) == waiting.end()) return;
      ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.001));
      const ros::WallTime now = ros::WallTime::now();
      const double waited = coordinator_->WaitingFor(name, now.toSec());
      auto it = ticks_.find(name);
      if (it != ticks_.end() && it->second.connected && it->second.pub.getNumSubscribers() == 0) {
        Drop(name, "its process is gone (tick topic unsubscribed)");
        return;
      }
      if (waited > opts_.lockstep_options.timeout) {
        Drop(name, "no acknowledgement within ~lockstep_timeout");
        return;
      }
      if (waited > 1.0 && (now - last_note).toSec() > 2.0) {
        last_note = now;
        ROS_WARN("minibot3d_sim: lock-step: sim time %.3f waits for %s (%.1f s wall so far)",
                 sim_->time(), name.c_str(), waited);
      }
    }
  }

  // Messages participants sent to the simulator (cmd_vel, acks) are all here before commands are
  // applied and physics goes on.
  void WaitForDeliveryToSim() {
    const auto expected = coordinator_->Expected(ros::this_node::getName());
    const ros::WallTime start = ros::WallTime::now();
    while (ros::ok()) {
      std::map<std::pair<std::string, std::string>, std::uint64_t> have;
      for (const auto& l : minibot3d_lockstep::ReceivedCounts()) have[{l.topic, l.peer}] = l.count;
      bool ok = true;
      for (const auto& e : expected) {
        auto it = have.find({e.topic, e.peer});
        if (it == have.end() || it->second < e.count) {
          ok = false;
          if ((ros::WallTime::now() - start).toSec() > opts_.lockstep_options.timeout) {
            ROS_WARN("minibot3d_sim: lock-step: going on without %s's messages on %s",
                     e.peer.c_str(), e.topic.c_str());
            ok = true;
          }
          break;
        }
      }
      if (ok) break;
      minibot3d_lockstep::WaitForPollIteration(0.002);
    }
    minibot3d_lockstep::SyncWithPollThread();
  }

  // Participants whose process is gone are dropped between rounds too.
  void DropDead() {
    std::vector<std::string> dead;
    for (const auto& kv : ticks_) {
      if (kv.second.connected && kv.second.pub.getNumSubscribers() == 0) dead.push_back(kv.first);
    }
    for (const auto& n : dead) Drop(n, "its process is gone (tick topic unsubscribed)");
  }

  void Drop(const std::string& name, const std::string& why) {
    ROS_WARN("minibot3d_sim: lock-step: dropped participant %s at sim time %.3f: %s",
             name.c_str(), sim_->time(), why.c_str());
    coordinator_->Remove(name);
    ticks_.erase(name);
    PublishParticipants();
  }

  void PublishParticipants() {
    minibot3d_lockstep::Participants p;
    p.stamp = ros::Time(sim_->time());
    p.names = coordinator_->Participants();
    participants_pub_.publish(p);
  }

  bool OnRegister(minibot3d_lockstep::Register::Request& req,
                  minibot3d_lockstep::Register::Response& res) {
    const std::string error = coordinator_->Register(req.name, req.wake_topics);
    res.accepted = error.empty();
    res.message = error;
    res.now = ros::Time(sim_->time());
    res.quantum = opts_.lockstep_options.quantum;
    if (!res.accepted) {
      ROS_WARN("minibot3d_sim: lock-step: refused %s: %s", req.name.c_str(), error.c_str());
      return true;
    }
    std::string topic = minibot3d_lockstep::kTickTopicPrefix;
    topic += req.name[0] == '/' ? req.name : "/" + req.name;
    res.tick_topic = topic;
    TickPublisher tp;
    tp.pub = nh_.advertise<minibot3d_lockstep::Tick>(topic, 1000);
    ticks_[req.name] = tp;
    ROS_INFO("minibot3d_sim: lock-step: %s joined at sim time %.3f", req.name.c_str(),
             sim_->time());
    PublishParticipants();
    return true;
  }

  bool OnUnregister(minibot3d_lockstep::Unregister::Request& req,
                    minibot3d_lockstep::Unregister::Response& res) {
    res.removed = coordinator_->Remove(req.name);
    ticks_.erase(req.name);
    if (res.removed) {
      ROS_INFO("minibot3d_sim: lock-step: %s left at sim time %.3f", req.name.c_str(),
               sim_->time());
      PublishParticipants();
    }
    return true;
  }

  void OnAck(const minibot3d_lockstep::Ack::ConstPtr& ack) {
    if (ack->working) {
      coordinator_->Heartbeat(ack->name, ack->seq, ros::WallTime::now().toSec());
      return;
    }
    std::vector<minibot3d_lockstep::LinkCount> sent;
    for (const auto& l : ack->sent) sent.push_back({l.topic, l.peer, l.count});
    const double wake = ack->next_wake.isZero() ? 0.0 : ack->next_wake.toSec();
    if (!coordinator_->Ack(ack->name, ack->seq, wake, sent)) {
      ROS_WARN_THROTTLE(5.0, "minibot3d_sim: lock-step: ignoring an acknowledgement from %s "
                        "for tick %lu it is not waiting on", ack->name.c_str(),
                        static_cast<unsigned long>(ack->seq));
    }
  }

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
      tf2_msgs::TFMessage m;
      m.transforms.push_back(tf);
      tf_pub_.publish(m);
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

  // robot_state_publisher publishes the same transforms, but only once its own sim-time timer
  // has fired: under lock-step that is after participants need them (base_link -> laser for the
  // first scan). Identical static transforms from two publishers are harmless to tf2.
  void PublishStaticTransforms() {
    for (auto& t : static_tf_.transforms) t.header.stamp = ros::Time(sim_->time());
    tf_static_pub_.publish(static_tf_);
  }

  // At most one /clock per instant, unless `again` (a round: a participant that connected since
  // must see its clock reach the tick's time).
  void PublishClock(bool again = false) {
    rosgraph_msgs::Clock c;
    c.clock = ros::Time(sim_->time());
    if (!again && c.clock == last_clock_ && clock_published_) return;
    clock_pub_.publish(c);
    last_clock_ = c.clock;
    clock_published_ = true;
    last_clock_wall_ = ros::WallTime::now();
  }

  // /clock for nodes that do not participate, at most ~pub_clock_frequency per wall second
  // (gazebo_ros's pub_clock_frequency): a listener is never flooded at high real-time factors.
  void MaybePublishClock() {
    if ((ros::WallTime::now() - last_clock_wall_).toSec() >= 1.0 / opts_.pub_clock_frequency) {
      PublishClock();
    }
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
  ros::Subscriber cmd_sub_, ack_sub_;
  ros::CallbackQueue cmd_queue_;
  ros::Publisher participants_pub_;
  struct TickPublisher {
    ros::Publisher pub;
    bool connected = false;
  };
  std::map<std::string, TickPublisher> ticks_;
  std::unique_ptr<minibot3d_lockstep::Coordinator> coordinator_;
  std::uint64_t tick_seq_ = 0;
  ros::Time last_clock_;
  bool clock_published_ = false;
  ros::WallTime last_clock_wall_;
  std::vector<ros::ServiceServer> services_;
  ros::Publisher tf_pub_, tf_static_pub_;
  tf2_msgs::TFMessage static_tf_;
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
