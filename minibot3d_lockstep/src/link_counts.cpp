#include "minibot3d_lockstep/link_counts.h"

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <map>
#include <string>

#include <ros/connection.h>
#include <ros/init.h>
#include <ros/poll_manager.h>
#include <ros/publication.h>
#include <ros/publisher_link.h>
#include <ros/subscriber_link.h>
#include <ros/subscription.h>
#include <ros/topic_manager.h>
#include <ros/transport/transport_tcp.h>
#include <ros/transport_subscriber_link.h>

namespace minibot3d_lockstep {
namespace {

// roscpp keeps the per-connection objects private. An explicit template instantiation may name a
// private member (C++17 [temp.explicit]/12); the friend function it defines hands out the member
// pointer. This reads the counters getBusStats reports, without an XML-RPC round trip.
template <typename Tag, typename Tag::type Member>
struct Expose {
  friend typename Tag::type Get(Tag) { return Member; }
};

struct SubscriptionsTag {
  using type = ros::L_Subscription ros::TopicManager::*;
  friend type Get(SubscriptionsTag);
};
struct SubsMutexTag {
  using type = boost::mutex ros::TopicManager::*;
  friend type Get(SubsMutexTag);
};
struct PublisherLinksTag {
  using type = ros::V_PublisherLink ros::Subscription::*;
  friend type Get(PublisherLinksTag);
};
struct PublisherLinksMutexTag {
  using type = boost::mutex ros::Subscription::*;
  friend type Get(PublisherLinksMutexTag);
};
struct SubscriberLinksTag {
  using type = ros::V_SubscriberLink ros::Publication::*;
  friend type Get(SubscriberLinksTag);
};
struct SubscriberLinksMutexTag {
  using type = boost::mutex ros::Publication::*;
  friend type Get(SubscriberLinksMutexTag);
};

template struct Expose<SubscriptionsTag, &ros::TopicManager::subscriptions_>;
template struct Expose<SubsMutexTag, &ros::TopicManager::subs_mutex_>;
template struct Expose<PublisherLinksTag, &ros::Subscription::publisher_links_>;
template struct Expose<PublisherLinksMutexTag, &ros::Subscription::publisher_links_mutex_>;
template struct Expose<SubscriberLinksTag, &ros::Publication::subscriber_links_>;
template struct Expose<SubscriberLinksMutexTag, &ros::Publication::subscriber_links_mutex_>;

void Sort(std::vector<LinkCount>* links) {
  std::sort(links->begin(), links->end(), [](const LinkCount& a, const LinkCount& b) {
    return a.topic != b.topic ? a.topic < b.topic : a.peer < b.peer;
  });
}

// Poll-thread iterations seen so far (the listener runs at the start of every iteration).
struct PollCounter {
  std::mutex mutex;
  std::condition_variable cv;
  std::uint64_t iterations = 0;
  bool installed = false;
};
PollCounter& Poll() {
  static PollCounter counter;
  return counter;
}

void SetNoDelay(const ros::SubscriberLinkPtr& link) {
  // Connections already switched; a weak pointer tells a live one from a new one at the same address.
  static std::map<const void*, boost::weak_ptr<ros::Connection>> done;
  static std::mutex done_mutex;
  auto* tsl = dynamic_cast<ros::TransportSubscriberLink*>(link.get());
  if (!tsl || !tsl->getConnection()) return;
  const void* key = tsl->getConnection().get();
  std::lock_guard<std::mutex> lock(done_mutex);
  auto it = done.find(key);
  if (it != done.end() && !it->second.expired()) return;
  done[key] = tsl->getConnection();
  auto tcp = boost::dynamic_pointer_cast<ros::TransportTCP>(tsl->getConnection()->getTransport());
  if (tcp) tcp->setNoDelay(true);
}

void InstallPollListener(PollCounter& poll) {
  if (poll.installed) return;
  poll.installed = true;
  ros::PollManager::instance()->addPollThreadListener([] {
    PollCounter& p = Poll();
    {
      std::lock_guard<std::mutex> l(p.mutex);
      ++p.iterations;
    }
    p.cv.notify_all();
  });
}

}  // namespace

std::vector<LinkCount> SentCounts() {
  std::vector<LinkCount> out;
  ros::V_string topics;
  const ros::TopicManagerPtr& tm = ros::TopicManager::instance();
  tm->getAdvertisedTopics(topics);
  for (const auto& topic : topics) {
    ros::PublicationPtr pub = tm->lookupPublication(topic);
    if (!pub) continue;
    boost::mutex::scoped_lock lock((*pub).*Get(SubscriberLinksMutexTag()));
    for (const auto& link : (*pub).*Get(SubscriberLinksTag())) {
      if (link->isIntraprocess()) continue;
      SetNoDelay(link);
      out.push_back(LinkCount{topic, link->getDestinationCallerID(), link->getStats().messages_sent_});
    }
  }
  Sort(&out);
  return out;
}

std::vector<LinkCount> ReceivedCounts() {
  std::vector<LinkCount> out;
  ros::TopicManager& tm = *ros::TopicManager::instance();
  boost::mutex::scoped_lock lock(tm.*Get(SubsMutexTag()));
  for (const auto& sub : tm.*Get(SubscriptionsTag())) {
    boost::mutex::scoped_lock links_lock((*sub).*Get(PublisherLinksMutexTag()));
    for (const auto& link : (*sub).*Get(PublisherLinksTag())) {
      if (link->getTransportType() == "INTRAPROCESS") continue;
      out.push_back(LinkCount{sub->getName(), link->getCallerID(),
                              link->getStats().messages_received_});
    }
  }
  Sort(&out);
  return out;
}

void SyncWithPollThread() {
  PollCounter& poll = Poll();
  std::unique_lock<std::mutex> lock(poll.mutex);
  InstallPollListener(poll);
  const std::uint64_t start = poll.iterations;
  lock.unlock();
  ros::PollManager::instance()->getPollSet().signal();  // wake poll() rather than wait 100 ms
  lock.lock();
  while (poll.iterations < start + 1 && ros::ok()) {
    // The signal wakes poll(); re-signal if an iteration was in progress and took it already.
    if (!poll.cv.wait_for(lock, std::chrono::milliseconds(2),
                          [&] { return poll.iterations >= start + 1; })) {
      lock.unlock();
      ros::PollManager::instance()->getPollSet().signal();
      lock.lock();
    }
  }
}

}  // namespace minibot3d_lockstep

namespace minibot3d_lockstep {

bool WaitForPollIteration(double timeout) {
  PollCounter& poll = Poll();
  std::unique_lock<std::mutex> lock(poll.mutex);
  InstallPollListener(poll);
  const std::uint64_t start = poll.iterations;
  return poll.cv.wait_for(lock, std::chrono::duration<double>(timeout),
                          [&] { return poll.iterations > start; });
}

}  // namespace minibot3d_lockstep
