// explore: frontier-based exploration (Yamauchi 1997) driving move_base.
//
// Every ~planner_frequency seconds (sim time), and at once when move_base ends a
// goal (no standing still between goals), it takes the latest map, finds the
// reachable frontiers (minibot3d_navigation/explore/frontier_search.h) and sends
// move_base a goal at the nearest one's viewpoint, heading the way the robot
// comes.  A goal is kept until it is reached or fails, the robot neither gets
// closer to it nor moves 0.5 m for ~progress_timeout seconds (nor gets closer
// for three times that, moving or not: explore/goal_progress.h), or a frontier
// nearer by ~switch_margin metres appears.  What it remembers is
// nav::ExplorationMemory: a reached viewpoint is not used again, and the
// frontier cells still in sight of it (judged on the next map) cannot be cleared
// by the sensor (glass, below the lidar) and no longer count; a goal move_base
// aborted or made no progress towards is excluded until the map round it
// changes, at most max_goal_attempts times.  When no reachable frontier is left
// on a fresher map (or for three cycles) it logs the explored area and exits 0 —
// the map can then be saved.  Progress (known free area, frontiers, sim time) is
// printed as it goes.  Its frames take the robot's frame_prefix when several
// robots share one tf tree (minibot3d_ros/frames.h).
#include <atomic>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <actionlib/client/simple_action_client.h>
#include <geometry_msgs/PoseArray.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>

#include <ros/topic_manager.h>

#include "minibot3d_lockstep/participant.h"
#include "minibot3d_lockstep/transform_listener.h"
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>
#include <tf2_ros/buffer.h>

#include "minibot3d_navigation/explore/explore_node_options.h"
#include "minibot3d_navigation/explore/frontier_search.h"
#include "minibot3d_navigation/explore/goal_progress.h"
#include "minibot3d_ros/conversions.h"
#include "minibot3d_ros/frames.h"
#include "minibot3d_ros/params.h"

namespace minibot3d_navigation {
namespace {

using Client = actionlib::SimpleActionClient<move_base_msgs::MoveBaseAction>;

// A goal move_base gives up on with the robot this close to it was reached all the same.
constexpr double kArrived = 0.25;  // m

class ExploreNode {
 public:
  ExploreNode()
      : pnh_("~"),
        lockstep_(nh_, LockstepOptions()),
        tf_listener_(tf_, lockstep_),
        client_(nh_, "move_base", /*spin_thread=*/!lockstep_.enabled()) {}

  // Woken by new maps and by move_base's results as well as by its planning period.
  static minibot3d_lockstep::ParticipantOptions LockstepOptions() {
    minibot3d_lockstep::ParticipantOptions o;
    o.wake_topics = {"map", "move_base/result"};
    return o;
  }

  bool Spin() { return lockstep_.Spin(); }

  // actionlib's isServerConnected() waits for a status message, which move_base sends on a
  // timer at no fixed sim time; under lock-step the connections alone decide, the same way in
  // every run (this node's connections are settled at its first tick).
  bool ServerReady() const {
    if (!lockstep_.enabled()) return client_.isServerConnected();
    const auto& tm = ros::TopicManager::instance();
    const std::string ns = ros::names::resolve("move_base");
    return tm->getNumSubscribers(ns + "/goal") > 0 && tm->getNumSubscribers(ns + "/cancel") > 0 &&
           tm->getNumPublishers(ns + "/status") > 0 && tm->getNumPublishers(ns + "/result") > 0 &&
           tm->getNumPublishers(ns + "/feedback") > 0;
  }

  // Reads the private namespace (frontier search and loop); throws std::invalid_argument
  // naming each problem.
  void Configure() {
    minibot3d_ros::ParamReport report =
        minibot3d_ros::LoadTable(pnh_, nav::ExploreOptionTable(), &o_);
    report.Also(minibot3d_ros::LoadTable(pnh_, nav::ExploreNodeOptionTable(), &node_));
    minibot3d_ros::FrameOptions frames;
    report.Also(minibot3d_ros::LoadFrameOptions(pnh_, &frames));
    report.WarnUnknown("explore");
    std::vector<std::string> problems = report.problems;
    try {
      nav::ValidateExploreNodeOptions(node_);
    } catch (const std::invalid_argument& e) {
      problems.push_back(e.what());
    }
    if (report.problems.empty()) {  // else a bad frame_prefix is among them
      const minibot3d_ros::FrameNames names(frames);
      node_.global_frame = names.Resolve(node_.global_frame);
      node_.robot_base_frame = names.Resolve(node_.robot_base_frame);
    }
    try {
      search_ = std::make_unique<nav::FrontierSearch>(o_);
      memory_ = std::make_unique<nav::ExplorationMemory>(o_);
      progress_ = std::make_unique<nav::GoalProgress>(node_.progress_timeout);
    } catch (const std::invalid_argument& e) {
      problems.push_back(e.what());
    }
    if (!problems.empty()) {
      std::string msg;
      for (const auto& p : problems) msg += "\n  " + p;
      throw std::invalid_argument(msg);
    }
  }

  void Start() {
    map_sub_ = nh_.subscribe("map", 1, &ExploreNode::OnMap, this);
    frontier_pub_ = pnh_.advertise<geometry_msgs::PoseArray>("frontiers", 1);
    lockstep_.AddPeriodic(1.0 / node_.planner_frequency, [this](const ros::Time&) { OnTimer(); });
    start_time_ = ros::Time::now();
  }

 private:
  void OnMap(const nav_msgs::OccupancyGrid::ConstPtr& map) {
    map_ = map;
    ++map_count_;
  }

  bool RobotPose(nav::Pose2* pose) {
    try {
      const auto t = tf_.lookupTransform(node_.global_frame, node_.robot_base_frame, ros::Time(0));
      tf2::Transform tt;
      tf2::fromMsg(t.transform, tt);
      *pose = minibot3d_ros::PoseFromTf(tt);
      return true;
    } catch (const tf2::TransformException& e) {
      ROS_WARN_THROTTLE(5.0, "explore: no transform %s <- %s: %s (is SLAM running?)",
                        node_.global_frame.c_str(), node_.robot_base_frame.c_str(), e.what());
      return false;
    }
  }

  // A goal is reached: the viewpoint is not used again; what stays frontier there is judged
  // on the next map SLAM publishes (the last scans are in it), while the robot goes on.
  void GoalReached() {
    have_goal_ = false;
    memory_->Reached(goal_);
    // Looking from off, the frontier cells it was sent to see were seen, whatever the next map
    // shows of them: they count no more at once (the cleared ones are no frontier anyway), so
    // that the next goal is not another look at them before that map comes.
    memory_->LookedAt(goal_in_view_);
    to_judge_.push_back({goal_, goal_view_radius_, map_count_});
  }

  // Frontier cells within look_radius (looking from off: as far as it looked) in sight of a
  // reached goal that stay frontier.
  void Judge(const nav::Point2& viewpoint, double view_radius, const nav::OccupancyGrid& grid) {
    std::vector<nav::Point2> in_sight;
    try {
      in_sight = search_->InSight(grid, viewpoint, view_radius);
    } catch (const std::invalid_argument& e) {
      ROS_WARN_THROTTLE(5.0, "explore: %s", e.what());
    }
    memory_->LookedAt(in_sight);
    ROS_INFO("explore: goal (%.2f, %.2f) reached; %zu frontier cells in sight there stay unknown "
             "and are not chased again", viewpoint.x, viewpoint.y, in_sight.size());
  }

  void GoalFailed(const nav::OccupancyGrid& grid, const std::string& why) {
    const int attempts = memory_->Failed(goal_, grid);
    if (attempts >= o_.max_goal_attempts) {
      ROS_WARN("explore: goal (%.2f, %.2f) %s; given up after %d attempts near it", goal_.x,
               goal_.y, why.c_str(), attempts);
    } else {
      ROS_INFO("explore: goal (%.2f, %.2f) %s (attempt %d of %d); excluded until the map within "
               "%.1f m of it changes", goal_.x, goal_.y, why.c_str(), attempts,
               o_.max_goal_attempts, o_.retry_window);
    }
    have_goal_ = false;
  }

  void OnTimer() {
    if (!map_ || !ServerReady()) {
      ROS_INFO_THROTTLE(10.0, "explore: waiting for %s", !map_ ? "a map" : "move_base");
      return;
    }
    nav::Pose2 robot;
    if (!RobotPose(&robot)) return;
    const ros::Time now = ros::Time::now();
    const nav::OccupancyGrid grid = minibot3d_ros::GridFromMsg(*map_);

    if (have_goal_) {
      const auto state = client_.getState();
      const double d = std::hypot(goal_.x - robot.x, goal_.y - robot.y);
      if (state == actionlib::SimpleClientGoalState::SUCCEEDED) {
        GoalReached();
      } else if (state.isDone() && d < kArrived) {
        // At the goal but not at its heading (say, no room to turn): the scans were taken.
        ROS_INFO("explore: goal (%.2f, %.2f) ended %s %.2f m from the robot: counted as reached",
                 goal_.x, goal_.y, state.toString().c_str(), d);
        GoalReached();
      } else if (state.isDone()) {
        GoalFailed(grid, "ended " + state.toString() + ": " + state.getText());
      } else {
        const std::string why = progress_->Update(now.toSec(), {robot.x, robot.y});
        if (!why.empty()) {
          client_.cancelGoal();
          GoalFailed(grid, why);
        }
      }
    }
    for (auto it = to_judge_.begin(); it != to_judge_.end();) {
      if (map_count_ > it->map_count) {
        Judge(it->viewpoint, it->view_radius, grid);
        it = to_judge_.erase(it);
      } else {
        ++it;
      }
    }
    for (const nav::Point2& p : memory_->Refresh(grid)) {
      ROS_INFO("explore: the map changed round unreachable goal (%.2f, %.2f); it may be retried",
               p.x, p.y);
    }

    nav::FrontierSearchResult r;
    try {
      r = search_->Find(grid, robot, memory_->Excluded(), memory_->looked_at(),
                        memory_->Unreachable());
    } catch (const std::invalid_argument& e) {
      ROS_WARN_THROTTLE(5.0, "explore: %s", e.what());
      return;
    }
    PublishFrontiers(r);
    ROS_INFO_THROTTLE(15.0, "explore: %.1f m^2 known free, %zu frontiers (%d unreachable, %d "
                      "blacklisted), %.0f s sim", r.known_free_area, r.frontiers.size(),
                      r.unreachable, r.blacklisted, (now - start_time_).toSec());
    if (r.frontiers.empty()) {
      if (have_goal_) return;  // let the current goal finish first
      // Done when a newer map also shows nothing, or (SLAM publishes no new map
      // while the robot stands still) nothing has shown up for 3 cycles.
      if (empty_at_map_ == 0) {
        empty_at_map_ = map_count_;
        empty_since_ = now;
      } else if (map_count_ > empty_at_map_ ||
                 (now - empty_since_).toSec() > 3.0 / node_.planner_frequency) {
        ROS_INFO("explore: exploration complete: %.1f m^2 known free, %d goals, %.1f s sim",
                 r.known_free_area, goals_sent_, (now - start_time_).toSec());
        lockstep_.Leave();
        ros::shutdown();
      }
      return;
    }
    empty_at_map_ = 0;
    const nav::Frontier& best = r.frontiers.front();
    if (have_goal_) {
      const double current = std::hypot(goal_.x - robot.x, goal_.y - robot.y);
      if (std::hypot(best.goal.x - goal_.x, best.goal.y - goal_.y) < o_.blacklist_radius ||
          best.distance > current - node_.switch_margin) {
        return;  // keep the current goal
      }
    }
    SendGoal(best, robot, now);
  }

  void SendGoal(const nav::Frontier& f, const nav::Pose2& robot, const ros::Time& now) {
    move_base_msgs::MoveBaseGoal g;
    g.target_pose.header.frame_id = node_.global_frame;
    g.target_pose.header.stamp = now;
    g.target_pose.pose.position.x = f.goal.x;
    g.target_pose.pose.position.y = f.goal.y;
    // Arrive heading the way the robot comes, not facing the frontier: the lidar sees all
    // round, and a turn on the spot at a goal beside furniture is where a robot gets wedged.
    double yaw = robot.yaw;
    if (std::hypot(f.goal.y - robot.y, f.goal.x - robot.x) > 0.3) {
      yaw = std::atan2(f.goal.y - robot.y, f.goal.x - robot.x);
    }
    g.target_pose.pose.orientation.z = std::sin(yaw / 2.0);
    g.target_pose.pose.orientation.w = std::cos(yaw / 2.0);
    client_.sendGoal(g, [this](const actionlib::SimpleClientGoalState&,
                               const move_base_msgs::MoveBaseResultConstPtr&) { PlanSoon(); });
    ++goals_sent_;
    goal_ = f.goal;
    goal_view_radius_ = f.view_radius;
    goal_in_view_ = f.in_view;
    have_goal_ = true;
    progress_->Start(now.toSec(), {robot.x, robot.y}, goal_);
    if (f.view_radius > 0.0) {
      ROS_INFO("explore: going to look at frontier at (%.2f, %.2f), %.1f m long, from (%.2f, "
               "%.2f), %.1f m away (%s), which sees %zu of its cells",
               f.centroid.x, f.centroid.y, f.size, f.goal.x, f.goal.y, f.distance,
               f.creeping ? "no roomy cell sees it: creeping, closer to walls than goal_clearance"
                          : "no room nearer to it",
               f.in_view.size());
    } else {
      ROS_INFO("explore: going to frontier at (%.2f, %.2f), %.1f m long, %.1f m away",
               f.centroid.x, f.centroid.y, f.size, f.distance);
    }
  }

  // move_base ended the goal: plan the next one now, not at the next period. Called on the
  // action client's thread when free-running; the planning runs on the node's own.
  void PlanSoon() {
    if (plan_queued_.exchange(true)) return;
    ros::getGlobalCallbackQueue()->addCallback(boost::make_shared<PlanCallback>(this));
    if (lockstep_.enabled()) lockstep_.WakeAt(ros::Time::now() + ros::Duration(1e-6));
  }

  class PlanCallback : public ros::CallbackInterface {
   public:
    explicit PlanCallback(ExploreNode* node) : node_(node) {}
    CallResult call() override {
      node_->plan_queued_ = false;
      node_->OnTimer();
      return Success;
    }

   private:
    ExploreNode* node_;
  };

  void PublishFrontiers(const nav::FrontierSearchResult& r) {
    if (frontier_pub_.getNumSubscribers() == 0) return;
    geometry_msgs::PoseArray a;
    a.header.frame_id = node_.global_frame;
    a.header.stamp = ros::Time::now();
    for (const auto& f : r.frontiers) {
      geometry_msgs::Pose p;
      p.position.x = f.centroid.x;
      p.position.y = f.centroid.y;
      p.orientation.w = 1.0;
      a.poses.push_back(p);
    }
    frontier_pub_.publish(a);
  }

  ros::NodeHandle nh_, pnh_;
  minibot3d_lockstep::Participant lockstep_;
  tf2_ros::Buffer tf_;
  minibot3d_lockstep::TransformListener tf_listener_;
  Client client_;
  nav::ExploreOptions o_;
  nav::ExploreNodeOptions node_;
  std::unique_ptr<nav::FrontierSearch> search_;
  std::unique_ptr<nav::ExplorationMemory> memory_;
  ros::Subscriber map_sub_;
  ros::Publisher frontier_pub_;
  nav_msgs::OccupancyGrid::ConstPtr map_;
  int map_count_ = 0, empty_at_map_ = 0;
  bool have_goal_ = false;
  std::atomic<bool> plan_queued_{false};  // a PlanCallback is in the node's queue
  struct ToJudge {
    nav::Point2 viewpoint;
    double view_radius;  // Frontier::view_radius of the goal
    int map_count;       // maps received when it was reached
  };
  std::vector<ToJudge> to_judge_;  // reached viewpoints
  nav::Point2 goal_;
  double goal_view_radius_ = 0.0;
  std::vector<nav::Point2> goal_in_view_;
  std::unique_ptr<nav::GoalProgress> progress_;
  ros::Time start_time_, empty_since_;
  int goals_sent_ = 0;
};

}  // namespace
}  // namespace minibot3d_navigation

int main(int argc, char** argv) {
  ros::init(argc, argv, "explore");
  minibot3d_navigation::ExploreNode node;
  try {
    node.Configure();
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("explore: bad parameters:%s", e.what());
    return 1;
  }
  node.Start();
  return node.Spin() ? 0 : 1;
}
