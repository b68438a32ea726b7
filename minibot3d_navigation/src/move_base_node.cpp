// move_base: ROS 1 node wrapping the ROS-free navigation core, a drop-in for
// the navigation stack's move_base.  Same action (move_base_msgs/MoveBase),
// topics (move_base_simple/goal, cmd_vel, odom, scan, map), parameters (its
// own, ~global_costmap/, ~local_costmap/, ~TrajectoryPlannerROS/ or
// ~DWAPlannerROS/, ~NavfnROS/ or ~GlobalPlanner/) and services (~make_plan,
// ~clear_costmaps).  The state machine, planners, controller and costmaps are
// in the core; this file converts goals, poses, scans and maps and runs the
// control loop on the ROS (simulator) clock.  The costmaps' frames take the
// robot's frame_prefix when several robots share one tf tree
// (minibot3d_ros/frames.h).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <actionlib/server/simple_action_server.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/Twist.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <nav_msgs/GetPlan.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <std_srvs/Empty.h>
#include <tf2/utils.h>
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>
#include <tf2_ros/buffer.h>

#include "costmap_ros.h"
#include "minibot3d_lockstep/participant.h"
#include "minibot3d_lockstep/transform_listener.h"
#include "minibot3d_navigation/costmap/costmap_options.h"
#include "minibot3d_navigation/dwa/dwa_options.h"
#include "minibot3d_navigation/dwa/dwa_planner.h"
#include "minibot3d_navigation/move_base/back_out_recovery.h"
#include "minibot3d_navigation/move_base/clear_costmap_recovery.h"
#include "minibot3d_navigation/move_base/move_base_options.h"
#include "minibot3d_navigation/move_base/navigation_executive.h"
#include "minibot3d_navigation/move_base/recovery_behavior.h"
#include "minibot3d_navigation/move_base/rotate_recovery.h"
#include "minibot3d_navigation/move_base/wait_recovery.h"
#include "minibot3d_navigation/planner/planner_factory.h"
#include "minibot3d_navigation/planner/planner_options.h"
#include "minibot3d_navigation/tracking/obstacle_tracker.h"
#include "minibot3d_ros/conversions.h"
#include "minibot3d_ros/frames.h"
#include "minibot3d_ros/params.h"

namespace minibot3d_navigation {
namespace {

using MoveBaseServer = actionlib::SimpleActionServer<move_base_msgs::MoveBaseAction>;
using minibot3d_ros::ParamReport;

// Sub-namespaces of move_base's own whose keys the node reads with their own tables.
const char* const kCostmapNamespaces[] = {"global_costmap", "local_costmap"};
const char* const kLocalPlannerNamespaces[] = {"TrajectoryPlannerROS", "DWAPlannerROS"};
const char* const kGlobalPlannerNamespaces[] = {"NavfnROS", "GlobalPlanner", "OmplPlanner"};

std::string JoinLines(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& p : v) s += "\n  " + p;
  return s;
}

class MoveBaseNode {
 public:
  MoveBaseNode()
      : pnh_("~"),
        lockstep_(nh_, LockstepOptions()),
        tf_listener_(tf_, lockstep_),
        global_costmap_("global_costmap", &tf_),
        local_costmap_("local_costmap", &tf_) {}

  // Reads every parameter; throws std::invalid_argument naming each problem.
  void Configure() {
    ParamReport report = minibot3d_ros::LoadTable(pnh_, nav::MoveBaseOptionTable(), &mb_);
    minibot3d_ros::FrameOptions frame_options;
    report.Also(minibot3d_ros::LoadFrameOptions(pnh_, &frame_options));
    for (const char* ns : kCostmapNamespaces) report.Known(ns);
    for (const char* ns : kLocalPlannerNamespaces) report.Known(ns);
    for (const char* ns : kGlobalPlannerNamespaces) report.Known(ns);
    // ROS move_base's recoveries read ~<name>/; ours take theirs from move_base's own keys.
    for (const std::string& name : RecoveryNames()) report.Known(name);
    report.Known("obstacle_tracker");
    report.WarnUnknown("move_base");
    std::vector<std::string> problems = report.problems;
    try {
      nav::ValidateMoveBaseOptions(mb_);
    } catch (const std::invalid_argument& e) {
      problems.push_back(e.what());
    }

    // Local planner parameters: the namespace named by base_local_planner.
    const bool dwa_ns = mb_.base_local_planner.find("DWAPlannerROS") != std::string::npos;
    if (mb_.base_local_planner != "base_local_planner/TrajectoryPlannerROS" &&
        mb_.base_local_planner != "dwa_local_planner/DWAPlannerROS") {
      problems.push_back("~base_local_planner: '" + mb_.base_local_planner +
                         "' is not one of base_local_planner/TrajectoryPlannerROS, "
                         "dwa_local_planner/DWAPlannerROS (both run minibot3d's DWA)");
    }
    local_ns_ = dwa_ns ? "DWAPlannerROS" : "TrajectoryPlannerROS";
    const ros::NodeHandle lnh(pnh_, local_ns_);
    ParamReport local = minibot3d_ros::LoadTable(lnh, nav::dwa::DwaOptionTable(), &dwa_);
    const ParamReport aliases = minibot3d_ros::LoadTable(lnh, nav::dwa::DwaAliasOptionTable(), &dwa_);
    for (const std::string& name : aliases.read) {
      if (nav::dwa::IsSymmetricRotationName(name)) nav::dwa::ApplySymmetricRotation(&dwa_);
    }
    local.Also(aliases);
    for (const std::string& name : nav::dwa::DwaIgnoredOptionNames()) local.Known(name);
    local.WarnUnknown("move_base");
    problems.insert(problems.end(), local.problems.begin(), local.problems.end());
    dwa_.controller_frequency = mb_.controller_frequency;

    // The moving-obstacle tracker: ~obstacle_tracker.
    const ParamReport tracking = minibot3d_ros::LoadTable(
        ros::NodeHandle(pnh_, "obstacle_tracker"), nav::ObstacleTrackerOptionTable(), &tracker_);
    tracking.WarnUnknown("move_base");
    problems.insert(problems.end(), tracking.problems.begin(), tracking.problems.end());
    try {
      nav::ValidateObstacleTrackerOptions(tracker_);
    } catch (const std::invalid_argument& e) {
      problems.push_back(e.what());
    }

    // Global planner parameters: ~NavfnROS, ~GlobalPlanner, ~OmplPlanner.
    planner_.base_global_planner = mb_.base_global_planner;
    for (const char* ns : kGlobalPlannerNamespaces) {
      const ParamReport global =
          minibot3d_ros::LoadTable(ros::NodeHandle(pnh_, ns), nav::GlobalPlannerOptionTable(),
                                   &planner_);
      global.WarnUnknown("move_base");
      problems.insert(problems.end(), global.problems.begin(), global.problems.end());
    }

    minibot3d_ros::FrameNames frames;  // a bad frame_prefix is among the problems already
    try {
      frames = minibot3d_ros::FrameNames(frame_options);
    } catch (const std::invalid_argument&) {
    }
    for (CostmapRos* c : {&global_costmap_, &local_costmap_}) {
      try {
        c->Configure(frames);
      } catch (const std::invalid_argument& e) {
        problems.push_back(e.what());
      }
    }
    if (!problems.empty()) throw std::invalid_argument(JoinLines(problems));
    if (!frames.prefix().empty()) {
      ROS_INFO("move_base: frames: global costmap %s, local costmap %s, robot %s (frame_prefix "
               "%s)", global_costmap_.options().global_frame.c_str(),
               local_costmap_.options().global_frame.c_str(),
               local_costmap_.options().robot_base_frame.c_str(), frames.prefix().c_str());
    }

    // The planners (validate their options on construction).
    try {
      global_planner_ = nav::MakeGlobalPlanner(planner_, global_costmap_.footprint());
      local_planner_ = std::make_unique<nav::dwa::DwaPlanner>(dwa_, local_costmap_.footprint());
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("\n  ") + e.what());
    }
    if (tracker_.enabled) {
      obstacle_tracker_ = std::make_unique<nav::ObstacleTracker>(tracker_);
      local_costmap_.set_observation_callback(
          [this](double stamp, const nav::Observation& obs) {
            pending_observations_.push_back({stamp, obs.origin, obs.hits});
          });
    }
    BuildRecoveries();
    executive_ = std::make_unique<nav::NavigationExecutive>(
        mb_, global_planner_.get(), local_planner_.get(), recovery_ptrs_);
    ROS_INFO("move_base: global planner %s, local planner %s (~%s), %zu recovery behaviours",
             global_planner_->name().c_str(), local_planner_->name().c_str(), local_ns_.c_str(),
             recovery_ptrs_.size());
  }

  void Start() {
    global_costmap_.Start();
    local_costmap_.Start();
    cmd_pub_ = nh_.advertise<geometry_msgs::Twist>("cmd_vel", 1);
    goal_pub_ = pnh_.advertise<geometry_msgs::PoseStamped>("current_goal", 1, true);
    plan_pub_ = pnh_.advertise<nav_msgs::Path>(
        (mb_.base_global_planner == "ompl" ? "OmplPlanner" : "NavfnROS") + std::string("/plan"), 1);
    local_global_plan_pub_ = pnh_.advertise<nav_msgs::Path>(local_ns_ + "/global_plan", 1);
    local_plan_pub_ = pnh_.advertise<nav_msgs::Path>(local_ns_ + "/local_plan", 1);
    odom_sub_ = nh_.subscribe("odom", 1, &MoveBaseNode::OnOdom, this);
    simple_goal_sub_ = nh_.subscribe("move_base_simple/goal", 1, &MoveBaseNode::OnSimpleGoal, this);
    ros::NodeHandle snh = lockstep_.ServiceHandle(pnh_);
    make_plan_srv_ = snh.advertiseService("make_plan", &MoveBaseNode::OnMakePlan, this);
    clear_srv_ = snh.advertiseService("clear_costmaps", &MoveBaseNode::OnClearCostmaps, this);
    server_ = std::make_unique<MoveBaseServer>(nh_, "move_base", false);
    server_->registerGoalCallback([this] { OnGoal(); });
    server_->registerPreemptCallback([this] { OnPreempt(); });
    server_->start();
    lockstep_.AddPeriodic(1.0 / mb_.controller_frequency, [this](const ros::Time&) { OnControl(); });
  }

  // Until shutdown: ros::spin(), or the lock-step loop under /use_lockstep.
  bool Spin() { return lockstep_.Spin(); }

 private:
  // recovery_behaviors, or move_base's default list (after wait and back_out when they are on).
  std::vector<std::string> RecoveryNames() const {
    std::vector<std::string> names = mb_.recovery_behaviors;
    if (names.empty()) {
      if (mb_.wait_duration > 0.0) names.push_back("wait");
      if (mb_.back_out_distance > 0.0) names.push_back("back_out");
      names.push_back("conservative_reset");
      if (mb_.clearing_rotation_allowed) names.push_back("rotate_recovery");
      names.push_back("aggressive_reset");
      if (mb_.clearing_rotation_allowed) names.push_back("rotate_recovery");
    }
    return names;
  }

  void BuildRecoveries() {
    const std::vector<std::string> names = RecoveryNames();
    nav::RotateRecoveryOptions rot;
    rot.max_rotational_vel = dwa_.max_vel_theta;
    rot.min_rotational_vel = dwa_.min_in_place_vel_theta;
    rot.acc_lim_th = dwa_.acc_lim_theta;
    rot.frequency = mb_.controller_frequency;
    nav::BackOutOptions back;
    back.distance = mb_.back_out_distance;
    back.vel = mb_.back_out_vel;
    back.max_rotational_vel = dwa_.max_vel_theta;
    back.min_rotational_vel = dwa_.min_in_place_vel_theta;
    nav::WaitOptions wait;
    wait.duration = mb_.wait_duration;
    wait.backoff_vel = mb_.back_out_vel;
    for (const std::string& n : names) {
      if (n == "wait") {
        recoveries_.push_back(std::make_unique<nav::WaitRecovery>(n, wait, local_costmap_.footprint()));
      } else if (n == "back_out") {
        recoveries_.push_back(
            std::make_unique<nav::BackOutRecovery>(n, back, local_costmap_.footprint()));
      } else if (n == "rotate_recovery") {
        recoveries_.push_back(
            std::make_unique<nav::RotateRecovery>(n, rot, local_costmap_.footprint()));
      } else {
        // aggressive_reset clears everything outside the robot's footprint
        // (move_base: a square of side 4 x the circumscribed radius).
        const double d = n == "conservative_reset"
                             ? mb_.conservative_reset_dist
                             : 4.0 * local_costmap_.layered().circumscribed_radius();
        recoveries_.push_back(std::make_unique<nav::ClearCostmapRecovery>(
            n, d, [this](double reset_distance) { ClearAround(reset_distance); }));
      }
      recovery_ptrs_.push_back(recoveries_.back().get());
    }
  }

  void ClearAround(double reset_distance) {
    nav::Pose2 p;
    std::string why;
    for (CostmapRos* c : {&global_costmap_, &local_costmap_}) {
      if (c->RobotPose(&p, &why)) c->ClearExceptAround(p, reset_distance);
    }
  }

  void OnOdom(const nav_msgs::Odometry::ConstPtr& odom) {
    velocity_.vx = odom->twist.twist.linear.x;
    velocity_.vy = odom->twist.twist.linear.y;
    velocity_.wz = odom->twist.twist.angular.z;
  }

  // Goal pose -> global frame, once, at reception.  Empty string on success,
  // else the reason to reject it.
  std::string ToGlobal(const geometry_msgs::PoseStamped& in, nav::Pose2* out) {
    const auto& q = in.pose.orientation;
    const double n = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    if (!std::isfinite(n) || n < 1e-6 || !std::isfinite(in.pose.position.x) ||
        !std::isfinite(in.pose.position.y)) {
      return "goal has an invalid pose (position or quaternion not finite, or quaternion of "
             "length 0)";
    }
    tf2::Quaternion tq(q.x / n, q.y / n, q.z / n, q.w / n);
    // A goal must be planar: its z axis may not tip more than ~1 degree.
    if (std::fabs(tf2::Matrix3x3(tq).getColumn(2).z() - 1.0) > 1e-3) {
      return "goal quaternion is not a rotation about z (the goal must lie in the plane)";
    }
    geometry_msgs::PoseStamped normalized = in;
    normalized.pose.orientation = tf2::toMsg(tq);
    const std::string frame = in.header.frame_id.empty() ? global_costmap_.options().global_frame
                                                         : in.header.frame_id;
    normalized.header.frame_id = frame;
    normalized.header.stamp = ros::Time(0);  // latest: "1 m ahead of where the robot is now"
    try {
      geometry_msgs::PoseStamped g;
      tf2::doTransform(normalized, g,
                       lockstep_.LookupTransform(tf_, global_costmap_.options().global_frame,
                                                 normalized.header.frame_id,
                                                 normalized.header.stamp, 0.5));
      out->x = g.pose.position.x;
      out->y = g.pose.position.y;
      out->yaw = tf2::getYaw(g.pose.orientation);
      return "";
    } catch (const tf2::TransformException& e) {
      return "cannot transform the goal from frame '" + frame + "' into '" +
             global_costmap_.options().global_frame + "': " + e.what();
    }
  }

  void OnGoal() {
    const auto goal = server_->acceptNewGoal();
    nav::Pose2 g;
    const std::string error = ToGlobal(goal->target_pose, &g);
    if (!error.empty()) {
      ROS_ERROR("move_base: rejecting goal: %s", error.c_str());
      executive_->Cancel();
      PublishZero();
      server_->setAborted(move_base_msgs::MoveBaseResult(), error);
      return;
    }
    ROS_INFO("move_base: new goal (%.2f, %.2f, yaw %.2f) in %s", g.x, g.y, g.yaw,
             global_costmap_.options().global_frame.c_str());
    executive_->SetGoal(g, ros::Time::now().toSec());
    geometry_msgs::PoseStamped cg;
    cg.header.frame_id = global_costmap_.options().global_frame;
    cg.header.stamp = ros::Time::now();
    cg.pose.position.x = g.x;
    cg.pose.position.y = g.y;
    cg.pose.orientation = tf2::toMsg(minibot3d_ros::TfFromPose(g).getRotation());
    goal_pub_.publish(cg);
  }

  void OnPreempt() {
    executive_->Cancel();
    PublishZero();
    if (server_->isActive()) server_->setPreempted(move_base_msgs::MoveBaseResult(), "cancelled");
  }

  void OnSimpleGoal(const geometry_msgs::PoseStamped::ConstPtr& goal) {
    // As move_base: wrap it into an action goal to ourselves.
    if (!simple_client_pub_) {
      simple_client_pub_ = nh_.advertise<move_base_msgs::MoveBaseActionGoal>("move_base/goal", 1);
    }
    move_base_msgs::MoveBaseActionGoal ag;
    ag.header.stamp = ros::Time::now();
    ag.goal_id.stamp = ag.header.stamp;
    ag.goal.target_pose = *goal;
    simple_client_pub_.publish(ag);
  }

  void PublishZero() { cmd_pub_.publish(geometry_msgs::Twist()); }

  static nav_msgs::Path ToPath(const nav::Path& path, const std::string& frame,
                               const ros::Time& stamp) {
    nav_msgs::Path msg;
    msg.header.frame_id = frame;
    msg.header.stamp = stamp;
    for (const nav::Pose2& p : path) {
      geometry_msgs::PoseStamped ps;
      ps.header = msg.header;
      ps.pose.position.x = p.x;
      ps.pose.position.y = p.y;
      ps.pose.orientation = tf2::toMsg(minibot3d_ros::TfFromPose(p).getRotation());
      msg.poses.push_back(ps);
    }
    return msg;
  }

  // Woken by goals as well as by the control period: a goal is accepted at once.
  static minibot3d_lockstep::ParticipantOptions LockstepOptions() {
    minibot3d_lockstep::ParticipantOptions o;
    o.wake_topics = {"move_base/goal", "move_base/cancel", "move_base_simple/goal"};
    return o;
  }

  // What to check when the robot's pose cannot be looked up, naming the frames involved: the
  // localizer's global -> local (e.g. amcl's map -> odom) when the global costmap failed and its
  // frame differs from the local one's; else odometry's local -> robot base (mapless mode, where
  // both costmaps are in odom).
  std::string PoseHint(bool global_failed) const {
    const nav::CostmapOptions& g = global_costmap_.options();
    const nav::CostmapOptions& l = local_costmap_.options();
    if (global_failed && g.global_frame != l.global_frame) {
      return "Is the localizer (amcl or SLAM) publishing " + g.global_frame + " -> " +
             l.global_frame + "?";
    }
    return "Is the odometry (the simulator) publishing " + l.global_frame + " -> the robot (" +
           l.robot_base_frame + ")? rosrun tf tf_echo " + l.global_frame + " " +
           l.robot_base_frame + " shows what tf has";
  }

  void OnControl() {
    const ros::Time now = ros::Time::now();
    nav::RobotState state;
    state.time = now.toSec();
    state.velocity = velocity_;
    std::string why;
    bool clocks_disagree = false;
    const bool have_global =
        global_costmap_.RobotPose(&state.global_pose, &why, &clocks_disagree);
    const bool have_local =
        have_global && local_costmap_.RobotPose(&state.local_pose, &why, &clocks_disagree);
    if (!have_global || !have_local) {
      if (!clocks_disagree) {
        while (!why.empty() && why.back() == ' ') why.pop_back();
        why += (!why.empty() && why.back() == '.' ? " " : ". ") + PoseHint(!have_global);
      }
      ROS_WARN_THROTTLE(5.0, "move_base: robot pose unknown: %s", why.c_str());
      if (executive_->active()) PublishZero();
      return;
    }
    global_costmap_.Update(now, state.global_pose);
    local_costmap_.Update(now, state.local_pose);
    if (obstacle_tracker_) {
      // The observations stamped before this cycle, in stamp order: one stamped now may or may
      // not have arrived yet, so it waits for the next cycle (the same run every time on
      // lock-step time). Fed with or without a goal, so none pile up while the robot is idle.
      std::stable_sort(pending_observations_.begin(), pending_observations_.end(),
                       [](const PendingObservation& a, const PendingObservation& b) {
                         return a.stamp < b.stamp;
                       });
      size_t used = 0;
      for (; used < pending_observations_.size() &&
             pending_observations_[used].stamp < now.toSec();
           ++used) {
        const PendingObservation& o = pending_observations_[used];
        obstacle_tracker_->Update(o.stamp, o.origin, o.hits);
      }
      pending_observations_.erase(pending_observations_.begin(),
                                  pending_observations_.begin() + used);
    }
    if (!executive_->active()) return;
    if (!global_costmap_.ready()) {
      ROS_WARN_THROTTLE(5.0, "move_base: waiting for the map on %s to plan",
                        ros::names::resolve("map").c_str());
      PublishZero();
      return;
    }
    state.global_costmap = &global_costmap_.costmap();
    state.local_costmap = &local_costmap_.costmap();
    // The global frame's pose in the local one: local = global_to_local (+) global.
    const nav::Pose2 global_to_local =
        nav::Compose(state.local_pose, nav::Between(state.global_pose, nav::Pose2()));
    if (obstacle_tracker_) {
      std::vector<nav::dwa::MovingObstacle> moving;
      for (const nav::TrackedObstacle& t : obstacle_tracker_->MovingAt(now.toSec())) {
        moving.push_back({t.position, t.velocity, t.radius, t.outline});
      }
      local_planner_->SetMovingObstacles(moving);
    }
    if (const nav::InflationLayer* inflation = global_costmap_.layered().inflation_layer()) {
      // The wait recovery's test of an open way: the robot fits at any heading.
      // (Inflation that ends inside the circumscribed radius gives no such cost: then the
      // planner's own test.)
      const double circumscribed = global_costmap_.layered().circumscribed_radius();
      const uint8_t cost =
          inflation->ComputeCost(circumscribed / global_costmap_.costmap().resolution());
      executive_->SetOpenWayTest(cost > 0 ? cost : nav::kInscribedInflatedObstacle,
                                 circumscribed);
    }
    const nav::CycleResult r = executive_->Step(state, global_to_local);

    geometry_msgs::Twist cmd;
    cmd.linear.x = r.cmd.vx;
    cmd.angular.z = r.cmd.wz;
    cmd_pub_.publish(cmd);
    if (r.new_plan) {
      plan_pub_.publish(ToPath(executive_->plan(), global_costmap_.options().global_frame, now));
    }
    if (executive_->state() == nav::NavState::kControlling && r.status == nav::GoalStatus::kActive) {
      local_global_plan_pub_.publish(
          ToPath(local_planner_->pruned_plan(), local_costmap_.options().global_frame, now));
      local_plan_pub_.publish(ToPath(local_planner_->last_trajectory().poses,
                                     local_costmap_.options().global_frame, now));
    }
    if (!server_->isActive()) return;
    switch (r.status) {
      case nav::GoalStatus::kActive: {
        move_base_msgs::MoveBaseFeedback fb;
        fb.base_position.header.frame_id = global_costmap_.options().global_frame;
        fb.base_position.header.stamp = now;
        fb.base_position.pose.position.x = state.global_pose.x;
        fb.base_position.pose.position.y = state.global_pose.y;
        fb.base_position.pose.orientation =
            tf2::toMsg(minibot3d_ros::TfFromPose(state.global_pose).getRotation());
        server_->publishFeedback(fb);
        if (!r.message.empty() && r.message != last_message_) {
          ROS_WARN("move_base: %s", r.message.c_str());
        }
        last_message_ = r.message;
        break;
      }
      case nav::GoalStatus::kSucceeded:
        PublishZero();
        ROS_INFO("move_base: goal reached");
        server_->setSucceeded(move_base_msgs::MoveBaseResult(), r.message);
        break;
      case nav::GoalStatus::kAborted:
        PublishZero();
        ROS_ERROR("move_base: aborting goal: %s", r.message.c_str());
        server_->setAborted(move_base_msgs::MoveBaseResult(), r.message);
        break;
      case nav::GoalStatus::kNone:
        break;
    }
  }

  bool OnMakePlan(nav_msgs::GetPlan::Request& req, nav_msgs::GetPlan::Response& res) {
    if (!global_costmap_.ready()) {
      ROS_ERROR("move_base: make_plan: no map yet");
      return false;
    }
    nav::Pose2 start, goal;
    std::string error;
    if (req.start.header.frame_id.empty()) {
      if (!global_costmap_.RobotPose(&start, &error)) {
        ROS_ERROR("move_base: make_plan: %s", error.c_str());
        return false;
      }
    } else if (!(error = ToGlobal(req.start, &start)).empty()) {
      ROS_ERROR("move_base: make_plan: start: %s", error.c_str());
      return false;
    }
    if (!(error = ToGlobal(req.goal, &goal)).empty()) {
      ROS_ERROR("move_base: make_plan: goal: %s", error.c_str());
      return false;
    }
    try {
      const nav::Path p = global_planner_->MakePlan(global_costmap_.costmap(), start, goal);
      res.plan = ToPath(p, global_costmap_.options().global_frame, ros::Time::now());
    } catch (const nav::PlanningError& e) {
      // An empty plan is make_plan's "no path" answer.
      ROS_WARN("move_base: make_plan: %s", e.what());
      res.plan.header.frame_id = global_costmap_.options().global_frame;
    }
    return true;
  }

  bool OnClearCostmaps(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    global_costmap_.Reset();
    local_costmap_.Reset();
    ROS_INFO("move_base: costmaps cleared");
    return true;
  }

  ros::NodeHandle nh_, pnh_;
  minibot3d_lockstep::Participant lockstep_;
  tf2_ros::Buffer tf_;
  minibot3d_lockstep::TransformListener tf_listener_;
  CostmapRos global_costmap_, local_costmap_;
  nav::MoveBaseOptions mb_;
  nav::dwa::DwaOptions dwa_;
  nav::GlobalPlannerOptions planner_;
  std::string local_ns_;
  std::unique_ptr<nav::GlobalPlanner> global_planner_;
  std::unique_ptr<nav::dwa::DwaPlanner> local_planner_;
  nav::ObstacleTrackerOptions tracker_;
  std::unique_ptr<nav::ObstacleTracker> obstacle_tracker_;
  struct PendingObservation {
    double stamp;
    nav::Point2 origin;
    std::vector<nav::Point2> hits;
  };
  std::vector<PendingObservation> pending_observations_;
  std::vector<std::unique_ptr<nav::RecoveryBehavior>> recoveries_;
  std::vector<nav::RecoveryBehavior*> recovery_ptrs_;
  std::unique_ptr<nav::NavigationExecutive> executive_;
  std::unique_ptr<MoveBaseServer> server_;
  ros::Publisher cmd_pub_, goal_pub_, plan_pub_, local_global_plan_pub_, local_plan_pub_,
      simple_client_pub_;
  ros::Subscriber odom_sub_, simple_goal_sub_;
  ros::ServiceServer make_plan_srv_, clear_srv_;
  nav::Twist2 velocity_;
  std::string last_message_;
};

}  // namespace
}  // namespace minibot3d_navigation

int main(int argc, char** argv) {
  // For tools (tune_planner) that check parameter names before starting a stack: one
  // NAMESPACE/NAME per line ("/NAME" for move_base's own), no master needed.
  if (argc > 1 && std::strcmp(argv[1], "--print-parameter-names") == 0) {
    namespace nav = minibot3d_navigation::nav;
    for (const auto& n : nav::dwa::DwaOptionNames()) {
      std::cout << "TrajectoryPlannerROS/" << n << "\n";
    }
    for (const char* ns : minibot3d_navigation::kCostmapNamespaces) {
      for (const auto& n : nav::CostmapOptionNames()) std::cout << ns << "/" << n << "\n";
      for (const auto& n : nav::CostmapSensorOptionTable().Names()) {
        std::cout << ns << "/" << n << "\n";
      }
    }
    for (const auto& n : nav::GlobalPlannerOptionNames()) std::cout << "NavfnROS/" << n << "\n";
    for (const auto& n : nav::MoveBaseOptionNames()) std::cout << "/" << n << "\n";
    return 0;
  }
  ros::init(argc, argv, "move_base");
  minibot3d_navigation::MoveBaseNode node;
  try {
    node.Configure();
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("move_base: bad parameters:%s", e.what());
    return 1;
  }
  node.Start();
  return node.Spin() ? 0 : 1;
}
