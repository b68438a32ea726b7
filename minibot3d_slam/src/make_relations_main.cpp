// make_relations: relations for the Kümmerle et al. 2009 metric (see relations.h) from a
// ground-truth trajectory, e.g. the simulator's true pose logged as 'timestamp x y theta'.
//
//   make_relations GROUND_TRUTH OUT.relations [--every S] [--max-span S] [--seed N] [--random K]
//
// Anchors every S seconds (default 1); each anchor is related to the next anchor and to K
// (default 3) poses drawn at random among those up to --max-span seconds later (default 10).
// Exit codes: 0 written, 1 a file cannot be read or written, 2 bad arguments.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "minibot3d_slam/relations.h"

namespace {

constexpr char kUsage[] =
    "Usage: make_relations GROUND_TRUTH OUT.relations [--every S] [--max-span S] [--seed N] "
    "[--random K]\n"
    "  GROUND_TRUTH: 'timestamp x y theta' per line (true poses).\n"
    "  Writes 't1 t2 x y z roll pitch yaw' lines: anchors every S s (default 1, 0 = every pose),\n"
    "  each related to the next anchor and to K (default 3) random poses at most --max-span s\n"
    "  (default 10) later, drawn with --seed (default 0).\n";

int Usage(const std::string& error) {
  std::fprintf(stderr, "make_relations: %s\n%s", error.c_str(), kUsage);
  return 2;
}

bool ParseDouble(const char* s, double* out) {
  char* end = nullptr;
  const double v = std::strtod(s, &end);
  if (end == s || *end != '\0' || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

bool ParseUnsigned(const char* s, unsigned long long* out) {
  if (*s == '-' || *s == '\0') return false;
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(s, &end, 10);
  if (*end != '\0' || errno == ERANGE) return false;
  *out = v;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  minibot3d_slam::MakeRelationsOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    if (arg == "--every" || arg == "--max-span" || arg == "--seed" || arg == "--random") {
      if (i + 1 >= argc) return Usage(arg + " needs a value");
      const char* value = argv[++i];
      unsigned long long n = 0;
      if (arg == "--every") {
        if (!ParseDouble(value, &options.every) || options.every < 0.0) {
          return Usage(std::string("--every must be a number of seconds >= 0, got '") + value +
                       "'");
        }
      } else if (arg == "--max-span") {
        if (!ParseDouble(value, &options.max_span) || options.max_span <= 0.0) {
          return Usage(std::string("--max-span must be a number of seconds > 0, got '") + value +
                       "'");
        }
      } else if (arg == "--seed") {
        if (!ParseUnsigned(value, &n)) {
          return Usage(std::string("--seed must be an unsigned integer, got '") + value + "'");
        }
        options.seed = n;
      } else {
        if (!ParseUnsigned(value, &n) || n > 1000000) {
          return Usage(std::string("--random must be an integer in 0..1000000, got '") + value +
                       "'");
        }
        options.random_per_anchor = static_cast<int>(n);
      }
    } else if (arg.size() > 1 && arg[0] == '-') {
      return Usage("unknown option '" + arg + "'");
    } else {
      files.push_back(arg);
    }
  }
  if (files.size() != 2) return Usage("expected GROUND_TRUTH and OUT.relations");

  try {
    const auto truth = minibot3d_slam::ReadTrajectory(files[0]);
    const auto relations = minibot3d_slam::MakeRelations(truth, options);
    if (relations.empty()) {
      std::fprintf(stderr, "make_relations: '%s' gives no relation (%zu poses, need two times)\n",
                   files[0].c_str(), truth.size());
      return 1;
    }
    char comment[512];
    std::snprintf(comment, sizeof(comment),
                  "relations from ground truth '%s' by make_relations: anchors every %g s, next "
                  "anchor + %d random poses within %g s, seed %llu\n"
                  "the true pose at t2 in the robot's frame at t1 (Kuemmerle et al. 2009)",
                  files[0].c_str(), options.every, options.random_per_anchor, options.max_span,
                  static_cast<unsigned long long>(options.seed));
    minibot3d_slam::WriteRelations(files[1], relations, comment);
    double longest = 0.0;
    for (const auto& r : relations) longest = std::max(longest, r.t2 - r.t1);
    std::printf("wrote %zu relations to %s (from %zu poses, %.3f..%.3f s; longest span %.3f s)\n",
                relations.size(), files[1].c_str(), truth.size(), truth.front().time,
                truth.back().time, longest);
  } catch (const minibot3d_slam::RelationsError& e) {
    std::fprintf(stderr, "make_relations: %s\n", e.what());
    return 1;
  }
  return 0;
}
