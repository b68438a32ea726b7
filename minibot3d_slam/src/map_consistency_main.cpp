// map_consistency: how well a trajectory's scans of a CARMEN log agree where the robot came back
// (map_consistency.h), for logs without relations.
//
//   map_consistency LOG [TRAJECTORY] [--scans-of REFERENCE_LOG] [--param NAME=VALUE ...] [--worst N]
//
// With TRAJECTORY ("timestamp x y theta", what slam_offline writes), each reading of LOG is placed
// at the trajectory's pose of the same timestamp (within 1e-3 s; readings without one are left
// out and counted). Without it, at the log's own poses: raw odometry for a raw log, the corrected
// poses for a corrected one (e.g. GMapping's .gfs logs). With --scans-of, only the readings that
// REFERENCE_LOG also holds (the same ranges) are placed, so that a trajectory and a reference that
// kept only some of the log's scans are scored on the same ones. Prints one line:
//   "consistency conflict_pct P scans_inconsistent K of J agreed A conflicts C not_revisited U
//    scans N checked M placed Q of R"
// (with --scans-of, followed by "reference_scans_found F of G"),
// then the N (default 5) most inconsistent scans by time. Exit codes: 0 evaluated, 1 a file is
// bad or no reading could be placed, 2 bad arguments.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "minibot3d_slam/carmen_log.h"
#include "minibot3d_slam/map_consistency.h"
#include "minibot3d_slam/relations.h"

namespace {

using minibot3d_slam::ConsistencyOptions;
using minibot3d_slam::PlacedScan;

constexpr char kUsage[] =
    "Usage: map_consistency LOG [TRAJECTORY] [--scans-of REFERENCE_LOG] [--param NAME=VALUE ...]\n"
    "                       [--worst N]\n"
    "  LOG:        CARMEN log (FLASER / ROBOTLASER1).\n"
    "  TRAJECTORY: 'timestamp x y theta' per line (e.g. slam_offline's trajectory.txt); each\n"
    "              reading is placed at the pose with its timestamp (within 1e-3 s). Without it\n"
    "              the log's own poses are used.\n"
    "  --scans-of  place only the readings REFERENCE_LOG also holds (the same ranges), e.g. the\n"
    "              scans GMapping processed, kept in its corrected .gfs log\n"
    "  --param     resolution, max_range, tolerance, separation, every_distance, every_angle,\n"
    "              min_scan_endpoints, scan_conflict_fraction (docs/parameters/map_consistency.md)\n"
    "  --worst N   list the N most inconsistent scans (default 5)\n";

int Usage(const std::string& error) {
  std::fprintf(stderr, "map_consistency: %s\n%s", error.c_str(), kUsage);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  ConsistencyOptions options;
  int worst = 5;
  std::string reference_log;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg == "--param") {
        if (i + 1 >= argc) return Usage("--param expects NAME=VALUE");
        const std::string nv = argv[++i];
        const size_t eq = nv.find('=');
        if (eq == std::string::npos || eq == 0) return Usage("--param expects NAME=VALUE, got '" + nv + "'");
        minibot3d_slam::ConsistencyOptionTable().Set(nv.substr(0, eq), nv.substr(eq + 1), &options);
      } else if (arg == "--worst") {
        if (i + 1 >= argc) return Usage("--worst expects a count");
        char* end = nullptr;
        const long n = std::strtol(argv[++i], &end, 10);
        if (end == argv[i] || *end != '\0' || n < 0 || n > 100000) {
          return Usage(std::string("--worst expects a count >= 0, got '") + argv[i] + "'");
        }
        worst = static_cast<int>(n);
      } else if (arg == "--scans-of") {
        if (i + 1 >= argc) return Usage("--scans-of expects a log");
        reference_log = argv[++i];
      } else if (arg == "-h" || arg == "--help") {
        std::fputs(kUsage, stdout);
        return 0;
      } else if (!arg.empty() && arg[0] == '-') {
        return Usage("unknown option '" + arg + "'");
      } else {
        files.push_back(arg);
      }
    }
    if (files.empty() || files.size() > 2) return Usage("expected LOG and optionally TRAJECTORY");
    minibot3d_slam::ValidateConsistencyOptions(options);
  } catch (const std::invalid_argument& e) {
    return Usage(e.what());
  }

  try {
    std::vector<minibot3d_slam::StampedPose> trajectory;
    if (files.size() == 2) trajectory = minibot3d_slam::ReadTrajectory(files[1]);
    std::unique_ptr<minibot3d_slam::ReferenceScans> reference;
    minibot3d_slam::LogScan reading;
    if (!reference_log.empty()) {
      std::unique_ptr<minibot3d_slam::LogReader> ref = minibot3d_slam::OpenCarmenLog(reference_log);
      std::vector<minibot3d_slam::LaserScan> ref_scans;
      while (ref->Next(&reading)) ref_scans.push_back(std::move(reading.scan));
      if (ref_scans.empty()) {
        std::fprintf(stderr, "map_consistency: the reference log %s holds no laser reading\n",
                     reference_log.c_str());
        return 1;
      }
      reference = std::make_unique<minibot3d_slam::ReferenceScans>(ref_scans);
    }
    std::unique_ptr<minibot3d_slam::LogReader> log = minibot3d_slam::OpenCarmenLog(files[0]);
    std::vector<PlacedScan> scans;
    int readings = 0;
    while (log->Next(&reading)) {
      ++readings;
      if (reference && !reference->Take(reading.scan)) continue;
      PlacedScan ps;
      ps.time = reading.timestamp;
      if (trajectory.empty()) {
        ps.pose = reading.odom;
      } else {
        auto it = std::lower_bound(
            trajectory.begin(), trajectory.end(), reading.timestamp - 1e-3,
            [](const minibot3d_slam::StampedPose& p, double t) { return p.time < t; });
        if (it == trajectory.end() || it->time > reading.timestamp + 1e-3) continue;
        ps.pose = it->pose;
      }
      ps.scan = std::move(reading.scan);
      scans.push_back(std::move(ps));
    }
    if (scans.empty()) {
      if (reference && reference->taken() == 0) {
        std::fprintf(stderr, "map_consistency: none of the %d readings of %s is in %s (not a log of the same run?)\n",
                     readings, files[0].c_str(), reference_log.c_str());
      } else {
        std::fprintf(stderr, "map_consistency: none of the %d readings of %s has a pose in %s\n",
                     readings, files[0].c_str(), files.size() == 2 ? files[1].c_str() : "the log");
      }
      return 1;
    }
    const minibot3d_slam::ConsistencyReport r = minibot3d_slam::EvaluateConsistency(scans, options);
    std::printf(
        "consistency conflict_pct %.2f scans_inconsistent %zu of %d agreed %lld conflicts %lld "
        "not_revisited %lld scans %d checked %d placed %zu of %d",
        100.0 * r.conflict_fraction, r.inconsistent.size(), r.scans_judged, r.agreed, r.conflicts,
        r.not_revisited, r.scans, r.scans_checked, scans.size(), readings);
    if (reference) std::printf(" reference_scans_found %d of %d", reference->taken(), reference->size());
    std::printf("\n");
    for (int i = 0; i < worst && i < static_cast<int>(r.inconsistent.size()); ++i) {
      const auto& s = r.inconsistent[i];
      std::printf("inconsistent scan at time %.6f: %d of %d endpoints where another pass saw free space\n",
                  s.time, s.conflicts, s.agreed + s.conflicts);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "map_consistency: %s\n", e.what());
    return 1;
  }
  return 0;
}
