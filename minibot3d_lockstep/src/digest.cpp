#include "minibot3d_lockstep/digest.h"

#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <typeinfo>

#include <ros/names.h>
#include <ros/param.h>
#include <ros/subscription.h>
#include <ros/subscription_callback_helper.h>
#include <ros/this_node.h>
#include <ros/topic_manager.h>

#include "minibot3d_lockstep/link_counts.h"
#include "minibot3d_lockstep/participant.h"

namespace minibot3d_lockstep {
namespace {

// Hashes a message's bytes where another callback's helper would deserialize them; nothing is
// called afterwards.
class HashingHelper : public ros::SubscriptionCallbackHelper {
 public:
  HashingHelper(DigestLog* log, std::string topic, std::string type)
      : log_(log), topic_(std::move(topic)), type_(std::move(type)) {}

  ros::VoidConstPtr deserialize(const ros::SubscriptionCallbackHelperDeserializeParams& p) override {
    static const std::string kUnknown = "?";
    const std::string* publisher = &kUnknown;
    if (p.connection_header) {
      auto it = p.connection_header->find("callerid");
      if (it != p.connection_header->end()) publisher = &it->second;
    }
    log_->Received(topic_, *publisher, p.buffer, p.length, type_);
    return ros::VoidConstPtr();  // nothing to call
  }
  void call(ros::SubscriptionCallbackHelperCallParams&) override {}
  const std::type_info& getTypeInfo() override { return typeid(HashingHelper); }
  bool isConst() override { return true; }
  bool hasHeader() override { return false; }

 private:
  DigestLog* log_;
  std::string topic_;
  std::string type_;
};

bool Recorded(const std::string& topic) {
  const std::string tick_prefix = std::string(kTickTopicPrefix) + "/";
  return topic != "/clock" && topic != kAckTopic && topic.compare(0, tick_prefix.size(), tick_prefix) != 0;
}

std::string RunId() {
  std::string id;
  ros::param::getCached("/run_id", id);
  return id;
}

}  // namespace

std::unique_ptr<DigestRecorder> DigestRecorder::FromEnvironment() {
  const char* dir = std::getenv(kDigestEnv);
  if (!dir || !*dir) return nullptr;
  auto recorder = std::make_unique<DigestRecorder>(dir);
  const char* whole = std::getenv(kDigestMessagesEnv);
  std::vector<std::string> topics;
  for (const std::string& t : SplitTopicList(whole ? whole : "")) {
    try {
      topics.push_back(ros::names::resolve(t));
    } catch (const ros::InvalidNameException& e) {
      throw std::runtime_error(std::string(kDigestMessagesEnv) + ": '" + t +
                               "' is not a topic name: " + e.what());
    }
  }
  recorder->log_.WriteMessagesOf(topics);
  return recorder;
}

DigestRecorder::DigestRecorder(const std::string& dir)
    : log_(dir, ros::this_node::getName(), RunId(), static_cast<long>(getpid()),
           ros::WallTime::now().toSec()) {}

void DigestRecorder::Instrument() {
  for (const ros::SubscriptionPtr& sub : Subscriptions()) {
    auto it = instrumented_.find(sub.get());
    if (it != instrumented_.end() && !it->second.subscription.expired()) {
      // The node's own subscribers are gone: roscpp keeps a subscription while any callback is
      // left, so this one's would keep it connected. Leaving as the node did removes it.
      if (it->second.helper && sub->getNumCallbacks() == 1) {
        Drain();
        ros::TopicManager::instance()->unsubscribe(sub->getName(), it->second.helper);
        it->second.helper.reset();
      }
      continue;
    }
    Instrumented& in = instrumented_[sub.get()];
    in.subscription = sub;
    in.helper.reset();
    if (!Recorded(sub->getName())) continue;
    in.helper = boost::make_shared<HashingHelper>(&log_, sub->getName(), sub->datatype());
    // Unbounded (0): none is dropped. A latched message already here is delivered to the new
    // callback at once.
    sub->addCallback(in.helper, "*", &queue_, 0, ros::VoidConstPtr(), false);
  }
}

void DigestRecorder::Drain() { queue_.callAvailable(); }

void DigestRecorder::Tick(std::uint64_t seq, const ros::Time& stamp) {
  Drain();
  log_.Tick(seq, static_cast<std::int64_t>(stamp.toNSec()));
}

void DigestRecorder::Acknowledged(const std::vector<LinkCount>& sent, const ros::Time& next_wake) {
  std::vector<LinkCount> recorded;
  for (const auto& l : sent) {
    if (Recorded(l.topic)) recorded.push_back(l);
  }
  log_.Acknowledged(recorded, static_cast<std::int64_t>(next_wake.toNSec()));
}

void DigestRecorder::ReceivedBy(std::uint64_t seq, const ros::Time& stamp) {
  Drain();
  log_.ReceivedBy(seq, static_cast<std::int64_t>(stamp.toNSec()));
}

}  // namespace minibot3d_lockstep
