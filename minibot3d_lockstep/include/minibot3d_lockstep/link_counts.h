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

#include <vector>

#include "minibot3d_lockstep/coordinator.h"

namespace minibot3d_lockstep {

// Per (topic, subscriber caller id): messages this process has queued, sorted. Messages published
// before the call and still in roscpp's publish queue are handed to their connections first,
// so they are counted (and on their way) when this returns. Also turns on
// TCP_NODELAY on every outgoing TCPROS connection: in a lock-step round a second small message on
// a connection would otherwise wait for the first one's (delayed) ACK, up to 40 ms on Linux.
std::vector<LinkCount> SentCounts();
// Per (topic, publisher caller id): messages this process has received, sorted.
std::vector<LinkCount> ReceivedCounts();
// Returns once roscpp's poll thread has handed every message it counted before the call to the
// callback queues (it counts a message just before queueing its callback).
void SyncWithPollThread();
// Connections the master says this process should have and does not have yet, one description
// each: a publisher of a topic it subscribes to, a subscriber of a topic it advertises, or a
// latching publisher whose message has not arrived. Empty when the graph is settled (or the master
// cannot be asked: then "master" is the one entry).
std::vector<std::string> MissingConnections();

// Blocks until roscpp's poll thread starts another iteration (it has handled socket activity) or
// `timeout` wall seconds pass; false on time-out.
bool WaitForPollIteration(double timeout);

}  // namespace minibot3d_lockstep

#endif  // MINIBOT3D_LOCKSTEP_LINK_COUNTS_H
