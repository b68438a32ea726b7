// The simulator's side of lock-step time (minibot3d_lockstep): participants register, and at each
// quantum every participant with work (a wake time, mail, or a first tick) is ticked in turn; the
// simulator waits for its acknowledgement and for the messages it sent before going on. The
// bookkeeping is minibot3d_lockstep's Coordinator; this class owns its ROS side (services, tick
// publishers, acknowledgements) for the simulator node.
#ifndef MINIBOT3D_SIM_SRC_NODE_LOCKSTEP_HOST_H_
#define MINIBOT3D_SIM_SRC_NODE_LOCKSTEP_HOST_H_

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <ros/ros.h>

#include "minibot3d_lockstep/Ack.h"
#include "minibot3d_lockstep/Register.h"
#include "minibot3d_lockstep/Unregister.h"
#include "minibot3d_lockstep/coordinator.h"
#include "minibot3d_lockstep/digest.h"

namespace minibot3d_sim {

class LockstepHost {
 public:
  struct Options {
    minibot3d_lockstep::CoordinatorOptions coordinator;
    std::vector<std::string> participants;  // waited for before time starts (resolved names)
    double start_timeout = 60.0;            // wall s
  };
  // `sim_time` reads the simulator's clock; `publish_clock(again)` publishes /clock;
  // `apply_commands` applies the queued commands between rounds.
  LockstepHost(ros::NodeHandle nh, const Options& options, std::function<double()> sim_time,
               std::function<void(bool)> publish_clock, std::function<void()> apply_commands);

  // Before time starts: the named participants have joined, and every subscriber of the
  // simulator's topics is connected; then the participant list is published (not before).
  void WaitForExpectedParticipants();
  void WaitForOwnConnections();
  // Ticks every participant that has work at the current time, in name order, waiting for each.
  void Round();
  // What the simulator itself sent since the last call (lock-step counts messages per link).
  void RecordSent();

 private:
  bool WaitReady(const std::string& name);
  void WaitForAck(const std::string& name);
  void WaitForDeliveryToSim();
  void DropDead();
  void Drop(const std::string& name, const std::string& why);
  void PublishParticipants();
  bool OnRegister(minibot3d_lockstep::Register::Request& req,
                  minibot3d_lockstep::Register::Response& res);
  bool OnUnregister(minibot3d_lockstep::Unregister::Request& req,
                    minibot3d_lockstep::Unregister::Response& res);
  void OnAck(const minibot3d_lockstep::Ack::ConstPtr& ack);
  static std::string Join(const std::vector<std::string>& names);

  ros::NodeHandle nh_;
  Options options_;
  std::function<double()> sim_time_;
  std::function<void(bool)> publish_clock_;
  std::function<void()> apply_commands_;
  std::unique_ptr<minibot3d_lockstep::Coordinator> coordinator_;
  ros::Subscriber ack_sub_;
  ros::Publisher participants_pub_;
  std::vector<ros::ServiceServer> services_;
  struct TickPublisher {
    ros::Publisher pub;
    bool connected = false;
  };
  std::map<std::string, TickPublisher> ticks_;
  std::uint64_t tick_seq_ = 0;
  bool started_ = false;  // time has started: the participant list is published from then on
  std::unique_ptr<minibot3d_lockstep::DigestRecorder> digest_;  // MINIBOT3D_LOCKSTEP_DIGEST set
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_SRC_NODE_LOCKSTEP_HOST_H_
