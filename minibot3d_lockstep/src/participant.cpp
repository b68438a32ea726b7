#include "minibot3d_lockstep/participant.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

#include "minibot3d_lockstep/Ack.h"
#include "minibot3d_lockstep/Register.h"
#include "minibot3d_lockstep/Unregister.h"
#include "minibot3d_lockstep/link_counts.h"

namespace minibot3d_lockstep {

bool LockstepEnabled() {
  bool on = false;
  return ros::param::get(kLockstepParam, on) && on;
}

Participant::Participant(const ros::NodeHandle& nh, const ParticipantOptions& options)
    : nh_(nh), options_(options), enabled_(LockstepEnabled()), name_(ros::this_node::getName()),
      tf_nh_(nh), service_nh_(nh), tick_nh_(nh) {
  if (!enabled_) return;
  tf_nh_.setCallbackQueue(&tf_queue_);
  // Ticks and service requests share a queue: both are handled while the node waits for a tick.
  service_nh_.setCallbackQueue(&service_queue_);
  tick_nh_.setCallbackQueue(&service_queue_);
  ack_pub_ = nh_.advertise<Ack>(kAckTopic, 100);
  try {
    digest_ = DigestRecorder::FromEnvironment();
  } catch (const std::runtime_error& e) {
    ROS_FATAL("%s: %s", name_.c_str(), e.what());
    throw;
  }
}

Participant::~Participant() { Unregister(); }

ros::NodeHandle Participant::ServiceHandle(const ros::NodeHandle& nh) {
  ros::NodeHandle h(nh);
  if (enabled_) h.setCallbackQueue(&service_queue_);
  return h;
}

void Participant::AddPeriodic(double period, std::function<void(const ros::Time&)> job) {
  auto j = std::make_unique<Job>();
  j->period = period;
  j->next = std::numeric_limits<double>::quiet_NaN();
  j->fn = std::move(job);
  if (!enabled_) {
    auto fn = j->fn;
    j->timer = nh_.createTimer(ros::Duration(period),
                               [fn](const ros::TimerEvent&) { fn(ros::Time::now()); });
  }
  jobs_.push_back(std::move(j));
}

void Participant::WakeAt(const ros::Time& t) { wake_at_.push_back(t.toSec()); }

bool Participant::WaitForSimulator() {
  int waited = 0;
  while (ros::ok() && !ros::service::waitForService(kRegisterService, 1000)) {
    if (++waited % 10 == 1) {
      ROS_WARN("%s: /use_lockstep is true; waiting for the simulator's %s (is minibot3d_sim "
               "running with lockstep:=true?)", name_.c_str(), kRegisterService);
    }
  }
  return ros::ok();
}

bool Participant::Register() {
  minibot3d_lockstep::Register srv;
  srv.request.name = name_;
  for (const auto& t : options_.wake_topics) srv.request.wake_topics.push_back(nh_.resolveName(t));
  if (!ros::service::call(kRegisterService, srv)) {
    ROS_FATAL("%s: the lock-step registration call to %s failed", name_.c_str(), kRegisterService);
    return false;
  }
  if (!srv.response.accepted) {
    ROS_FATAL("%s: the simulator refused lock-step registration: %s", name_.c_str(),
              srv.response.message.c_str());
    return false;
  }
  tick_sub_ = tick_nh_.subscribe<Tick>(
      srv.response.tick_topic, 10, [this](const TickConstPtr& t) { pending_tick_ = t; },
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  registered_ = true;
  ROS_INFO("%s: lock-step participant of the simulator (ticks on %s, quantum %g s)",
           name_.c_str(), srv.response.tick_topic.c_str(), srv.response.quantum);
  return true;
}

void Participant::Unregister() {
  if (!registered_ || !ros::ok()) return;
  registered_ = false;
  minibot3d_lockstep::Unregister srv;
  srv.request.name = name_;
  ros::ServiceClient c = ros::NodeHandle().serviceClient<minibot3d_lockstep::Unregister>(
      kUnregisterService);
  // A simulator that is already gone does not need telling.
  if (c.exists()) c.call(srv);
}

void Participant::SettleConnections() {
  // Sim time holds while this node has a tick in hand, so connections made now are made at the
  // same sim time in every run. Only when this node's own topics change (at its first tick, or
  // when it advertises or subscribes later) is the master asked.
  ros::V_string topics, advertised;
  ros::this_node::getSubscribedTopics(topics);
  ros::this_node::getAdvertisedTopics(advertised);
  std::sort(topics.begin(), topics.end());
  std::sort(advertised.begin(), advertised.end());
  topics.push_back("--");
  topics.insert(topics.end(), advertised.begin(), advertised.end());
  if (topics == settled_topics_) return;
  settled_topics_ = topics;
  KeepEveryMessage();  // a new publication's queue too
  const ros::WallTime start = ros::WallTime::now();
  ros::WallTime beat = start, checked = start;
  while (ros::ok()) {
    Heartbeat(&beat);
    const auto missing = MissingConnections();
    if (missing.empty()) return;
    const ros::WallTime now = ros::WallTime::now();
    // Past delivery_timeout, and then every 10 s: a connection to a node that is running is on
    // its way, however loaded the machine (going on without it would make the run depend on
    // that); one to a node that is gone (registered, then killed) never comes.
    if ((now - start).toSec() > options_.delivery_timeout && (now - checked).toSec() > 10.0) {
      checked = now;
      std::string alive, gone;
      for (const auto& m : missing) (NodeAnswers(PeerOf(m)) ? alive : gone) += " " + m + ";";
      if (alive.empty()) {
        ROS_WARN("%s: lock-step: going on without connections:%s (their nodes do not answer: "
                 "registered with the master, no longer running)", name_.c_str(), gone.c_str());
        return;
      }
      ROS_WARN("%s: lock-step: still waiting for connections to running nodes:%s (%.0f s wall)",
               name_.c_str(), alive.c_str(), (now - start).toSec());
    }
    WaitForPollIteration(0.005);
    service_queue_.callAvailable();
  }
}

void Participant::Heartbeat(ros::WallTime* last) {
  if (!current_ || (ros::WallTime::now() - *last).toSec() < 1.0) return;
  *last = ros::WallTime::now();
  Ack ack;
  ack.name = name_;
  ack.seq = current_->seq;
  ack.working = true;
  ack_pub_.publish(ack);
}

void Participant::ServeBetweenTicks() { service_queue_.callAvailable(ros::WallDuration(0.001)); }

bool Participant::WaitForTick(TickConstPtr* tick) {
  while (ros::ok() && !pending_tick_) ServeBetweenTicks();
  *tick = pending_tick_;
  pending_tick_.reset();
  return static_cast<bool>(*tick);
}

void Participant::WaitForDelivery(const Tick& tick) {
  const ros::WallTime start = ros::WallTime::now();
  std::map<std::pair<std::string, std::string>, std::uint64_t> want;
  for (const auto& l : tick.expected) want[{l.topic, l.peer}] = l.count;
  ros::WallTime beat = start, noted = start;
  while (ros::ok()) {
    Heartbeat(&beat);
    std::vector<std::string> missing;
    bool connected = false;  // a connection that still has messages to bring is there
    std::map<std::pair<std::string, std::string>, std::uint64_t> have;
    for (const auto& l : ReceivedCounts()) have[{l.topic, l.peer}] = l.count;
    for (const auto& w : want) {
      auto it = have.find(w.first);
      const std::uint64_t got = it == have.end() ? 0 : it->second;
      if (got < w.second) {
        connected = connected || it != have.end();
        std::ostringstream m;
        m << w.first.first << " from " << w.first.second << " (" << got << " of " << w.second << ")";
        missing.push_back(m.str());
      }
    }
    if (missing.empty()) break;
    // Messages on a connection that is there are on their way, however loaded the machine:
    // waited for. A connection that is gone (its publisher died mid-send) brings nothing more.
    const ros::WallTime now = ros::WallTime::now();
    if ((now - start).toSec() > options_.delivery_timeout && (now - noted).toSec() > 10.0) {
      noted = now;
      std::ostringstream m;
      for (const auto& s : missing) m << " " << s << ";";
      if (!connected) {
        ROS_WARN("%s: going on at t=%.3f without messages announced by the simulator's tick:%s "
                 "(their publishers' connections are gone)", name_.c_str(), tick.stamp.toSec(),
                 m.str().c_str());
        break;
      }
      ROS_WARN("%s: lock-step: still waiting at t=%.3f for messages:%s (%.0f s wall)",
               name_.c_str(), tick.stamp.toSec(), m.str().c_str(), (now - start).toSec());
    }
    WaitForPollIteration(0.002);
    service_queue_.callAvailable();
  }
  SyncWithPollThread();
}

void Participant::WaitForClock(const ros::Time& stamp) {
  // roscpp's own /clock callback (on its internal thread) sets ros::Time::now(). The simulator
  // publishes /clock for `stamp` before the tick, and older /clock messages come before it on
  // the same connection: once now() shows `stamp`, no older value can overwrite it.
  const ros::WallTime start = ros::WallTime::now();
  while (ros::ok() && ros::Time::now() < stamp) {
    if ((ros::WallTime::now() - start).toSec() > options_.delivery_timeout) {
      ROS_WARN_THROTTLE(10.0, "%s: /clock has not reached the tick's time %.3f (now %.3f); "
                        "setting it", name_.c_str(), stamp.toSec(), ros::Time::now().toSec());
      ros::Time::setNow(stamp);
      break;
    }
    ros::WallDuration(0.00005).sleep();
  }
  // Timers made with ros::Timer (by a library: actionlib's status) fire at this tick if due.
  // The timer thread is this process's own: it gets there, however loaded the machine.
  const ros::WallTime timers_start = ros::WallTime::now();
  while (ros::ok() && !WaitForDueTimers(options_.delivery_timeout)) {
    ROS_WARN("%s: lock-step: roscpp's timer thread has not yet queued the timers due at %.3f "
             "(%.0f s wall)", name_.c_str(), stamp.toSec(),
             (ros::WallTime::now() - timers_start).toSec());
  }
}

bool Participant::Spin() {
  if (!enabled_) {
    ros::spin();
    return true;
  }
  if (digest_) digest_->Instrument();
  // Every connection the node's topics call for is made, and every latched message is here,
  // before it joins: whoever holds sim time while it joins (a script starting it), nothing is
  // published meanwhile, so it starts with the same messages in every run.
  if (!WaitForSimulator()) return false;
  SettleConnections();
  if (!Register()) return false;
  while (ros::ok()) {
    TickConstPtr tick;
    if (!WaitForTick(&tick)) break;
    current_ = tick;
    SettleConnections();
    WaitForDelivery(*tick);
    if (digest_) digest_->Tick(tick->seq, tick->stamp);
    WaitForClock(tick->stamp);
    // tf first, so a message's transform is in the buffer when its callback looks it up; then
    // timers and the other topics' messages in an order that does not depend on the sockets.
    tf_queue_.callAvailable();
    OrderCallbacks(ros::getGlobalCallbackQueue());
    ros::getGlobalCallbackQueue()->callAvailable();
    service_queue_.callAvailable();
    const double t = tick->stamp.toSec();
    const double eps = 1e-9;
    double next_wake = std::numeric_limits<double>::infinity();
    for (auto& j : jobs_) {
      if (std::isnan(j->next)) j->next = std::ceil(t / j->period - 1e-6) * j->period;
      if (j->next <= t + eps) {
        j->fn(tick->stamp);
        while (j->next <= t + eps) j->next += j->period;
      }
      next_wake = std::min(next_wake, j->next);
    }
    wake_at_.erase(std::remove_if(wake_at_.begin(), wake_at_.end(),
                                  [&](double w) { return w <= t + eps; }),
                   wake_at_.end());
    for (double w : wake_at_) next_wake = std::min(next_wake, w);
    // Topics advertised or subscribed during this tick connect before the ack, sim time still
    // held: a latched message published at once is counted now, not delivered at a later tick
    // that depends on how fast the master and the peer answered.
    if (digest_) digest_->Instrument();
    SettleConnections();
    Ack ack;
    ack.name = name_;
    ack.seq = tick->seq;
    ack.next_wake = std::isfinite(next_wake) ? ros::Time(next_wake) : ros::Time(0);
    const std::vector<LinkCount> sent = SentCounts();
    if (digest_) digest_->Acknowledged(sent, ack.next_wake);
    for (const auto& l : sent) {
      Link link;
      link.topic = l.topic;
      link.peer = l.peer;
      link.count = l.count;
      ack.sent.push_back(link);
    }
    ack_pub_.publish(ack);
  }
  Unregister();
  return true;
}

}  // namespace minibot3d_lockstep
