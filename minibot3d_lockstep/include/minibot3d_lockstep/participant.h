// Makes a roscpp node a lock-step participant of minibot3d_sim in a few lines:
//
//   minibot3d_lockstep::Participant lockstep(nh, {/*wake_topics=*/{"scan"}});
//   minibot3d_lockstep::TransformListener tf(buffer, lockstep);  // transform_listener.h
//   lockstep.AddPeriodic(0.05, [&](const ros::Time& now) { Control(now); });  // not ros::Timer
//   lockstep.Spin();                                                          // not ros::spin()
//
// With the global parameter /use_lockstep false (or unset) this is plain ROS: AddPeriodic makes a
// ros::Timer and Spin() is ros::spin(). With it true, Spin() registers with the simulator and,
// for every tick: waits until every message other participants have sent to this node is here,
// waits until this node's clock shows the tick's time, runs the tf callbacks, then every other
// callback, then the periodic jobs that are due, and acknowledges with the messages it has sent
// and the time its next job is due. The node is single-threaded: its callbacks and jobs run only
// inside Spin(), at a sim time that no longer moves while they run. Service servers advertised
// through service_node_handle() are also answered between ticks (another participant may call
// them while it works).
#ifndef MINIBOT3D_LOCKSTEP_PARTICIPANT_H
#define MINIBOT3D_LOCKSTEP_PARTICIPANT_H

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>

#include "minibot3d_lockstep/Tick.h"
#include "minibot3d_lockstep/digest.h"

namespace minibot3d_lockstep {

// The global parameter that switches lock-step on for every participant (like /use_sim_time).
constexpr char kLockstepParam[] = "/use_lockstep";
constexpr char kRegisterService[] = "/minibot3d_sim/lockstep/register";
constexpr char kUnregisterService[] = "/minibot3d_sim/lockstep/unregister";
constexpr char kAckTopic[] = "/minibot3d_sim/lockstep/ack";
constexpr char kParticipantsTopic[] = "/minibot3d_sim/lockstep/participants";
constexpr char kTickTopicPrefix[] = "/minibot3d_sim/lockstep/tick";

// True when /use_lockstep is set and true.
bool LockstepEnabled();

struct ParticipantOptions {
  // Topics (resolved against the node handle) whose messages wake the node between its jobs.
  std::vector<std::string> wake_topics;
  // Wall seconds after which a connection or an announced message that has not come is looked
  // into (then every 10 s): one from a node that is running is waited for however long it takes
  // (a loaded machine); one whose node or connection is gone is given up, with a warning.
  double delivery_timeout = 10.0;
};

class Participant {
 public:
  Participant(const ros::NodeHandle& nh, const ParticipantOptions& options);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  bool enabled() const { return enabled_; }
  // The node handle whose callbacks run first at each tick (TransformListener subscribes on it).
  ros::NodeHandle& tf_node_handle() { return tf_nh_; }
  // A tf lookup that may wait `seconds` for data when free-running. Under lock-step sim time
  // stands still while this node works and every transform it can get is already in the buffer:
  // it does not wait (tf2's waiting lookups also insist on a tf thread, which there is not).
  geometry_msgs::TransformStamped LookupTransform(const tf2_ros::Buffer& buffer,
                                                  const std::string& target,
                                                  const std::string& source, const ros::Time& time,
                                                  double seconds) const {
    if (enabled_) return buffer.lookupTransform(target, source, time);
    return buffer.lookupTransform(target, source, time, ros::Duration(seconds));
  }
  // For service servers other participants call while they work.
  ros::NodeHandle& service_node_handle() { return service_nh_; }
  // `nh` (e.g. a private "~" handle) with the same service queue.
  ros::NodeHandle ServiceHandle(const ros::NodeHandle& nh);

  // Runs `job` every `period` s of sim time, first at the first tick.
  void AddPeriodic(double period, std::function<void(const ros::Time&)> job);
  // Asks to be woken at `t` (once) even if no job is due and no mail arrives.
  void WakeAt(const ros::Time& t);
  // Until shutdown. Returns false if the simulator refused the registration.
  bool Spin();
  // Leaves the loop now, at the current sim time (call before ros::shutdown() when a node decides
  // to end: the simulator and whoever waits on this node see it go at a fixed sim time).
  void Leave() { Unregister(); }

 private:
  struct Job {
    double period;
    double next;
    std::function<void(const ros::Time&)> fn;
    ros::Timer timer;
  };
  bool WaitForSimulator();
  bool Register();
  void Unregister();
  bool WaitForTick(TickConstPtr* tick);
  void WaitForDelivery(const Tick& tick);
  void WaitForClock(const ros::Time& stamp);
  void ServeBetweenTicks();
  void SettleConnections();
  // While a long wait holds the tick: tells the simulator this node is alive (once a second).
  void Heartbeat(ros::WallTime* last);

  ros::NodeHandle nh_;
  ParticipantOptions options_;
  bool enabled_ = false;
  bool registered_ = false;
  std::string name_;
  ros::CallbackQueue tf_queue_, service_queue_, tick_queue_;
  ros::NodeHandle tf_nh_, service_nh_, tick_nh_;
  ros::Publisher ack_pub_;
  ros::Subscriber tick_sub_;
  TickConstPtr pending_tick_, current_;
  std::vector<std::unique_ptr<Job>> jobs_;
  std::vector<double> wake_at_;
  std::vector<std::string> settled_topics_;
  std::unique_ptr<DigestRecorder> digest_;  // with MINIBOT3D_LOCKSTEP_DIGEST set
};

}  // namespace minibot3d_lockstep

#endif  // MINIBOT3D_LOCKSTEP_PARTICIPANT_H
