// Lock-step coordination of a simulator and the nodes that act on its data (ROS-free).
//
// The idea is conservative discrete-event synchronisation (Chandy & Misra 1979; the same contract
// as CARLA's synchronous mode and Webots' synchronised controllers): the simulator owns sim time
// and advances it in quanta; before it advances past time t, every participant that has work at t
// has done it and said so. What makes the loop deterministic across processes is that "done"
// includes delivery: each acknowledgement carries, per ROS connection, how many messages the
// participant has queued so far, and a participant is told, with its next tick, how many it must
// have received on each of its connections before it may process them. TCPROS counts queued
// messages on the publishing end and received ones on the subscribing end of the same connection,
// and both counts start when the connection is made, so they agree whenever a participant joins.
//
// A participant works at t when (a) it has just joined, (b) t has reached the wake time it asked
// for in its last acknowledgement, or (c) a message arrived for it on one of its wake topics
// ("mail") since its last tick. Mail sent while working at t is handled at t + quantum at the
// earliest, so every hop of the loop costs one quantum of latency, as a real network would.
//
// This class holds the bookkeeping only: time and wall time are arguments, so it is tested
// without ROS. minibot3d_sim's node drives it.
#ifndef MINIBOT3D_LOCKSTEP_COORDINATOR_H
#define MINIBOT3D_LOCKSTEP_COORDINATOR_H

#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace minibot3d_lockstep {

// Messages queued on one connection (see msg/Link.msg); `peer` is the other end.
struct LinkCount {
  std::string topic;
  std::string peer;
  std::uint64_t count = 0;
  bool latched = false;  // ReceivedCounts(): the publisher latches (sends its last message on connect)
  bool operator==(const LinkCount& o) const {
    return topic == o.topic && peer == o.peer && count == o.count;
  }
};

struct CoordinatorOptions {
  double quantum = 0.005;  // s of sim time between rounds
  // Wall s a participant may take to acknowledge before it is dropped; 0: never. A participant
  // that is dropped while alive makes the run depend on the machine's speed and load.
  double timeout = 0.0;
};

// Throws std::invalid_argument naming the offending option.
void ValidateOptions(const CoordinatorOptions& options);

class Coordinator {
 public:
  static constexpr double kNever = std::numeric_limits<double>::infinity();

  // `self`: the simulator's own caller id (its sent counts are set with SetSent(self, ...)).
  Coordinator(const CoordinatorOptions& options, std::string self);

  const CoordinatorOptions& options() const { return options_; }

  // Adds a participant (or re-adds one that restarted under the same name). Returns "" on success,
  // or why it is refused.
  std::string Register(const std::string& name, const std::vector<std::string>& wake_topics);
  // Removes a participant and every count it sent or was sent. False if it was unknown.
  bool Remove(const std::string& name);
  bool Has(const std::string& name) const { return participants_.count(name) != 0; }
  std::vector<std::string> Participants() const;

  // Replaces what `publisher` (a participant or the simulator) has queued per connection.
  void SetSent(const std::string& publisher, const std::vector<LinkCount>& sent);

  // Participants that must work at sim time t, in name order (not those still waiting on a tick).
  std::vector<std::string> Due(double t) const;
  // Records that `name` was sent tick `seq` for time t at wall time `wall`.
  void MarkTicked(const std::string& name, std::uint64_t seq, double t, double wall);
  // What `name` must have received before working: per (topic, publisher), publisher in `peer`.
  std::vector<LinkCount> Expected(const std::string& name) const;

  // An acknowledgement. False (and nothing changes) if the name is unknown or seq is not the
  // tick it is waiting on.
  bool Ack(const std::string& name, std::uint64_t seq, double next_wake,
           const std::vector<LinkCount>& sent);

  // `name` is still working on tick `seq` at wall time `wall`: its time-out starts again.
  // False if it is not waiting on that tick.
  bool Heartbeat(const std::string& name, std::uint64_t seq, double wall);

  // Participants ticked and not yet acknowledged, in name order.
  std::vector<std::string> Waiting() const;
  // Waiting participants whose tick is older than options().timeout at wall time `wall` (none
  // when the timeout is 0).
  std::vector<std::string> Overdue(double wall) const;
  // Wall seconds `name` has been waiting at `wall` (0 if not waiting).
  double WaitingFor(const std::string& name, double wall) const;

 private:
  struct Participant {
    std::set<std::string> wake_topics;
    bool ticked_once = false;
    bool waiting = false;
    std::uint64_t seq = 0;
    double tick_time = 0.0;
    double tick_wall = 0.0;
    double next_wake = kNever;
    std::uint64_t mail_seen = 0;  // mail on wake topics received by the last tick
  };
  // Sum of counts on wake-topic connections into `name`.
  std::uint64_t Mail(const std::string& name, const Participant& p) const;

  CoordinatorOptions options_;
  std::string self_;
  std::map<std::string, Participant> participants_;
  // publisher -> its connections (topic, subscriber, count)
  std::map<std::string, std::vector<LinkCount>> sent_;
};

}  // namespace minibot3d_lockstep

#endif  // MINIBOT3D_LOCKSTEP_COORDINATOR_H
