// The lock-step digest: per tick, what a participant received and sent, as a text file that two
// runs can be compared by (tools/lockstep_digest.py, minibot3d_lockstep.digest).
//
// Lock-step time promises that every participant receives the same messages at the same ticks in
// every run. To find where a run breaks that promise, each process appends to <dir>/<node>.digest:
//
//   N <node> run=<run_id> pid=<pid> wall=<unix time>   a process starts (a section of the file)
//   T <seq> <stamp>                                     a tick: seq and sim time from the simulator
//   I <topic> <publisher> <count> <crc>                 received on this connection by that tick:
//                                                       messages so far and the CRC-32 of all of
//                                                       them, each as its 4-byte length and bytes
//   O <topic> <subscriber> <count>                      queued to a subscriber by the tick's end
//   A <next_wake>                                       the acknowledgement (0: none asked for)
//   M <topic> <publisher> <count> <type> <hex>          message <count> of that connection, its
//                                                       bytes in hex (only for the topics named
//                                                       in kDigestMessagesEnv; after the I lines)
//
// I and O lines are written only for connections whose count changed since the last tick. The
// CRC is chained over a connection's messages in order (zlib's crc32 with the previous value as
// its seed), so one differing message makes every later line of that connection differ, and
// Python's zlib.crc32 gives the same values for the same bytes. Stamps are written as
// seconds.nanoseconds, exactly.
//
// This class is the ROS-free part: roscpp's side (which messages, when) is DigestRecorder
// (digest.h); the Python participant writes the same format.
#ifndef MINIBOT3D_LOCKSTEP_DIGEST_LOG_H
#define MINIBOT3D_LOCKSTEP_DIGEST_LOG_H

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "minibot3d_lockstep/coordinator.h"

namespace minibot3d_lockstep {

// The environment variable naming the directory digests are written to; unset or empty: off.
constexpr char kDigestEnv[] = "MINIBOT3D_LOCKSTEP_DIGEST";
// Topics (comma- or space-separated) whose received messages are written whole ("M" lines), so
// that a comparison can say which fields of a differing message differ.
constexpr char kDigestMessagesEnv[] = "MINIBOT3D_LOCKSTEP_DIGEST_MESSAGES";

// "a, /b c" -> {"a", "/b", "c"}.
std::vector<std::string> SplitTopicList(const std::string& text);

// CRC-32 (zlib's) of a message as it travels on a TCPROS connection: its length as 4 bytes,
// little-endian, then its bytes; `crc` is the value so far on the connection (0 at the start).
std::uint32_t ChainCrc(std::uint32_t crc, const std::uint8_t* data, std::size_t size);

// "/ns/node" -> "ns.node.digest" (ROS names have no dots, so no two nodes share a file).
std::string DigestFileName(const std::string& node);

// Nanoseconds as "seconds.nanoseconds" (nine digits).
std::string FormatStamp(std::int64_t nanoseconds);

class DigestLog {
 public:
  // Appends a section to dir/DigestFileName(node); the directory is made if missing. Throws
  // std::runtime_error naming the file when it cannot be opened.
  DigestLog(const std::string& dir, const std::string& node, const std::string& run_id, long pid,
            double wall);
  // Topics whose messages are written whole from now on (resolved names).
  void WriteMessagesOf(const std::vector<std::string>& topics);
  bool WritesMessagesOf(const std::string& topic) const { return whole_.count(topic) > 0; }
  ~DigestLog();
  DigestLog(const DigestLog&) = delete;
  DigestLog& operator=(const DigestLog&) = delete;

  const std::string& path() const { return path_; }

  // One message received from `publisher` on `topic`; `type` (say "std_msgs/String") is written
  // with the message's bytes when the topic is one of WriteMessagesOf's.
  void Received(const std::string& topic, const std::string& publisher, const std::uint8_t* data,
                std::size_t size, const std::string& type = "");
  // A tick begins: "T", then an "I" line per connection that received since the last tick.
  void Tick(std::uint64_t seq, std::int64_t stamp_ns);
  // The tick ends: an "O" line per connection whose sent count changed, then "A"; flushed.
  void Acknowledged(const std::vector<LinkCount>& sent, std::int64_t next_wake_ns);
  // For a node that is not ticked (the simulator): like Tick, but only written when something was
  // received since the last call; flushed.
  void ReceivedBy(std::uint64_t seq, std::int64_t stamp_ns);

 private:
  struct In {
    std::uint64_t count = 0;
    std::uint32_t crc = 0;
    std::uint64_t written = 0;  // count at the last I line
  };
  void WriteIn();

  std::string path_;
  std::FILE* file_ = nullptr;
  std::map<std::pair<std::string, std::string>, In> in_;
  std::map<std::pair<std::string, std::string>, std::uint64_t> out_;
  std::set<std::string> whole_;
  std::vector<std::string> pending_messages_;  // M lines written with the next I lines
};

}  // namespace minibot3d_lockstep

#endif  // MINIBOT3D_LOCKSTEP_DIGEST_LOG_H
