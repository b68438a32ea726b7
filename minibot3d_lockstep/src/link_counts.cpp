#include "minibot3d_lockstep/link_counts.h"

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <map>
#include <string>

#include <ros/connection.h>
#include <ros/master.h>
#include <ros/network.h>
#include <xmlrpcpp/XmlRpcClient.h>
#include <ros/this_node.h>
#include <ros/init.h>
#include <ros/poll_manager.h>
#include <ros/publication.h>
#include <ros/publisher_link.h>
#include <ros/subscriber_link.h>
#include <ros/subscription.h>
#include <ros/subscription_queue.h>
#include <ros/timer_manager.h>
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

using SimTimers = ros::TimerManager<ros::Time, ros::Duration, ros::TimerEvent>;
struct TimersWaitingTag {
  using type = std::list<int32_t> SimTimers::*;
  friend type Get(TimersWaitingTag);
};
struct TimersWaitingMutexTag {
  using type = boost::mutex SimTimers::*;
  friend type Get(TimersWaitingMutexTag);
};

struct MaxQueueTag {
  using type = size_t ros::Publication::*;
  friend type Get(MaxQueueTag);
};
struct PollSignalMutexTag {
  using type = boost::recursive_mutex ros::PollManager::*;
  friend type Get(PollSignalMutexTag);
};

struct SubscriptionQueueTopicTag {
  using type = std::string ros::SubscriptionQueue::*;
  friend type Get(SubscriptionQueueTopicTag);
};

// CallbackQueue's waiting callbacks are protected members: a derived class may name them.
struct QueueAccess : ros::CallbackQueue {
  using Entries = D_CallbackInfo;
  using Entry = CallbackInfo;
  static Entries& Callbacks(ros::CallbackQueue* q) { return q->*(&QueueAccess::callbacks_); }
  static boost::mutex& Mutex(ros::CallbackQueue* q) { return q->*(&QueueAccess::mutex_); }
};

template struct Expose<SubscriptionsTag, &ros::TopicManager::subscriptions_>;
template struct Expose<MaxQueueTag, &ros::Publication::max_queue_>;
template struct Expose<PollSignalMutexTag, &ros::PollManager::signal_mutex_>;
template struct Expose<SubscriptionQueueTopicTag, &ros::SubscriptionQueue::topic_>;
template struct Expose<TimersWaitingTag, &SimTimers::waiting_>;
template struct Expose<TimersWaitingMutexTag, &SimTimers::waiting_mutex_>;
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

// Calls fn(topic, publication) for each of this process's publications, holding the lock under
// which roscpp's poll thread hands published messages to their connections (it takes a whole
// publish queue first and hands the messages over after): while it is held, no message is half
// way between the two, and no queue limit is being read.
template <typename Fn>
void ForEachPublication(Fn fn) {
  ros::V_string topics;
  const ros::TopicManagerPtr& tm = ros::TopicManager::instance();
  tm->getAdvertisedTopics(topics);
  ros::PollManager& poll = *ros::PollManager::instance();
  boost::recursive_mutex::scoped_lock poll_lock(poll.*Get(PollSignalMutexTag()));
  for (const auto& topic : topics) {
    ros::PublicationPtr pub = tm->lookupPublication(topic);
    if (pub) fn(topic, *pub);
  }
}

}  // namespace

std::vector<LinkCount> SentCounts() {
  std::vector<LinkCount> out;
  ForEachPublication([&out](const std::string& topic, ros::Publication& pub) {
    // publish() only queues the message; the poll thread hands it to each connection (and counts
    // it) later. What this thread has published is handed over here (or was, completely), so it
    // is counted now.
    pub.processPublishQueue();
    boost::mutex::scoped_lock lock(pub.*Get(SubscriberLinksMutexTag()));
    for (const auto& link : pub.*Get(SubscriberLinksTag())) {
      if (link->isIntraprocess()) continue;
      SetNoDelay(link);
      out.push_back(LinkCount{topic, link->getDestinationCallerID(), link->getStats().messages_sent_});
    }
  });
  Sort(&out);
  return out;
}

void KeepEveryMessage() {
  ForEachPublication([](const std::string&, ros::Publication& pub) {
    pub.*Get(MaxQueueTag()) = 0;  // 0: unbounded
  });
}

std::vector<LinkCount> ReceivedCounts() {
  std::vector<LinkCount> out;
  ros::TopicManager& tm = *ros::TopicManager::instance();
  boost::mutex::scoped_lock lock(tm.*Get(SubsMutexTag()));
  for (const auto& sub : tm.*Get(SubscriptionsTag())) {
    boost::mutex::scoped_lock links_lock((*sub).*Get(PublisherLinksMutexTag()));
    for (const auto& link : (*sub).*Get(PublisherLinksTag())) {
      if (link->getTransportType() == "INTRAPROCESS") continue;
      LinkCount l{sub->getName(), link->getCallerID(), link->getStats().messages_received_};
      l.latched = link->isLatched();
      out.push_back(l);
    }
  }
  Sort(&out);
  return out;
}

std::vector<ros::SubscriptionPtr> Subscriptions() {
  ros::TopicManager& tm = *ros::TopicManager::instance();
  boost::mutex::scoped_lock lock(tm.*Get(SubsMutexTag()));
  const ros::L_Subscription& subs = tm.*Get(SubscriptionsTag());
  return std::vector<ros::SubscriptionPtr>(subs.begin(), subs.end());
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

void OrderCallbacks(ros::CallbackQueue* queue) {
  boost::mutex::scoped_lock lock(QueueAccess::Mutex(queue));
  QueueAccess::Entries& entries = QueueAccess::Callbacks(queue);
  // The topic of a subscription's callback; "" (first) for any other callback.
  const auto topic = [](const QueueAccess::Entry& e) -> const std::string& {
    static const std::string kNone;
    const auto* sq = dynamic_cast<const ros::SubscriptionQueue*>(e.callback.get());
    return sq ? sq->*Get(SubscriptionQueueTopicTag()) : kNone;
  };
  std::stable_sort(entries.begin(), entries.end(),
                   [&](const QueueAccess::Entry& a, const QueueAccess::Entry& b) {
                     return topic(a) < topic(b);
                   });
}

bool WaitForDueTimers(double timeout) {
  // The timer thread keeps the timers not yet queued in `waiting_`, earliest first; it queues a
  // due one's callback and takes it off the list under the list's lock. hasPending() (public)
  // says whether a timer is due; it takes the timers' lock, which the timer thread takes before
  // the list's, so the list's is not held while asking.
  SimTimers& timers = SimTimers::global();
  const ros::WallTime start = ros::WallTime::now();
  while (ros::ok()) {
    int32_t front;
    {
      boost::mutex::scoped_lock lock(timers.*Get(TimersWaitingMutexTag()));
      const std::list<int32_t>& waiting = timers.*Get(TimersWaitingTag());
      if (waiting.empty()) return true;
      front = waiting.front();
    }
    if (!timers.hasPending(front)) return true;
    if ((ros::WallTime::now() - start).toSec() > timeout) return false;
    ros::WallDuration(0.00005).sleep();
  }
  return false;
}

bool WaitForPollIteration(double timeout) {
  PollCounter& poll = Poll();
  std::unique_lock<std::mutex> lock(poll.mutex);
  InstallPollListener(poll);
  const std::uint64_t start = poll.iterations;
  return poll.cv.wait_for(lock, std::chrono::duration<double>(timeout),
                          [&] { return poll.iterations > start; });
}

namespace {

// Messages `node` has queued to this node on `topic`, from its own getBusInfo/getBusStats
// (the XML-RPC calls rosnode uses); -1 if it cannot be asked.
long SentByPeer(const std::string& topic, const std::string& node) {
  using V = XmlRpc::XmlRpcValue;
  // Type-checked reads: a node's answer is input, never trusted to have the expected shape.
  auto str = [](V& v) { return v.getType() == V::TypeString ? static_cast<std::string>(v) : ""; };
  auto num = [](V& v) { return v.getType() == V::TypeInt ? static_cast<int>(v) : -1; };
  auto arr = [](V& v, int n) { return v.getType() == V::TypeArray && v.size() >= n; };
  V args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = node;
  if (!ros::master::execute("lookupNode", args, result, payload, false)) return -1;
  std::string host;
  uint32_t port = 0;
  if (!ros::network::splitURI(str(payload), host, port)) return -1;
  XmlRpc::XmlRpcClient client(host.c_str(), port, "/");
  V a, info, stats;
  a[0] = ros::this_node::getName();
  if (!client.execute("getBusInfo", a, info) || !client.execute("getBusStats", a, stats)) return -1;
  // info: [code, msg, [[conn_id, destination, direction, transport, topic, connected, ...]]]
  if (!arr(info, 3) || !arr(info[2], 0)) return -1;
  int conn_id = -1;
  for (int i = 0; i < info[2].size(); ++i) {
    V& c = info[2][i];
    if (arr(c, 5) && str(c[4]) == topic && str(c[1]) == ros::this_node::getName() &&
        str(c[2]) == "o") {
      conn_id = num(c[0]);
    }
  }
  if (conn_id < 0) return -1;
  // stats: [publish_stats, subscribe_stats, service_stats] from roscpp, [code, msg, that] from
  // rospy; a publish_stats entry is [topic, [[conn_id, bytes, data_bytes, num_sent, connected]]]
  // from roscpp and [topic, data_bytes, [[conn_id, bytes, num_sent, connected]]] from rospy.
  if (arr(stats, 3) && stats[0].getType() == V::TypeInt) stats = V(stats[2]);
  if (!arr(stats, 1) || !arr(stats[0], 0)) return -1;
  V& pubs = stats[0];
  for (int i = 0; i < pubs.size(); ++i) {
    if (!arr(pubs[i], 2) || str(pubs[i][0]) != topic) continue;
    V& cs = pubs[i][pubs[i].size() - 1];
    if (!arr(cs, 0)) continue;
    for (int k = 0; k < cs.size(); ++k) {
      if (!arr(cs[k], 3) || num(cs[k][0]) != conn_id) continue;
      return num(cs[k][cs[k].size() >= 5 ? 3 : 2]);
    }
  }
  return -1;
}

}  // namespace

std::string PeerOf(const std::string& missing) {
  const auto space = missing.rfind(' ');
  return space == std::string::npos ? missing : missing.substr(space + 1);
}

bool NodeAnswers(const std::string& node) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = node;
  if (!ros::master::execute("lookupNode", args, result, payload, false) ||
      payload.getType() != XmlRpc::XmlRpcValue::TypeString) {
    return false;
  }
  std::string host;
  uint32_t port = 0;
  if (!ros::network::splitURI(static_cast<std::string>(payload), host, port)) return false;
  XmlRpc::XmlRpcClient client(host.c_str(), port, "/");
  XmlRpc::XmlRpcValue a, pid;
  a[0] = ros::this_node::getName();
  return client.execute("getPid", a, pid) && !client.isFault();
}

std::vector<std::string> MissingConnections() {
  std::vector<std::string> missing;
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  if (!ros::master::execute("getSystemState", args, result, payload, false) ||
      payload.getType() != XmlRpc::XmlRpcValue::TypeArray || payload.size() < 2) {
    return {"master"};
  }
  const std::string self = ros::this_node::getName();
  ros::V_string subscribed, advertised;
  ros::this_node::getSubscribedTopics(subscribed);
  ros::this_node::getAdvertisedTopics(advertised);
  const auto in = ReceivedCounts();
  const auto out = SentCounts();
  auto has = [](const std::vector<LinkCount>& links, const std::string& topic,
                const std::string& peer) {
    for (const auto& l : links) {
      if (l.topic == topic && l.peer == peer) return true;
    }
    return false;
  };
  // payload[0]: [[topic, [publishers]]...], payload[1]: [[topic, [subscribers]]...]
  for (int kind = 0; kind < 2; ++kind) {
    const ros::V_string& mine = kind == 0 ? subscribed : advertised;
    XmlRpc::XmlRpcValue& list = payload[kind];
    for (int i = 0; i < list.size(); ++i) {
      const std::string topic = list[i][0];
      if (std::find(mine.begin(), mine.end(), topic) == mine.end()) continue;
      XmlRpc::XmlRpcValue& nodes = list[i][1];
      for (int j = 0; j < nodes.size(); ++j) {
        const std::string node = nodes[j];
        if (node == self) continue;
        if (!has(kind == 0 ? in : out, topic, node)) {
          missing.push_back((kind == 0 ? topic + " from " : topic + " to ") + node);
        }
      }
    }
  }
  for (const auto& l : in) {
    if (!l.latched) continue;
    // A latching publisher sends its last message when a connection is made, the first on the
    // connection; ask it whether it has queued one to this node (it may not have published yet:
    // then there is nothing to wait for). Its later messages are not waited for here: a
    // participant's and the simulator's are announced by ticks like any others, and a publisher
    // streaming while sim time runs free (/clock) would always be ahead.
    const long sent = SentByPeer(l.topic, l.peer);
    if (sent < 0 || static_cast<long>(l.count) < std::min(sent, 1L)) {
      missing.push_back(l.topic + " (latched) from " + l.peer);
    }
  }
  std::sort(missing.begin(), missing.end());
  return missing;
}

}  // namespace minibot3d_lockstep
