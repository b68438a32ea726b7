// evaluate_relations: the relations accuracy metric of Kümmerle et al. 2009 (see relations.h) for
// one estimated trajectory.
//
//   evaluate_relations TRAJECTORY RELATIONS [--max-dt S]
//
// Prints "relations N translation_m MEAN ± STD rotation_deg MEAN ± STD" first, then the squared
// errors, the maxima and how timestamps were matched. Exit codes: 0 evaluated, 1 a file is bad or
// no relation matched the trajectory, 2 bad arguments.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "minibot3d_slam/relations.h"

namespace {

constexpr char kUsage[] =
    "Usage: evaluate_relations TRAJECTORY RELATIONS [--max-dt S]\n"
    "  TRAJECTORY: 'timestamp x y theta' per line (the SLAM estimate).\n"
    "  RELATIONS:  't1 t2 x y z roll pitch yaw' per line (true pose at t2 in the frame at t1).\n"
    "  A relation time matches a pose within 1e-3 s exactly, else the nearest pose within\n"
    "  --max-dt seconds (default 0.05); relations with an unmatched time are left out and\n"
    "  counted.\n";

int Usage(const std::string& error) {
  std::fprintf(stderr, "evaluate_relations: %s\n%s", error.c_str(), kUsage);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  minibot3d_slam::MatchOptions match;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    if (arg == "--max-dt") {
      if (i + 1 >= argc) return Usage("--max-dt needs a value");
      char* end = nullptr;
      const double v = std::strtod(argv[++i], &end);
      if (end == argv[i] || *end != '\0' || !std::isfinite(v) || v < 0.0) {
        return Usage(std::string("--max-dt must be a number of seconds >= 0, got '") + argv[i] +
                     "'");
      }
      match.nearest_tolerance = v;
    } else if (arg.size() > 1 && arg[0] == '-') {
      return Usage("unknown option '" + arg + "'");
    } else {
      files.push_back(arg);
    }
  }
  if (files.size() != 2) return Usage("expected TRAJECTORY and RELATIONS");

  try {
    const auto trajectory = minibot3d_slam::ReadTrajectory(files[0]);
    const auto relations = minibot3d_slam::ReadRelations(files[1]);
    const auto report = minibot3d_slam::EvaluateRelations(trajectory, relations, match);
    if (report.used == 0) {
      std::fprintf(stderr,
                   "evaluate_relations: none of the %d relations in '%s' matched a pose of '%s' "
                   "(%zu poses from %.3f to %.3f s) within %g s\n",
                   report.total, files[1].c_str(), files[0].c_str(), trajectory.size(),
                   trajectory.front().time, trajectory.back().time, match.nearest_tolerance);
      return 1;
    }
    std::fputs(minibot3d_slam::FormatReport(report).c_str(), stdout);
  } catch (const minibot3d_slam::RelationsError& e) {
    std::fprintf(stderr, "evaluate_relations: %s\n", e.what());
    return 1;
  }
  return 0;
}
