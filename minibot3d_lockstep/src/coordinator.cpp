#include "minibot3d_lockstep/coordinator.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace minibot3d_lockstep {

void ValidateOptions(const CoordinatorOptions& o) {
  if (!(o.quantum > 0.0) || !std::isfinite(o.quantum) || o.quantum > 1.0) {
    std::ostringstream m;
    m << "lockstep_quantum must be in (0, 1] s, got " << o.quantum;
    throw std::invalid_argument(m.str());
  }
  if (!(o.timeout >= 0.0) || !std::isfinite(o.timeout)) {
    std::ostringstream m;
    m << "lockstep_timeout must be >= 0 wall s (0: never), got " << o.timeout;
    throw std::invalid_argument(m.str());
  }
}

Coordinator::Coordinator(const CoordinatorOptions& options, std::string self)
    : options_(options), self_(std::move(self)) {
  ValidateOptions(options_);
}

std::string Coordinator::Register(const std::string& name,
                                  const std::vector<std::string>& wake_topics) {
  if (name.empty()) return "empty participant name";
  if (name == self_) return "'" + name + "' is the simulator's own name";
  if (participants_.count(name)) Remove(name);  // a restarted node: its old connections are gone
  Participant p;
  p.wake_topics.insert(wake_topics.begin(), wake_topics.end());
  participants_[name] = p;
  participants_[name].mail_seen = Mail(name, participants_[name]);
  return "";
}

bool Coordinator::Remove(const std::string& name) {
  if (!participants_.erase(name)) return false;
  sent_.erase(name);
  for (auto& kv : sent_) {
    auto& links = kv.second;
    for (auto it = links.begin(); it != links.end();) {
      it = it->peer == name ? links.erase(it) : it + 1;
    }
  }
  return true;
}

std::vector<std::string> Coordinator::Participants() const {
  std::vector<std::string> names;
  for (const auto& kv : participants_) names.push_back(kv.first);
  return names;
}

void Coordinator::SetSent(const std::string& publisher, const std::vector<LinkCount>& sent) {
  if (publisher != self_ && !participants_.count(publisher)) return;
  auto& links = sent_[publisher];
  links.clear();
  for (const auto& l : sent) {
    // Only connections into participants matter: nobody waits on the others.
    if (l.peer == self_ || participants_.count(l.peer)) links.push_back(l);
  }
}

std::uint64_t Coordinator::Mail(const std::string& name, const Participant& p) const {
  std::uint64_t n = 0;
  if (p.wake_topics.empty()) return 0;
  for (const auto& kv : sent_) {
    for (const auto& l : kv.second) {
      if (l.peer == name && p.wake_topics.count(l.topic)) n += l.count;
    }
  }
  return n;
}

std::vector<std::string> Coordinator::Due(double t) const {
  std::vector<std::string> due;
  const double eps = 1e-9;
  for (const auto& kv : participants_) {
    const Participant& p = kv.second;
    if (p.waiting) continue;
    if (!p.ticked_once || p.next_wake <= t + eps || Mail(kv.first, p) > p.mail_seen) {
      due.push_back(kv.first);
    }
  }
  return due;
}

void Coordinator::MarkTicked(const std::string& name, std::uint64_t seq, double t, double wall) {
  auto it = participants_.find(name);
  if (it == participants_.end()) return;
  Participant& p = it->second;
  p.ticked_once = true;
  p.waiting = true;
  p.seq = seq;
  p.tick_time = t;
  p.tick_wall = wall;
  p.mail_seen = Mail(name, p);
}

std::vector<LinkCount> Coordinator::Expected(const std::string& name) const {
  std::vector<LinkCount> expected;
  for (const auto& kv : sent_) {
    if (kv.first == name) continue;
    for (const auto& l : kv.second) {
      if (l.peer == name) expected.push_back(LinkCount{l.topic, kv.first, l.count});
    }
  }
  return expected;
}

bool Coordinator::Ack(const std::string& name, std::uint64_t seq, double next_wake,
                      const std::vector<LinkCount>& sent) {
  auto it = participants_.find(name);
  if (it == participants_.end()) return false;
  Participant& p = it->second;
  if (!p.waiting || p.seq != seq) return false;
  p.waiting = false;
  // A wake time at or before the tick it answers would wake it again at once: treat as "next
  // quantum" so that a participant asking for every quantum gets exactly that.
  p.next_wake = next_wake > 0.0 ? std::max(next_wake, p.tick_time + options_.quantum) : kNever;
  SetSent(name, sent);
  return true;
}

bool Coordinator::Heartbeat(const std::string& name, std::uint64_t seq, double wall) {
  auto it = participants_.find(name);
  if (it == participants_.end() || !it->second.waiting || it->second.seq != seq) return false;
  it->second.tick_wall = wall;
  return true;
}

std::vector<std::string> Coordinator::Waiting() const {
  std::vector<std::string> w;
  for (const auto& kv : participants_) {
    if (kv.second.waiting) w.push_back(kv.first);
  }
  return w;
}

std::vector<std::string> Coordinator::Overdue(double wall) const {
  std::vector<std::string> w;
  if (options_.timeout <= 0.0) return w;
  for (const auto& kv : participants_) {
    if (kv.second.waiting && wall - kv.second.tick_wall > options_.timeout) w.push_back(kv.first);
  }
  return w;
}

double Coordinator::WaitingFor(const std::string& name, double wall) const {
  auto it = participants_.find(name);
  if (it == participants_.end() || !it->second.waiting) return 0.0;
  return wall - it->second.tick_wall;
}

}  // namespace minibot3d_lockstep
