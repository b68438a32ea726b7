// The relations metric of Kümmerle et al. 2009 (see relations.h).
#include "minibot3d_slam/relations.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <utility>

#include "minibot3d_map_io/file_util.h"

namespace minibot3d_slam {

using minibot3d_map_io::FormatDouble;

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// Reads a whitespace-separated numeric table with exactly `columns` numbers per data line.
// `what` names the file's kind for messages ("trajectory", "relations").
std::vector<std::vector<double>> ReadTable(const std::string& path, const char* what,
                                           std::size_t columns, const char* layout) {
  std::ifstream in(path);
  if (!in) {
    throw RelationsError(std::string("cannot open ") + what + " file '" + path +
                         "': " + std::strerror(errno));
  }
  std::vector<std::vector<double>> rows;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    std::vector<double> row;
    std::string token;
    while (fields >> token) {
      char* end = nullptr;
      const double v = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0' || !std::isfinite(v)) {
        throw RelationsError(path + ":" + std::to_string(line_no) + ": '" + token +
                             "' is not a finite number (expected '" + layout + "')");
      }
      row.push_back(v);
    }
    if (row.empty()) continue;
    if (row.size() != columns) {
      throw RelationsError(path + ":" + std::to_string(line_no) + ": expected " +
                           std::to_string(columns) + " numbers '" + layout + "', got " +
                           std::to_string(row.size()));
    }
    rows.push_back(std::move(row));
  }
  if (in.bad()) throw RelationsError(std::string("error reading ") + what + " file '" + path + "'");
  if (rows.empty()) {
    throw RelationsError(std::string(what) + " file '" + path + "' has no data lines ('" +
                         layout + "')");
  }
  return rows;
}

std::string CommentBlock(const std::string& comment) {
  std::string out;
  if (comment.empty()) return out;
  std::istringstream lines(comment);
  std::string line;
  while (std::getline(lines, line)) out += "# " + line + "\n";
  return out;
}

void WriteOrThrow(const std::string& path, const std::string& contents, const char* what) {
  const std::string error = minibot3d_map_io::WriteFileAtomically(path, contents);
  if (!error.empty()) {
    throw RelationsError(std::string("cannot write ") + what + " file '" + path + "': " + error);
  }
}

std::vector<StampedPose> SortedByTime(std::vector<StampedPose> poses) {
  std::stable_sort(poses.begin(), poses.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.time < b.time; });
  return poses;
}

// Index of the pose nearest in time to t in time-sorted `poses` (the earlier one on a tie).
std::size_t Nearest(const std::vector<StampedPose>& poses, double t) {
  const auto it = std::lower_bound(poses.begin(), poses.end(), t,
                                   [](const StampedPose& p, double time) { return p.time < time; });
  if (it == poses.begin()) return 0;
  if (it == poses.end()) return poses.size() - 1;
  const std::size_t after = static_cast<std::size_t>(it - poses.begin());
  return (t - poses[after - 1].time <= it->time - t) ? after - 1 : after;
}

ErrorStats Stats(const std::vector<double>& values) {
  ErrorStats s;
  if (values.empty()) return s;
  double sum = 0.0;
  for (double v : values) {
    sum += v;
    s.max = std::max(s.max, v);
  }
  s.mean = sum / values.size();
  if (values.size() > 1) {
    double sq = 0.0;
    for (double v : values) sq += (v - s.mean) * (v - s.mean);
    s.stddev = std::sqrt(sq / (values.size() - 1));
  }
  return s;
}

// Uniform integer in [0, n) from a 64-bit engine, by rejection: unlike
// std::uniform_int_distribution its sequence is the same with every standard library, so a
// --seed gives the same relations everywhere.
std::size_t UniformIndex(std::mt19937_64* rng, std::size_t n) {
  const std::uint64_t range = static_cast<std::uint64_t>(n);
  const std::uint64_t limit = std::mt19937_64::max() - std::mt19937_64::max() % range;
  std::uint64_t r = (*rng)();
  while (r >= limit) r = (*rng)();
  return static_cast<std::size_t>(r % range);
}

}  // namespace

std::vector<StampedPose> ReadTrajectory(const std::string& path) {
  std::vector<StampedPose> poses;
  for (const auto& row : ReadTable(path, "trajectory", 4, "timestamp x y theta")) {
    StampedPose p;
    p.time = row[0];
    p.pose = Pose2{row[1], row[2], row[3]};
    poses.push_back(p);
  }
  return SortedByTime(std::move(poses));
}

std::vector<Relation> ReadRelations(const std::string& path) {
  std::vector<Relation> relations;
  for (const auto& row : ReadTable(path, "relations", 8, "t1 t2 x y z roll pitch yaw")) {
    Relation r;
    r.t1 = row[0];
    r.t2 = row[1];
    r.delta = Pose2{row[2], row[3], row[7]};  // z, roll, pitch (row[4..6]) are not planar
    relations.push_back(r);
  }
  return relations;
}

void WriteTrajectory(const std::string& path, const std::vector<StampedPose>& poses,
                     const std::string& comment) {
  std::string out = CommentBlock(comment) + "# timestamp x y theta\n";
  for (const StampedPose& p : poses) {
    out += FormatDouble(p.time) + " " + FormatDouble(p.pose.x) + " " +
           FormatDouble(p.pose.y) + " " + FormatDouble(p.pose.yaw) + "\n";
  }
  WriteOrThrow(path, out, "trajectory");
}

void WriteRelations(const std::string& path, const std::vector<Relation>& relations,
                    const std::string& comment) {
  std::string out = CommentBlock(comment) + "# t1 t2 x y z roll pitch yaw\n";
  for (const Relation& r : relations) {
    out += FormatDouble(r.t1) + " " + FormatDouble(r.t2) + " " +
           FormatDouble(r.delta.x) + " " + FormatDouble(r.delta.y) +
           " 0 0 0 " + FormatDouble(r.delta.yaw) + "\n";
  }
  WriteOrThrow(path, out, "relations");
}

RelationsReport EvaluateRelations(const std::vector<StampedPose>& estimate,
                                  const std::vector<Relation>& relations,
                                  const MatchOptions& options) {
  const std::vector<StampedPose> poses = SortedByTime(estimate);
  RelationsReport report;
  report.total = static_cast<int>(relations.size());
  std::vector<double> trans, rot, trans_sq, rot_sq;

  // Finds the pose for time t; false when none is within nearest_tolerance.
  struct Lookup {
    bool found = false;
    bool exact = false;
    double offset = 0.0;
    Pose2 pose;
  };
  auto find = [&](double t) {
    Lookup l;
    if (poses.empty()) return l;
    const StampedPose& p = poses[Nearest(poses, t)];
    l.offset = std::abs(p.time - t);
    l.exact = l.offset <= options.exact_tolerance;
    l.found = l.exact || l.offset <= options.nearest_tolerance;
    l.pose = p.pose;
    return l;
  };

  for (const Relation& r : relations) {
    const Lookup a = find(r.t1);
    const Lookup b = find(r.t2);
    if (!a.found || !b.found) {
      ++report.unmatched;
      continue;
    }
    ++report.used;
    for (const Lookup* l : {&a, &b}) {
      ++(l->exact ? report.exact_matches : report.nearest_matches);
      report.max_time_offset = std::max(report.max_time_offset, l->offset);
    }
    const Pose2 estimated = Between(a.pose, b.pose);   // δ_ij = x_j ⊖ x_i
    const Pose2 error = Between(r.delta, estimated);   // δ_ij ⊖ δ*_ij
    report.errors.push_back(error);
    const double t = std::hypot(error.x, error.y);
    const double a_err = std::abs(NormalizeAngle(error.yaw));
    trans.push_back(t);
    rot.push_back(a_err);
    trans_sq.push_back(t * t);
    rot_sq.push_back(a_err * a_err);
  }
  report.translation = Stats(trans);
  report.rotation = Stats(rot);
  report.translation_sq = Stats(trans_sq);
  report.rotation_sq = Stats(rot_sq);
  return report;
}

std::string FormatReport(const RelationsReport& report) {
  const double deg2 = kRadToDeg * kRadToDeg;
  char buf[512];
  std::string out;
  std::snprintf(buf, sizeof(buf),
                "relations %d translation_m %.4f ± %.4f rotation_deg %.3f ± %.3f\n",
                report.used, report.translation.mean, report.translation.stddev,
                report.rotation.mean * kRadToDeg, report.rotation.stddev * kRadToDeg);
  out += buf;
  std::snprintf(buf, sizeof(buf),
                "squared translation_m2 %.6f ± %.6f rotation_deg2 %.4f ± %.4f\n",
                report.translation_sq.mean, report.translation_sq.stddev,
                report.rotation_sq.mean * deg2, report.rotation_sq.stddev * deg2);
  out += buf;
  std::snprintf(buf, sizeof(buf), "max translation_m %.4f rotation_deg %.3f\n",
                report.translation.max, report.rotation.max * kRadToDeg);
  out += buf;
  std::snprintf(buf, sizeof(buf),
                "matched %d of %d relations (unmatched %d); pose look-ups: exact %d, nearest %d "
                "(max |dt| %.4f s)\n",
                report.used, report.total, report.unmatched, report.exact_matches,
                report.nearest_matches, report.max_time_offset);
  out += buf;
  return out;
}

std::vector<Relation> MakeRelations(const std::vector<StampedPose>& ground_truth,
                                    const MakeRelationsOptions& options) {
  if (!(options.every >= 0.0) || !std::isfinite(options.every)) {
    throw RelationsError("every must be >= 0 s, got " + FormatDouble(options.every));
  }
  if (!(options.max_span > 0.0) || !std::isfinite(options.max_span)) {
    throw RelationsError("max span must be > 0 s, got " +
                         FormatDouble(options.max_span));
  }
  if (options.random_per_anchor < 0) {
    throw RelationsError("random relations per anchor must be >= 0, got " +
                         std::to_string(options.random_per_anchor));
  }
  const std::vector<StampedPose> poses = SortedByTime(ground_truth);

  std::vector<std::size_t> anchors;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (anchors.empty() || poses[i].time >= poses[anchors.back()].time + options.every) {
      // every = 0 still skips poses with the time of the previous anchor: a relation needs
      // two distinct times.
      if (!anchors.empty() && poses[i].time <= poses[anchors.back()].time) continue;
      anchors.push_back(i);
    }
  }

  std::mt19937_64 rng(options.seed);
  std::set<std::pair<std::size_t, std::size_t>> pairs;
  std::vector<std::size_t> candidates;
  for (std::size_t k = 0; k < anchors.size(); ++k) {
    const std::size_t i = anchors[k];
    if (k + 1 < anchors.size()) pairs.emplace(i, anchors[k + 1]);
    candidates.clear();
    const double span_end = poses[i].time + options.max_span;
    for (std::size_t j = i + 1; j < poses.size() && poses[j].time <= span_end; ++j) {
      if (poses[j].time > poses[i].time) candidates.push_back(j);
    }
    // A partial Fisher-Yates shuffle: the first `take` candidates are a uniform sample.
    const std::size_t take =
        std::min(candidates.size(), static_cast<std::size_t>(options.random_per_anchor));
    for (std::size_t n = 0; n < take; ++n) {
      std::swap(candidates[n], candidates[n + UniformIndex(&rng, candidates.size() - n)]);
      pairs.emplace(i, candidates[n]);
    }
  }

  std::vector<Relation> relations;
  relations.reserve(pairs.size());
  for (const auto& [i, j] : pairs) {  // std::set order = (t1, t2) order, poses being sorted
    Relation r;
    r.t1 = poses[i].time;
    r.t2 = poses[j].time;
    r.delta = Between(poses[i].pose, poses[j].pose);
    relations.push_back(r);
  }
  return relations;
}

}  // namespace minibot3d_slam
