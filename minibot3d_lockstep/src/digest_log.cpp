#include "minibot3d_lockstep/digest_log.h"

#include <cctype>
#include <cinttypes>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include <zlib.h>

namespace minibot3d_lockstep {

std::uint32_t ChainCrc(std::uint32_t crc, const std::uint8_t* data, std::size_t size) {
  const std::uint32_t n = static_cast<std::uint32_t>(size);
  const unsigned char length[4] = {static_cast<unsigned char>(n), static_cast<unsigned char>(n >> 8),
                                   static_cast<unsigned char>(n >> 16),
                                   static_cast<unsigned char>(n >> 24)};
  uLong c = crc32(crc, length, 4);
  return static_cast<std::uint32_t>(crc32_z(c, data, size));
}

std::vector<std::string> SplitTopicList(const std::string& text) {
  std::vector<std::string> out;
  std::string word;
  for (char ch : text + ",") {
    if (ch == ',' || std::isspace(static_cast<unsigned char>(ch))) {
      if (!word.empty()) out.push_back(word);
      word.clear();
    } else {
      word += ch;
    }
  }
  return out;
}

std::string DigestFileName(const std::string& node) {
  std::string name = node;
  while (!name.empty() && name.front() == '/') name.erase(name.begin());
  for (char& ch : name) {
    if (ch == '/') ch = '.';
  }
  return (name.empty() ? std::string("unnamed") : name) + ".digest";
}

std::string FormatStamp(std::int64_t ns) {
  char buf[40];
  const bool negative = ns < 0;
  const std::uint64_t a = negative ? static_cast<std::uint64_t>(-ns) : static_cast<std::uint64_t>(ns);
  std::snprintf(buf, sizeof(buf), "%s%" PRIu64 ".%09" PRIu64, negative ? "-" : "",
                a / UINT64_C(1000000000), a % UINT64_C(1000000000));
  return buf;
}

DigestLog::DigestLog(const std::string& dir, const std::string& node, const std::string& run_id,
                     long pid, double wall) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);  // an error shows when the file is opened
  path_ = (std::filesystem::path(dir) / DigestFileName(node)).string();
  file_ = std::fopen(path_.c_str(), "a");
  if (!file_) {
    throw std::runtime_error("cannot open the lock-step digest " + path_ + " for appending: " +
                             std::strerror(errno) + " (" + kDigestEnv + "=" + dir + ")");
  }
  std::fprintf(file_, "N %s run=%s pid=%ld wall=%.6f\n", node.c_str(),
               run_id.empty() ? "-" : run_id.c_str(), pid, wall);
  std::fflush(file_);
}

DigestLog::~DigestLog() {
  if (file_) std::fclose(file_);
}

void DigestLog::WriteMessagesOf(const std::vector<std::string>& topics) {
  whole_.insert(topics.begin(), topics.end());
}

void DigestLog::Received(const std::string& topic, const std::string& publisher,
                         const std::uint8_t* data, std::size_t size, const std::string& type) {
  In& in = in_[{topic, publisher}];
  in.crc = ChainCrc(in.crc, data, size);
  ++in.count;
  if (whole_.count(topic) == 0) return;
  static const char kHex[] = "0123456789abcdef";
  std::string line = "M " + topic + " " + publisher + " " + std::to_string(in.count) + " " +
                     (type.empty() ? std::string("?") : type) + " ";
  line.reserve(line.size() + 2 * size + 1);
  for (std::size_t i = 0; i < size; ++i) {
    line += kHex[data[i] >> 4];
    line += kHex[data[i] & 15];
  }
  if (size == 0) line += "-";
  line += "\n";
  pending_messages_.push_back(std::move(line));
}

void DigestLog::WriteIn() {
  for (auto& kv : in_) {
    In& in = kv.second;
    if (in.count == in.written) continue;
    in.written = in.count;
    std::fprintf(file_, "I %s %s %" PRIu64 " %08" PRIx32 "\n", kv.first.first.c_str(),
                 kv.first.second.c_str(), in.count, in.crc);
  }
  for (const std::string& line : pending_messages_) std::fputs(line.c_str(), file_);
  pending_messages_.clear();
}

void DigestLog::Tick(std::uint64_t seq, std::int64_t stamp_ns) {
  std::fprintf(file_, "T %" PRIu64 " %s\n", seq, FormatStamp(stamp_ns).c_str());
  WriteIn();
}

void DigestLog::Acknowledged(const std::vector<LinkCount>& sent, std::int64_t next_wake_ns) {
  for (const auto& l : sent) {
    std::uint64_t& last = out_[{l.topic, l.peer}];
    if (last == l.count) continue;
    last = l.count;
    std::fprintf(file_, "O %s %s %" PRIu64 "\n", l.topic.c_str(), l.peer.c_str(), l.count);
  }
  std::fprintf(file_, "A %s\n", FormatStamp(next_wake_ns).c_str());
  std::fflush(file_);
}

void DigestLog::ReceivedBy(std::uint64_t seq, std::int64_t stamp_ns) {
  bool any = !pending_messages_.empty();
  for (const auto& kv : in_) any = any || kv.second.count != kv.second.written;
  if (!any) return;
  Tick(seq, stamp_ns);
  std::fflush(file_);
}

}  // namespace minibot3d_lockstep
