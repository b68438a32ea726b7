// What this process's roscpp connections have carried: the counts the lock-step protocol trades.
//
// roscpp counts, per TCPROS connection, the messages a publication has queued to each subscriber
// (TransportSubscriberLink) and the messages a subscription has received from each publisher
// (TransportPublisherLink). Both counts start when the connection is made and cover every message
// on it, latched ones included, so "received >= what the publisher reported as queued" means the
// message is here. roscpp exposes them only through its XML-RPC getBusStats; these functions read
// the same numbers in-process. Intra-process connections deliver synchronously and are skipped.
#ifndef MINIBOT3D_LOCKSTEP_LINK_COUNTS_H
#define MINIBOT3D_LOCKSTEP_LINK_COUNTS_H

#include <string>
#include <vector>

#include <ros/callback_queue.h>
#include <ros/forwards.h>

#include "minibot3d_lockstep/coordinator.h"

namespace minibot3d_lockstep {

// Per (topic, subscriber caller id): messages this process has queued, sorted. Messages published
// before the call and still in roscpp's publish queue are handed to their connections first,
// so they are counted (and on their way) when this returns. Also turns on
// TCP_NODELAY on every outgoing TCPROS connection: in a lock-step round a second small message on
// a connection would otherwise wait for the first one's (delayed) ACK, up to 40 ms on Linux.
std::vector<LinkCount> SentCounts();
// Makes every outgoing queue of this process's publications unbounded. SentCounts counts each
// message a connection queues; a bounded queue drops its oldest when the poll thread has not yet
// written it (a matter of thread timing), and the receiver would wait for it for ever.
void KeepEveryMessage();
// Per (topic, publisher caller id): messages this process has received, sorted.
std::vector<LinkCount> ReceivedCounts();
// This process's subscriptions (roscpp keeps its list private).
std::vector<ros::SubscriptionPtr> Subscriptions();
// Returns once roscpp's poll thread has handed every message it counted before the call to the
// callback queues (it counts a message just before queueing its callback).
void SyncWithPollThread();
// Connections the master says this process should have and does not have yet, one description
// each, ending with the other node's name: a publisher of a topic it subscribes to, a subscriber
// of a topic it advertises, or a latching publisher whose message has not arrived. Empty when the
// graph is settled (or the master cannot be asked: then "master" is the one entry).
std::vector<std::string> MissingConnections();
// The node a MissingConnections() description names (its last word).
std::string PeerOf(const std::string& missing);

// True when `node` is registered with the master and its process answers at the XML-RPC address
// it registered (getPid); false when it is gone. Blocks while a stopped process (a debugger) does
// not answer.
bool NodeAnswers(const std::string& node);

// Returns once roscpp's timer thread has queued the callback of every sim-time timer
// (ros::Timer, such as actionlib's status timer) that is due at ros::Time::now(), or after
// `timeout` wall seconds (false). The timer thread looks at the clock about once a wall
// millisecond, so without this wait a timer due at a tick runs in it or in the next one, as
// the threads happen to run.
bool WaitForDueTimers(double timeout);

// Puts the callbacks waiting in `queue` in an order that does not depend on which message's
// socket was read first: callbacks that are not a subscription's (timers, in the order they fell
// due) first, then subscriptions' topic by topic in name order; one topic's messages keep their
// order. roscpp calls them in the order they were queued, which across topics is the order the
// messages happened to arrive in.
void OrderCallbacks(ros::CallbackQueue* queue);

// Blocks until roscpp's poll thread starts another iteration (it has handled socket activity) or
// `timeout` wall seconds pass; false on time-out.
bool WaitForPollIteration(double timeout);

}  // namespace minibot3d_lockstep

#endif  // MINIBOT3D_LOCKSTEP_LINK_COUNTS_H
