#include "lockstep_host.h"

#include <algorithm>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "minibot3d_lockstep/Link.h"
#include "minibot3d_lockstep/Participants.h"
#include "minibot3d_lockstep/Tick.h"
#include "minibot3d_lockstep/link_counts.h"
#include "minibot3d_lockstep/participant.h"

namespace minibot3d_sim {

namespace {
// Wall s after which a missing connection or message is looked into (then as often): waited for
// while the node at the other end is running, given up when it is gone.
constexpr double kLookInto = 10.0;
}  // namespace

LockstepHost::LockstepHost(ros::NodeHandle nh, const Options& options,
                           std::function<double()> sim_time,
                           std::function<void(bool)> publish_clock,
                           std::function<void()> apply_commands)
    : nh_(std::move(nh)),
      options_(options),
      sim_time_(std::move(sim_time)),
      publish_clock_(std::move(publish_clock)),
      apply_commands_(std::move(apply_commands)) {
  coordinator_ = std::make_unique<minibot3d_lockstep::Coordinator>(options_.coordinator,
                                                                   ros::this_node::getName());
  ack_sub_ = nh_.subscribe(minibot3d_lockstep::kAckTopic, 100, &LockstepHost::OnAck, this,
                           ros::TransportHints().tcpNoDelay());
  participants_pub_ = nh_.advertise<minibot3d_lockstep::Participants>(
      minibot3d_lockstep::kParticipantsTopic, 100000, true);
  services_.push_back(
      nh_.advertiseService(minibot3d_lockstep::kRegisterService, &LockstepHost::OnRegister, this));
  services_.push_back(nh_.advertiseService(minibot3d_lockstep::kUnregisterService,
                                           &LockstepHost::OnUnregister, this));
  digest_ = minibot3d_lockstep::DigestRecorder::FromEnvironment();
  if (digest_) {
    digest_->Instrument();
    ROS_INFO("minibot3d_sim: lock-step digest in %s", digest_->path().c_str());
  }
}

std::string LockstepHost::Join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// Time does not start until the participants a launch file names have joined (each joins at a
// sim time that then does not depend on how fast its process started).
void LockstepHost::WaitForExpectedParticipants() {
  const ros::WallTime start = ros::WallTime::now();
  ros::WallTime last_note = start;
  while (ros::ok()) {
    ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.01));
    std::vector<std::string> missing;
    for (const auto& n : options_.participants) {
      if (!coordinator_->Has(n)) missing.push_back(n);
    }
    if (missing.empty()) return;
    const ros::WallTime now = ros::WallTime::now();
    if ((now - start).toSec() > options_.start_timeout) {
      ROS_WARN("minibot3d_sim: lock-step: starting time without %s, which did not register "
               "within ~lockstep_start_timeout %g s", Join(missing).c_str(), options_.start_timeout);
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
// messages reach every node that has asked for them, however fast each process started. A
// connection to a node that is running is waited for however loaded the machine; one to a node
// that no longer answers (registered, then killed) never comes, and time starts without it.
void LockstepHost::WaitForOwnConnections() {
  const ros::WallTime start = ros::WallTime::now();
  ros::WallTime checked = start;
  while (ros::ok()) {
    const auto missing = minibot3d_lockstep::MissingConnections();
    if (missing.empty()) break;
    const ros::WallTime now = ros::WallTime::now();
    if ((now - start).toSec() > kLookInto && (now - checked).toSec() > kLookInto) {
      checked = now;
      std::vector<std::string> alive, gone;
      for (const auto& m : missing) {
        (minibot3d_lockstep::NodeAnswers(minibot3d_lockstep::PeerOf(m)) ? alive : gone)
            .push_back(m);
      }
      if (alive.empty()) {
        ROS_WARN("minibot3d_sim: lock-step: starting without connections: %s (their nodes do "
                 "not answer: registered with the master, no longer running)",
                 Join(gone).c_str());
        break;
      }
      ROS_WARN("minibot3d_sim: lock-step: still waiting for connections to running nodes: %s "
               "(%.0f s wall)", Join(alive).c_str(), (now - start).toSec());
    }
    ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.005));
  }
  // The participant list goes out first now: one list, the same in every run, whatever order
  // the participants joined in while time waited.
  started_ = true;
  PublishParticipants();
}

void LockstepHost::RecordSent() {
  coordinator_->SetSent(ros::this_node::getName(), minibot3d_lockstep::SentCounts());
}

void LockstepHost::Round() {
  ros::getGlobalCallbackQueue()->callAvailable();
  if (digest_) digest_->Instrument();
  DropDead();
  const double t = sim_time_();
  bool clock_sent = false;
  for (const std::string& name : coordinator_->Due(t)) {
    auto it = ticks_.find(name);
    if (it == ticks_.end()) continue;
    if (!WaitReady(name)) continue;
    if (!clock_sent) {
      publish_clock_(true);  // before the first tick: participants wait for their clock to show t
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
    if (digest_) digest_->ReceivedBy(tick.seq, tick.stamp);
  }
  apply_commands_();
}

// A joined participant is ticked once its tick subscription is connected; until then it is waited
// for as long as its process is there (a slow start is not a failure).
bool LockstepHost::WaitReady(const std::string& name) {
  const ros::WallTime start = ros::WallTime::now();
  ros::WallTime last_check = start, last_note = start;
  while (ros::ok()) {
    auto it = ticks_.find(name);
    if (it == ticks_.end()) return false;
    if (it->second.pub.getNumSubscribers() > 0) {
      it->second.connected = true;
      return true;
    }
    const ros::WallTime now = ros::WallTime::now();
    const double waited = (now - start).toSec();
    if (options_.coordinator.timeout > 0.0 && waited > options_.coordinator.timeout) {
      Drop(name, "did not subscribe to its tick topic within ~lockstep_timeout");
      return false;
    }
    if ((now - last_check).toSec() > 1.0) {
      last_check = now;
      if (!minibot3d_lockstep::NodeAnswers(name)) {
        Drop(name, "its process is gone (it never subscribed to its tick topic)");
        return false;
      }
    }
    if (waited > 2.0 && (now - last_note).toSec() > 10.0) {
      last_note = now;
      ROS_WARN("minibot3d_sim: lock-step: sim time %.3f waits for %s to subscribe to its tick "
               "topic (%.0f s wall so far)", sim_time_(), name.c_str(), waited);
    }
    ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.001));
  }
  return false;
}

// A participant that is alive is waited for however long it works (a loaded machine, a debugger):
// dropping it would make the run depend on the wall clock. It is dropped when its process is gone
// (its tick subscription closes), or, with ~lockstep_timeout > 0, when it takes longer than that.
void LockstepHost::WaitForAck(const std::string& name) {
  const ros::WallTime start = ros::WallTime::now();
  ros::WallTime last_note = start;
  double note_every = 2.0;
  while (ros::ok() && coordinator_->Has(name)) {
    const auto waiting = coordinator_->Waiting();
    if (std::find(waiting.begin(), waiting.end(), name) == waiting.end()) return;
    ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.001));
    const ros::WallTime now = ros::WallTime::now();
    auto it = ticks_.find(name);
    if (it != ticks_.end() && it->second.connected && it->second.pub.getNumSubscribers() == 0) {
      Drop(name, "its process is gone (tick topic unsubscribed)");
      return;
    }
    const auto overdue = coordinator_->Overdue(now.toSec());
    if (std::find(overdue.begin(), overdue.end(), name) != overdue.end()) {
      Drop(name, "no acknowledgement within ~lockstep_timeout");
      return;
    }
    // Every 2 s, then less often: a stop in a debugger may last an hour.
    if ((now - last_note).toSec() > note_every) {
      last_note = now;
      note_every = std::min(60.0, note_every * 1.5);
      ROS_WARN("minibot3d_sim: lock-step: sim time %.3f waits for %s (%.1f s wall so far; a "
               "participant must not block in rospy.sleep, wait_for_result or a waiting tf "
               "lookup, see docs/lockstep.md)", sim_time_(), name.c_str(),
               (now - start).toSec());
    }
  }
}

// Messages participants sent to the simulator (cmd_vel, acks) are all here before commands are
// applied and physics goes on. Messages on a connection that is there are on their way, however loaded the machine: waited
// for (going on without them would make the run depend on the load). A connection that is gone
// (its publisher died mid-send) brings nothing more: looked into after kLookInto wall s, then
// every kLookInto s, and given up with a warning.
void LockstepHost::WaitForDeliveryToSim() {
  const auto expected = coordinator_->Expected(ros::this_node::getName());
  const ros::WallTime start = ros::WallTime::now();
  ros::WallTime noted = start;
  while (ros::ok()) {
    std::map<std::pair<std::string, std::string>, std::uint64_t> have;
    for (const auto& l : minibot3d_lockstep::ReceivedCounts()) have[{l.topic, l.peer}] = l.count;
    std::vector<std::string> missing;
    bool connected = false;  // a connection that still has messages to bring is there
    for (const auto& e : expected) {
      auto it = have.find({e.topic, e.peer});
      const std::uint64_t got = it == have.end() ? 0 : it->second;
      if (got < e.count) {
        connected = connected || it != have.end();
        std::ostringstream m;
        m << e.topic << " from " << e.peer << " (" << got << " of " << e.count << ")";
        missing.push_back(m.str());
      }
    }
    if (missing.empty()) break;
    const ros::WallTime now = ros::WallTime::now();
    if ((now - start).toSec() > kLookInto && (now - noted).toSec() > kLookInto) {
      noted = now;
      if (!connected) {
        ROS_WARN("minibot3d_sim: lock-step: going on at t=%.3f without messages: %s (their "
                 "publishers' connections are gone)", sim_time_(), Join(missing).c_str());
        break;
      }
      ROS_WARN("minibot3d_sim: lock-step: still waiting at t=%.3f for messages: %s (%.0f s wall)",
               sim_time_(), Join(missing).c_str(), (now - start).toSec());
    }
    minibot3d_lockstep::WaitForPollIteration(0.002);
  }
  minibot3d_lockstep::SyncWithPollThread();
}

// Participants whose process is gone are dropped between rounds too.
void LockstepHost::DropDead() {
  std::vector<std::string> dead;
  for (const auto& kv : ticks_) {
    if (kv.second.connected && kv.second.pub.getNumSubscribers() == 0) dead.push_back(kv.first);
  }
  for (const auto& n : dead) Drop(n, "its process is gone (tick topic unsubscribed)");
}

void LockstepHost::Drop(const std::string& name, const std::string& why) {
  ROS_WARN("minibot3d_sim: lock-step: dropped participant %s at sim time %.3f: %s", name.c_str(),
           sim_time_(), why.c_str());
  coordinator_->Remove(name);
  ticks_.erase(name);
  PublishParticipants();
}

void LockstepHost::PublishParticipants() {
  if (!started_) return;
  minibot3d_lockstep::Participants p;
  p.stamp = ros::Time(sim_time_());
  p.names = coordinator_->Participants();
  participants_pub_.publish(p);
}

bool LockstepHost::OnRegister(minibot3d_lockstep::Register::Request& req,
                              minibot3d_lockstep::Register::Response& res) {
  const std::string error = coordinator_->Register(req.name, req.wake_topics);
  res.accepted = error.empty();
  res.message = error;
  res.now = ros::Time(sim_time_());
  res.quantum = options_.coordinator.quantum;
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
  ROS_INFO("minibot3d_sim: lock-step: %s joined at sim time %.3f", req.name.c_str(), sim_time_());
  PublishParticipants();
  return true;
}

bool LockstepHost::OnUnregister(minibot3d_lockstep::Unregister::Request& req,
                                minibot3d_lockstep::Unregister::Response& res) {
  res.removed = coordinator_->Remove(req.name);
  ticks_.erase(req.name);
  if (res.removed) {
    ROS_INFO("minibot3d_sim: lock-step: %s left at sim time %.3f", req.name.c_str(), sim_time_());
    PublishParticipants();
  }
  return true;
}

void LockstepHost::OnAck(const minibot3d_lockstep::Ack::ConstPtr& ack) {
  if (ack->working) {
    coordinator_->Heartbeat(ack->name, ack->seq, ros::WallTime::now().toSec());
    return;
  }
  std::vector<minibot3d_lockstep::LinkCount> sent;
  for (const auto& l : ack->sent) sent.push_back({l.topic, l.peer, l.count});
  const double wake = ack->next_wake.isZero() ? 0.0 : ack->next_wake.toSec();
  if (!coordinator_->Ack(ack->name, ack->seq, wake, sent)) {
    ROS_WARN_THROTTLE(5.0, "minibot3d_sim: lock-step: ignoring an acknowledgement from %s for tick "
                      "%lu it is not waiting on", ack->name.c_str(),
                      static_cast<unsigned long>(ack->seq));
  }
}

}  // namespace minibot3d_sim
