// minibot3d_sim node: the ROS face of the simulator core (simulator.h). It reads its parameters
// (sim_node_options.h), robot_description and the world; the robot's topics are RobotInterface's,
// lock-step time LockstepHost's. It publishes /clock, the collisions and the status, offers
// reset/pause/unpause/step/set_pose, and paces sim time against the wall clock
// (~real_time_factor; 0 = as fast as possible). All physics and sensing live in the core.
#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <ros/callback_queue.h>
#include <ros/package.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <std_srvs/Empty.h>

#include "node/lockstep_host.h"
#include "minibot3d_lockstep/participant.h"
#include "minibot3d_ros/params.h"
#include "minibot3d_sim/SimActors.h"
#include "minibot3d_sim/Collision.h"
#include "minibot3d_sim/SetPose.h"
#include "minibot3d_sim/SimStatus.h"
#include "minibot3d_sim/Step.h"
#include "minibot3d_sim/robot_model.h"
#include "minibot3d_sim/sim_node_options.h"
#include "minibot3d_sim/simulator.h"
#include "minibot3d_sim/world_loader.h"
#include "node/robot_interface.h"

namespace minibot3d_sim {
namespace {

// Every controller gazebo_ros_control would load: the namespaces under the robot's that hold a
// `type`, each with its keys as text (nested keys joined by '/').
ControllerParams ReadControllers(const std::string& robot_namespace) {
  ControllerParams out;
  ros::NodeHandle nh(robot_namespace.empty() ? "/" : robot_namespace);
  XmlRpc::XmlRpcValue all;
  if (!nh.getParam(nh.getNamespace() == "/" ? "/" : nh.getNamespace(), all) ||
      all.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
    return out;
  }
  std::function<void(XmlRpc::XmlRpcValue&, const std::string&, std::map<std::string, std::string>*)>
      flatten = [&](XmlRpc::XmlRpcValue& v, const std::string& prefix,
                    std::map<std::string, std::string>* keys) {
        for (auto it = v.begin(); it != v.end(); ++it) {
          const std::string key = prefix.empty() ? it->first : prefix + "/" + it->first;
          if (it->second.getType() == XmlRpc::XmlRpcValue::TypeStruct) {
            flatten(it->second, key, keys);
          } else {
            std::string text;
            if (minibot3d_ros::XmlToText(it->second, &text)) (*keys)[key] = text;
          }
        }
      };
  for (auto it = all.begin(); it != all.end(); ++it) {
    if (it->second.getType() != XmlRpc::XmlRpcValue::TypeStruct || !it->second.hasMember("type")) {
      continue;
    }
    flatten(it->second, "", &out[it->first]);
  }
  return out;
}

class SimNode {
 public:
  SimNode() : pnh_("~") {}

  // Reads a robot description from the parameter `param` (its plugins' topics resolved in
  // `robot_namespace`); false (after a fatal message) if it is missing or bad.
  bool LoadRobot(const std::string& param, const std::string& robot_namespace, bool named,
                 std::string* xml, RobotModel* robot) {
    if (!nh_.getParam(param, *xml)) {
      ROS_FATAL("minibot3d_sim: parameter %s is not set (load the robot's xacro, e.g. with "
                "minibot3d_gazebo.launch)", ros::names::resolve(param).c_str());
      return false;
    }
    try {
      RobotModelOptions model_options;
      model_options.spawn_namespace = robot_namespace;
      model_options.replace_namespaces = named;
      if (xml->find("libgazebo_ros_control.so") != std::string::npos) {
        model_options.controllers = ReadControllers(robot_namespace);
      }
      model_options.resolve_mesh_url = [](const std::string& url) -> std::string {
        const std::string kPackage = "package://";
        if (url.compare(0, kPackage.size(), kPackage) != 0) {
          return url.compare(0, 7, "file://") == 0 ? url.substr(7) : url;
        }
        const std::string rest = url.substr(kPackage.size());
        const std::string pkg = rest.substr(0, rest.find('/'));
        const std::string dir = ros::package::getPath(pkg);
        return dir.empty() ? "" : dir + rest.substr(pkg.size());
      };
      *robot = ParseRobotModel(*xml, model_options);
    } catch (const RobotModelError& e) {
      ROS_FATAL("minibot3d_sim: %s: %s", ros::names::resolve(param).c_str(), e.what());
      return false;
    }
    for (const auto& w : robot->warnings) {
      ROS_WARN("minibot3d_sim: %s: %s", ros::names::resolve(param).c_str(), w.c_str());
    }
    return true;
  }

  // Reads parameters, robot_description and the world; false (after a fatal message) if any is bad.
  bool Init() {
    lockstep_ = minibot3d_lockstep::LockstepEnabled();
    minibot3d_ros::ParamReport report =
        minibot3d_ros::LoadTable(pnh_, SimNodeOptionTable(), &options_);
    // lockstep_participants may also be one string of names separated by spaces.
    std::vector<std::string> participants;
    for (const auto& item : options_.lockstep_participants) {
      std::istringstream in(item);
      for (std::string n; in >> n;) participants.push_back(ros::names::resolve(n, false));
    }
    options_.lockstep_participants = participants;
    try {
      report.ThrowIfBad();
      ValidateSimNodeOptions(options_, lockstep_);
    } catch (const std::invalid_argument& e) {
      ROS_FATAL("minibot3d_sim: %s", e.what());
      return false;
    }
    // robots may also be one string of names separated by spaces, or a number N: robot1..robotN.
    names_.clear();
    std::vector<std::string>& names = names_;
    for (const auto& item : options_.robots) {
      std::istringstream in(item);
      for (std::string n; in >> n;) names.push_back(n);
    }
    if (names.size() == 1 && !names[0].empty() &&
        names[0].find_first_not_of("0123456789") == std::string::npos) {
      const int count = std::stoi(names[0]);
      names.clear();
      for (int k = 1; k <= count; ++k) names.push_back("robot" + std::to_string(k));
    }

    for (const std::string& name : names) report.Known(name);
    report.WarnUnknown("minibot3d_sim");
    if (options_.world.empty()) {
      options_.world = ros::package::getPath("minibot3d_sim") + "/worlds/default.world";
    }

    WorldLoadOptions load;
    load.floorplan_wall_height = options_.floorplan_wall_height;
    std::vector<std::string> warnings;
    World world;
    try {
      world = LoadWorld(options_.world, load, &warnings);
    } catch (const WorldError& e) {
      ROS_FATAL("minibot3d_sim: ~world: %s", e.what());
      return false;
    }
    for (const auto& w : warnings) ROS_WARN("minibot3d_sim: world: %s", w.c_str());

    std::vector<RobotEntry> robots;
    if (names.empty()) {
      RobotEntry e;
      e.options = ToRobotOptions("", RobotDefaults(options_));
      e.options.name.clear();
      robot_namespaces_.push_back(options_.robot_namespace);
      urdf_xmls_.emplace_back();
      if (!LoadRobot("robot_description", options_.robot_namespace, false, &urdf_xmls_.back(),
                     &e.model)) {
        return false;
      }
      robots.push_back(std::move(e));
    } else {
      for (const std::string& name : names) {
        const std::string problem = RobotNameProblem(name);
        if (!problem.empty()) {
          ROS_FATAL("minibot3d_sim: ~robots: %s", problem.c_str());
          return false;
        }
        RobotEntry e;
        RobotNodeOptions ro = RobotDefaults(options_);
        ros::NodeHandle robot_pnh(pnh_, name);
        minibot3d_ros::ParamReport robot_report =
            minibot3d_ros::LoadTable(robot_pnh, RobotNodeOptionTable(), &ro);
        try {
          robot_report.ThrowIfBad();
          e.options = ToRobotOptions(name, ro);
        } catch (const std::invalid_argument& ex) {
          ROS_FATAL("minibot3d_sim: %s", ex.what());
          return false;
        }
        robot_report.WarnUnknown("minibot3d_sim");
        const std::string ns = ros::NodeHandle(nh_, name).getNamespace();
        robot_namespaces_.push_back(ns);
        urdf_xmls_.emplace_back();
        if (!LoadRobot(ns + "/robot_description", ns, true, &urdf_xmls_.back(), &e.model)) {
          return false;
        }
        robots.push_back(std::move(e));
      }
    }

    const SimulatorOptions sim = ToSimulatorOptions(options_);
    try {
      sim_ = names.empty() ? std::make_unique<Simulator>(robots[0].model, std::move(world), sim)
                           : std::make_unique<Simulator>(std::move(robots), std::move(world), sim);
    } catch (const std::exception& e) {
      ROS_FATAL("minibot3d_sim: %s", e.what());
      return false;
    }
    for (size_t r = 0; r < sim_->robot_count(); ++r) {
      const SimRobot& robot = sim_->at(r);
      std::string what;
      const Pose2 spawn = robot.options().spawn;
      if (robot.PoseCollides(spawn, &what)) {
        ROS_FATAL("minibot3d_sim: %sthe spawn pose x=%g y=%g yaw=%g overlaps '%s' in %s",
                  robot.name().empty() ? "" : ("robot " + robot.name() + ": ").c_str(), spawn.x,
                  spawn.y, spawn.yaw, what.c_str(), options_.world.c_str());
        return false;
      }
    }

    // In lock-step a participant counts on receiving every message the simulator queued to it, so
    // outgoing queues must not drop (see RobotInterface).
    const auto q = [this](int free_running) { return lockstep_ ? 100000 : free_running; };
    // Latched: a node that starts while sim time is held (lock-step, or paused) gets the current
    // time at once; roscpp nodes wait for a first /clock (actionlib's clients, for one).
    clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", q(10), true);
    tf_static_pub_ = nh_.advertise<tf2_msgs::TFMessage>("/tf_static", 1, true);
    for (size_t r = 0; r < sim_->robot_count(); ++r) {
      SimRobot& robot = sim_->at(r);
      RobotInterface::Options ro;
      ro.lockstep = lockstep_;
      ro.publish_ground_truth = options_.publish_ground_truth;
      ro.world_frame = options_.world_frame;
      ro.frame_prefix = robot.name().empty() ? "" : robot.name() + "/";
      Robot x;
      x.sim = &robot;
      x.ros = std::make_unique<RobotInterface>(&robot, urdf_xmls_[r], ro, &cmd_queue_);
      // A named robot's simulator topics and services: NAME/minibot3d_sim/...
      ros::NodeHandle own = robot.name().empty()
                                ? pnh_
                                : ros::NodeHandle(ros::NodeHandle(nh_, robot.name()),
                                                  ros::this_node::getName().substr(1));
      x.collision_pub = own.advertise<Collision>("collisions", q(50));
      if (!robot.name().empty()) {
        x.status_pub = own.advertise<SimStatus>("status", q(5), true);
        services_.push_back(own.advertiseService<std_srvs::Empty::Request, std_srvs::Empty::Response>(
            "reset", [this, r](std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
              return ResetRobot(r);
            }));
        services_.push_back(own.advertiseService<SetPose::Request, SetPose::Response>(
            "set_pose", [this, r](SetPose::Request& req, SetPose::Response& res) {
              return SetRobotPose(r, req, &res);
            }));
      }
      robots_.push_back(std::move(x));
    }
    status_pub_ = pnh_.advertise<SimStatus>("status", q(5), true);
    if (sim_->actor_count() > 0) actors_pub_ = pnh_.advertise<SimActors>("actors", q(5));
    if (lockstep_) {
      LockstepHost::Options lo;
      lo.coordinator.quantum = options_.lockstep_quantum;
      lo.coordinator.timeout = options_.lockstep_timeout;
      lo.participants = options_.lockstep_participants;
      lo.start_timeout = options_.lockstep_start_timeout;
      lockstep_host_ = std::make_unique<LockstepHost>(
          nh_, lo, [this] { return sim_->time(); }, [this](bool again) { PublishClock(again); },
          [this] { cmd_queue_.callAvailable(); });
    }
    services_.push_back(pnh_.advertiseService("reset", &SimNode::OnReset, this));
    services_.push_back(pnh_.advertiseService("pause", &SimNode::OnPause, this));
    services_.push_back(pnh_.advertiseService("unpause", &SimNode::OnUnpause, this));
    services_.push_back(pnh_.advertiseService("step", &SimNode::OnStep, this));
    services_.push_back(pnh_.advertiseService("set_pose", &SimNode::OnSetPose, this));
    paused_ = options_.paused;

    ROS_INFO("minibot3d_sim: world %s (%zu shapes), physics %s at %g s, real-time factor %g%s",
             options_.world.c_str(), sim_->world().shapes.size(), sim.physics.c_str(),
             sim.physics_step, options_.real_time_factor, lockstep_ ? ", lock-step" : "");
    for (size_t r = 0; r < sim_->robot_count(); ++r) {
      const SimRobot& robot = sim_->at(r);
      const Pose2 spawn = robot.options().spawn;
      ROS_INFO("minibot3d_sim: robot %s'%s' (%s, %zu lasers, %zu IMUs, %zu cameras) at (%g, %g, %g)",
               robot.name().empty() ? "" : (robot.name() + ": ").c_str(),
               robot.model().name.c_str(), robot.drive().name().c_str(),
               robot.model().lasers.size(), robot.model().imus.size(),
               robot.model().cameras.size(), spawn.x, spawn.y, spawn.yaw);
    }
    return true;
  }

  // Every robot's fixed joints in one latched message (see RobotInterface::AppendStaticTransforms).
  void PublishStaticTransforms() {
    tf2_msgs::TFMessage msg;
    for (auto& r : robots_) r.ros->AppendStaticTransforms(&msg);
    tf_static_pub_.publish(msg);
  }

  void Run() {
    if (lockstep_) {
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
             static_cast<unsigned long>(TotalCollisions()));
  }

 private:
  // Sim time runs on; nodes take messages as they come.
  void RunFree() {
    const auto steps_per_clock =
        std::max<std::uint64_t>(1, std::llround(options_.clock_period / sim_->physics_step()));
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
        1, std::llround(options_.lockstep_quantum / sim_->physics_step()));
    // roscpp takes sim time 0 for "no clock yet" (ros::Time::isValid): nodes such as
    // robot_state_publisher wait for a later time before publishing, latched tf_static included.
    // One physics step with nothing published but the clock gets time going.
    sim_->Step();
    PublishClock();
    // Nothing else is published before the participants a launch file names have joined and made
    // their connections (in their first round): the first messages reach all of them alike.
    lockstep_host_->WaitForExpectedParticipants();
    lockstep_host_->WaitForOwnConnections();
    // The first sensor messages go out before the first round: robot_state_publisher answers
    // the first joint states with the latched tf_static that participants wait for.
    PublishStaticTransforms();
    Publish(true);
    lockstep_host_->RecordSent();
    lockstep_host_->Round();
    lockstep_host_->RecordSent();
    Anchor();
    while (ros::ok()) {
      if (paused_) {
        ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.005));
        Anchor();
        continue;
      }
      lockstep_host_->Round();
      for (std::uint64_t i = 0; i < steps_per_quantum && ros::ok(); ++i) StepOnce();
      lockstep_host_->RecordSent();
      Pace();
      // Non-participants (rviz, a user's script) still see time go by, throttled in wall time.
      MaybePublishClock();
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
    if (actors_pub_ && (all || t + 1e-9 >= actors_published_ / options_.actors_rate)) {
      PublishActors(stamp);
      actors_published_ = std::floor(t * options_.actors_rate + 1e-6) + 1.0;
    }
    bool collided = false;
    for (Robot& r : robots_) {
      r.ros->Publish(all);
      for (const auto& e : r.sim->TakeCollisionEvents()) {
        Collision c;
        c.header.stamp = ros::Time(e.time);
        c.header.frame_id = options_.world_frame;
        c.position.x = e.contact.point.x();
        c.position.y = e.contact.point.y();
        c.position.z = e.contact.point.z();
        c.normal.x = e.contact.normal.x();
        c.normal.y = e.contact.normal.y();
        c.normal.z = e.contact.normal.z();
        c.depth = e.contact.depth;
        c.object = e.shape_name;
        c.count = ++r.published_collisions;
        r.collision_pub.publish(c);
        ROS_WARN_THROTTLE(1.0, "minibot3d_sim: %scollision #%lu with '%s' at (%.2f, %.2f), t=%.2f s",
                          r.sim->name().empty() ? "" : (r.sim->name() + ": ").c_str(),
                          static_cast<unsigned long>(c.count), c.object.c_str(), c.position.x,
                          c.position.y, e.time);
        collided = true;
      }
    }
    if (collided) PublishStatus(stamp);
    if (all || t + 1e-9 >= next_status_) {
      next_status_ = std::floor(t + 1e-6) + 1.0;
      PublishStatus(stamp);
    }
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
    if ((ros::WallTime::now() - last_clock_wall_).toSec() >= 1.0 / options_.pub_clock_frequency) {
      PublishClock();
    }
  }

  // The actors where they are (for evaluation; a robot's stack does not read it).
  void PublishActors(const ros::Time& stamp) {
    SimActors m;
    m.header.stamp = stamp;
    m.header.frame_id = options_.world_frame;
    for (size_t k = 0; k < sim_->actor_count(); ++k) {
      const ActorState& a = sim_->actor_state(k);
      SimActor out;
      out.name = sim_->world().actors[k].name;
      out.pose.position.x = a.x;
      out.pose.position.y = a.y;
      out.pose.orientation.z = std::sin(0.5 * a.yaw);
      out.pose.orientation.w = std::cos(0.5 * a.yaw);
      out.twist.linear.x = a.vx;
      out.twist.linear.y = a.vy;
      out.twist.angular.z = a.wz;
      out.radius = options_.actor_radius;
      out.height = options_.actor_height;
      m.actors.push_back(out);
    }
    actors_pub_.publish(m);
  }

  // The simulation's status (collisions and contact: all robots'), and each named robot's.
  void PublishStatus(const ros::Time& stamp) {
    const ros::WallTime now = ros::WallTime::now();
    SimStatus s;
    s.header.stamp = stamp;
    s.physics = sim_->backend().name();
    s.sim_time = sim_->time();
    s.steps = sim_->steps();
    s.physics_step = sim_->physics_step();
    s.target_real_time_factor = options_.real_time_factor;
    const double wall = (now - status_wall_).toSec();
    s.real_time_factor = wall > 0 ? (s.sim_time - status_sim_) / wall : 0.0;
    s.paused = paused_;
    s.collisions = TotalCollisions();
    s.in_contact = false;
    for (const Robot& r : robots_) s.in_contact = s.in_contact || r.sim->in_contact();
    status_pub_.publish(s);
    for (const Robot& r : robots_) {
      if (!r.status_pub) continue;
      SimStatus own = s;
      own.collisions = r.sim->collision_count();
      own.in_contact = r.sim->in_contact();
      r.status_pub.publish(own);
    }
    status_wall_ = now;
    status_sim_ = s.sim_time;
  }

  std::uint64_t TotalCollisions() const {
    std::uint64_t n = 0;
    for (const Robot& r : robots_) n += r.sim->collision_count();
    return n;
  }

  // Restarts real-time pacing from the current instant (after start, pause or a rate change).
  void Anchor() {
    anchor_wall_ = ros::WallTime::now();
    anchor_sim_ = sim_->time();
    if (run_wall_start_.isZero()) run_wall_start_ = anchor_wall_;
  }

  void Pace() {
    if (options_.real_time_factor <= 0) return;
    const ros::WallTime target =
        anchor_wall_ + ros::WallDuration((sim_->time() - anchor_sim_) / options_.real_time_factor);
    const ros::WallTime now = ros::WallTime::now();
    if (target > now) {
      (target - now).sleep();
    } else if ((now - target).toSec() > 1.0) {
      // Far behind (the CPU cannot keep up): do not try to catch up in a burst.
      ROS_WARN_THROTTLE(10.0, "minibot3d_sim: running slower than ~real_time_factor %g",
                        options_.real_time_factor);
      Anchor();
    }
  }

  // Every robot back to its spawn pose.
  bool OnReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    for (size_t r = 0; r < sim_->robot_count(); ++r) sim_->at(r).Reset();
    ROS_INFO("minibot3d_sim: reset to the spawn pose%s", sim_->robot_count() > 1 ? "s" : "");
    Publish(true);
    return true;
  }
  bool ResetRobot(size_t r) {
    sim_->at(r).Reset();
    ROS_INFO("minibot3d_sim: %s reset to its spawn pose", sim_->at(r).name().c_str());
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
    if (sim_->robot_count() > 1) {
      res.success = false;
      res.message = "several robots: call NAME/" + ros::this_node::getName().substr(1) +
                    "/set_pose for robot NAME";
      return true;
    }
    return SetRobotPose(0, req, &res);
  }
  bool SetRobotPose(size_t r, SetPose::Request& req, SetPose::Response* res) {
    if (!std::isfinite(req.x) || !std::isfinite(req.y) || !std::isfinite(req.yaw)) {
      res->success = false;
      res->message = "x, y and yaw must be finite";
      return true;
    }
    std::string what;
    const Pose2 pose{req.x, req.y, req.yaw};
    if (sim_->at(r).PoseCollides(pose, &what)) {
      res->success = false;
      std::ostringstream msg;
      msg << "pose (" << req.x << ", " << req.y << ", " << req.yaw << ") overlaps '" << what << "'";
      res->message = msg.str();
      return true;
    }
    sim_->at(r).SetPose(pose);
    res->success = true;
    res->message = "teleported";
    Publish(true);
    return true;
  }

  ros::NodeHandle nh_, pnh_;
  SimNodeOptions options_;
  bool lockstep_ = false;
  // One per robot: its core, its ROS side, its collisions (and status and services, if named).
  struct Robot {
    SimRobot* sim = nullptr;
    std::unique_ptr<RobotInterface> ros;
    ros::Publisher collision_pub, status_pub;
    std::uint64_t published_collisions = 0;
  };
  std::vector<std::string> names_, robot_namespaces_, urdf_xmls_;
  std::unique_ptr<Simulator> sim_;
  std::vector<Robot> robots_;
  std::unique_ptr<LockstepHost> lockstep_host_;
  ros::CallbackQueue cmd_queue_;
  ros::Publisher clock_pub_, status_pub_, tf_static_pub_, actors_pub_;
  double actors_published_ = 0.0;  // ~actors messages sent (the next is due at this / rate)
  ros::Time last_clock_;
  bool clock_published_ = false;
  ros::WallTime last_clock_wall_;
  std::vector<ros::ServiceServer> services_;
  double next_status_ = 0.0;
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
