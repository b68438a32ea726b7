// roscpp's side of the lock-step digest (digest_log.h): the bytes of every message this process
// receives, per connection, and the counts it sends, written at its ticks.
//
// roscpp hands a subscription's messages to each callback registered on it, still serialized
// until a callback's helper deserializes them. The recorder registers one more callback on every
// subscription of the process, on a queue of its own, whose helper hashes the bytes instead of
// deserializing them; Drain() runs that queue. Messages on /clock (its count depends on how fast
// the simulator ran, not on what it did) and on the lock-step protocol's own topics are not
// recorded. With the digest off (kDigestEnv unset) nothing of this exists.
#ifndef MINIBOT3D_LOCKSTEP_DIGEST_H
#define MINIBOT3D_LOCKSTEP_DIGEST_H

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <ros/callback_queue.h>
#include <ros/forwards.h>
#include <ros/subscription_callback_helper.h>
#include <ros/time.h>

#include "minibot3d_lockstep/digest_log.h"

namespace minibot3d_lockstep {

class DigestRecorder {
 public:
  // A recorder writing to $MINIBOT3D_LOCKSTEP_DIGEST, or nullptr when it is unset or empty.
  // Throws std::runtime_error naming the file when it cannot be written.
  static std::unique_ptr<DigestRecorder> FromEnvironment();

  explicit DigestRecorder(const std::string& dir);
  DigestRecorder(const DigestRecorder&) = delete;
  DigestRecorder& operator=(const DigestRecorder&) = delete;

  const std::string& path() const { return log_.path(); }

  // Registers the digest's callback on every subscription that does not have it yet, and takes
  // it off those the node has left (so that they end as they would without it). Call it before
  // any message can arrive on a new subscription (at the start, and at the end of every tick) so
  // that none is missed.
  void Instrument();
  // Hashes every message delivered to this process so far.
  void Drain();
  // A participant's tick, once its messages are here; and its acknowledgement.
  void Tick(std::uint64_t seq, const ros::Time& stamp);
  void Acknowledged(const std::vector<LinkCount>& sent, const ros::Time& next_wake);
  // The simulator: what arrived by the end of tick `seq` (written only when something did).
  void ReceivedBy(std::uint64_t seq, const ros::Time& stamp);

 private:
  DigestLog log_;
  ros::CallbackQueue queue_;
  struct Instrumented {
    boost::weak_ptr<ros::Subscription> subscription;
    ros::SubscriptionCallbackHelperPtr helper;  // null: not recorded
  };
  std::map<const void*, Instrumented> instrumented_;
};

}  // namespace minibot3d_lockstep

#endif  // MINIBOT3D_LOCKSTEP_DIGEST_H
