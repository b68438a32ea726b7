// slam_offline: runs the RBPF SLAM core (rbpf_slam.h) on a CARMEN log or a ROS bag without a
// roscore and writes the best particle's map (map_server format) and trajectory.
//
//   slam_offline --log FILE | --bag FILE [--scan-topic /scan] [--odom-topic T] [--base-frame F]
//                [--odom-frame F]  [--out DIR] [--particles N] [--param-file YAML]
//                [--param NAME=VALUE ...] [--odometry-between] [--quiet]
//
// DIR/trajectory.txt has one line "timestamp x y theta" for every laser reading fed to the filter:
// the final best particle's pose at processed readings, and for the readings in between, the pose
// at the previous processed reading composed with the odometry increment since it. Timestamps are
// the log's ipc_timestamp. SIGINT stops the run early; what was processed is still written.
#include <sys/resource.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "minibot3d_slam/bag_log.h"
#include "minibot3d_slam/carmen_log.h"
#include "minibot3d_slam/gmapping_options.h"
#include "minibot3d_slam/map_files.h"
#include "minibot3d_slam/rbpf_slam.h"

namespace {

using minibot3d_slam::GmappingOptions;
using minibot3d_slam::GridMap;
using minibot3d_slam::Pose2;

volatile std::sig_atomic_t g_interrupted = 0;

void OnSigint(int) { g_interrupted = 1; }

constexpr char kUsage[] =
    "usage: slam_offline (--log FILE | --bag FILE [--scan-topic T] [--odom-topic T]\n"
    "                    [--base-frame F] [--odom-frame F]) [--out DIR] [--particles N]\n"
    "                    [--param-file YAML] [--param NAME=VALUE ...] [--odometry-between] [--quiet]\n"
    "  --log FILE          CARMEN log (FLASER / ROBOTLASER1 with odometry)\n"
    "  --bag FILE          ROS bag: scans from --scan-topic (default /scan), odometry from /tf\n"
    "                      (--odom-frame → --base-frame, default odom → base_footprint) or from a\n"
    "                      nav_msgs/Odometry --odom-topic\n"
    "  --param-file YAML   gmapping parameters as slam_gmapping loads them (e.g.\n"
    "                      config/gmapping.yaml; its base_frame/odom_frame are used for bags)\n"
    "  --out DIR           output folder for map.pgm, map.yaml, trajectory.txt (default: .)\n"
    "  --particles N       number of particles (gmapping's 'particles', default 30)\n"
    "  --param NAME=VALUE  any gmapping option by its gmapping name (e.g. linearUpdate=0.5)\n"
    "  --odometry-between  readings between processed scans take the processed pose moved by\n"
    "                      odometry (gmapping's output) instead of being matched against the\n"
    "                      final map\n"
    "  --quiet             no progress on stderr\n";

[[noreturn]] void UsageError(const std::string& what) {
  std::cerr << "slam_offline: " << what << "\n" << kUsage;
  std::exit(2);
}

struct Args {
  std::string log;
  std::string bag;
  minibot3d_slam::BagLogOptions bag_options;
  std::string out = ".";
  bool quiet = false;
  bool localize = true;
  GmappingOptions options;
};

Args ParseArgs(int argc, char** argv) {
  Args a;
  std::vector<std::pair<std::string, std::string>> params, file_params;
  std::string base_frame, odom_frame;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    std::string value;
    bool inline_value = false;
    const auto eq = arg.find('=');
    if (arg.rfind("--", 0) == 0 && eq != std::string::npos) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
      inline_value = true;
    }
    auto next = [&]() -> std::string {
      if (inline_value) return value;
      if (i + 1 >= argc) UsageError("option " + arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      std::exit(0);
    } else if (arg == "--log") {
      a.log = next();
    } else if (arg == "--bag") {
      a.bag = next();
    } else if (arg == "--scan-topic") {
      a.bag_options.scan_topic = next();
    } else if (arg == "--odom-topic") {
      a.bag_options.odom_topic = next();
    } else if (arg == "--base-frame") {
      base_frame = next();
    } else if (arg == "--odom-frame") {
      odom_frame = next();
    } else if (arg == "--param-file") {
      // slam_gmapping's own (non-filter) parameters: frames are used for bags, the rest ignored.
      const std::string file = next();
      try {
        const YAML::Node root = YAML::LoadFile(file);
        if (!root.IsMap()) UsageError(file + ": not a YAML mapping of parameters");
        for (const auto& kv : root) {
          const std::string name = kv.first.as<std::string>();
          const std::string value = kv.second.as<std::string>();
          if (name == "base_frame") {
            if (base_frame.empty()) base_frame = value;
          } else if (name == "odom_frame") {
            if (odom_frame.empty()) odom_frame = value;
          } else if (name == "map_frame" || name == "map_update_interval" ||
                     name == "transform_publish_period" || name == "throttle_scans" ||
                     name == "tf_delay") {
            continue;
          } else {
            file_params.emplace_back(name, value);
          }
        }
      } catch (const YAML::Exception& e) {
        UsageError("--param-file " + file + ": " + e.what());
      }
    } else if (arg == "--out") {
      a.out = next();
    } else if (arg == "--particles") {
      params.emplace_back("particles", next());
    } else if (arg == "--param") {
      const std::string nv = next();
      const auto p = nv.find('=');
      if (p == std::string::npos || p == 0) UsageError("--param expects NAME=VALUE, got '" + nv + "'");
      params.emplace_back(nv.substr(0, p), nv.substr(p + 1));
    } else if (arg == "--odometry-between") {
      if (inline_value) UsageError("option --odometry-between takes no value");
      a.localize = false;
    } else if (arg == "--quiet") {
      if (inline_value) UsageError("option --quiet takes no value");
      a.quiet = true;
    } else {
      UsageError("unknown option '" + std::string(argv[i]) + "'");
    }
  }
  if (a.log.empty() == a.bag.empty()) UsageError("give exactly one of --log FILE and --bag FILE");
  if (!base_frame.empty()) a.bag_options.base_frame = base_frame;
  if (!odom_frame.empty()) a.bag_options.odom_frame = odom_frame;
  // The file first, so --param and --particles on the command line override it.
  params.insert(params.begin(), file_params.begin(), file_params.end());
  for (const auto& [name, value] : params) {
    try {
      minibot3d_slam::SetOption(&a.options, name, value);
    } catch (const std::invalid_argument& e) {
      UsageError(std::string("bad --param: ") + e.what());
    }
  }
  try {
    minibot3d_slam::ValidateOptions(a.options);
  } catch (const std::invalid_argument& e) {
    UsageError(e.what());
  }
  return a;
}

// Crops the map to its observed cells (plus a small margin) so the image is not mostly unknown.
GridMap CropToKnown(const GridMap& m) {
  int x0 = m.width, y0 = m.height, x1 = -1, y1 = -1;
  for (int y = 0; y < m.height; ++y) {
    for (int x = 0; x < m.width; ++x) {
      if (m.data[static_cast<std::size_t>(y) * m.width + x] == -1) continue;
      x0 = std::min(x0, x);
      x1 = std::max(x1, x);
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
    }
  }
  if (x1 < 0) return m;
  constexpr int kMargin = 10;
  x0 = std::max(0, x0 - kMargin);
  y0 = std::max(0, y0 - kMargin);
  x1 = std::min(m.width - 1, x1 + kMargin);
  y1 = std::min(m.height - 1, y1 + kMargin);
  GridMap c = m;
  c.width = x1 - x0 + 1;
  c.height = y1 - y0 + 1;
  c.origin_x = m.origin_x + x0 * m.resolution;
  c.origin_y = m.origin_y + y0 * m.resolution;
  c.data.assign(static_cast<std::size_t>(c.width) * c.height, -1);
  for (int y = 0; y < c.height; ++y) {
    const auto* src = &m.data[static_cast<std::size_t>(y + y0) * m.width + x0];
    std::copy(src, src + c.width, &c.data[static_cast<std::size_t>(y) * c.width]);
  }
  return c;
}

double PeakMemoryMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

}  // namespace

int main(int argc, char** argv) {
  const Args args = ParseArgs(argc, argv);
  const auto start = std::chrono::steady_clock::now();
  auto wall = [&]() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };

  minibot3d_slam::CarmenLog log;
  try {
    log = args.bag.empty() ? minibot3d_slam::ReadCarmenLog(args.log)
                           : minibot3d_slam::ReadBagLog(args.bag, args.bag_options);
  } catch (const std::exception& e) {
    std::cerr << "slam_offline: " << e.what() << "\n";
    return 1;
  }
  if (!args.quiet) {
    for (const std::string& w : log.warnings) std::cerr << "slam_offline: warning: " << w << "\n";
  }
  std::error_code ec;
  std::filesystem::create_directories(args.out, ec);
  if (ec) {
    std::cerr << "slam_offline: cannot create output folder " << args.out << ": " << ec.message() << "\n";
    return 1;
  }

  std::signal(SIGINT, OnSigint);
  minibot3d_slam::RbpfSlam slam(args.options);
  const std::size_t n = log.scans.size();
  std::vector<int> processed_index(n, -1);  // index into the best trajectory, or -1
  std::size_t fed = 0;
  int processed = 0;
  std::size_t peak_map_bytes = 0;  // map cells of all particles, sampled every 10 processed scans
  double last_report = 0.0;
  for (; fed < n && !g_interrupted; ++fed) {
    const minibot3d_slam::LogScan& s = log.scans[fed];
    if (slam.AddScan(s.scan, s.odom)) {
      processed_index[fed] = processed++;
      if (processed % 10 == 0) peak_map_bytes = std::max(peak_map_bytes, slam.MapMemoryBytes());
    }
    if (!args.quiet && (wall() - last_report >= 1.0 || fed + 1 == n)) {
      last_report = wall();
      std::fprintf(stderr, "\rslam_offline: %5.1f%%  scans %zu/%zu  processed %d  %.0f scans/s   ",
                   100.0 * static_cast<double>(fed + 1) / static_cast<double>(n), fed + 1, n, processed,
                   static_cast<double>(fed + 1) / std::max(wall(), 1e-9));
    }
  }
  if (!args.quiet) std::fprintf(stderr, "\n");
  if (g_interrupted) {
    std::cerr << "slam_offline: interrupted after " << fed << " of " << n << " scans; writing what was processed\n";
  }

  slam.FinishLoops();
  // Trajectory: processed readings take the best particle's poses; the others the previous
  // processed pose moved by the odometry increment.
  const std::vector<minibot3d_slam::StampedPose> best = slam.BestTrajectory();
  const std::string traj_path = args.out + "/trajectory.txt";
  const std::string traj_tmp = traj_path + ".tmp";
  std::FILE* out = std::fopen(traj_tmp.c_str(), "w");
  if (out == nullptr) {
    std::cerr << "slam_offline: cannot write " << traj_tmp << ": " << std::strerror(errno) << "\n";
    return 1;
  }
  // The pose of every reading: processed ones from the trajectory; the others first moved from
  // the last processed one by odometry, then (unless --odometry-between) matched against the final
  // map — independent matches against a map no longer changing, so on two threads.
  std::vector<Pose2> poses(fed);
  std::vector<std::size_t> to_localize;
  std::size_t anchor = 0;
  for (std::size_t i = 0; i < fed; ++i) {
    if (processed_index[i] >= 0) anchor = i;
    const int k = processed_index[anchor];
    if (k < 0 || static_cast<std::size_t>(k) >= best.size()) continue;  // cannot happen: scan 0 is processed
    poses[i] = minibot3d_slam::Compose(best[static_cast<std::size_t>(k)].pose,
                                       minibot3d_slam::Between(log.scans[i].odom, log.scans[anchor].odom));
    if (args.localize && i != anchor) to_localize.push_back(i);
  }
  {
    constexpr int kThreads = 2;
    std::vector<std::thread> workers;
    for (int t = 0; t < kThreads; ++t) {
      workers.emplace_back([&, t]() {
        for (std::size_t j = static_cast<std::size_t>(t); j < to_localize.size(); j += kThreads) {
          const std::size_t i = to_localize[j];
          poses[i] = slam.Localize(log.scans[i].scan, poses[i]);
        }
      });
    }
    for (std::thread& w : workers) w.join();
  }
  for (std::size_t i = 0; i < fed; ++i) {
    std::fprintf(out, "%.6f %.6f %.6f %.6f\n", log.scans[i].timestamp, poses[i].x, poses[i].y, poses[i].theta);
  }
  if (std::fclose(out) != 0 || std::rename(traj_tmp.c_str(), traj_path.c_str()) != 0) {
    std::cerr << "slam_offline: cannot write " << traj_path << ": " << std::strerror(errno) << "\n";
    return 1;
  }
  try {
    const minibot3d_slam::GridMap map = CropToKnown(slam.Map());
    minibot3d_map_io::SaveMap(map, args.out + "/map", minibot3d_slam::SlamMapSaveOptions(map));
  } catch (const std::exception& e) {
    std::cerr << "slam_offline: " << e.what() << "\n";
    return 1;
  }
  std::size_t log_bytes = 0;  // the log held in memory (for the memory figures)
  for (const auto& s : log.scans) {
    log_bytes += sizeof(s) + (s.scan.ranges.capacity() + s.scan.angles.capacity()) * sizeof(double);
  }
  const double log_s = fed > 0 ? log.scans[fed - 1].timestamp - log.scans[0].timestamp : 0.0;
  std::printf("scans %zu processed %d wall_s %.2f log_s %.1f peak_mem_mb %.1f loop_closures %d loop_constraints %d "
              "map_peak_mb %.1f log_mb %.1f loop_scans_mb %.1f\n",
              fed, processed, wall(), log_s, PeakMemoryMb(), slam.loop_closures(), slam.loop_constraints(),
              static_cast<double>(peak_map_bytes) / 1048576.0, static_cast<double>(log_bytes) / 1048576.0,
              static_cast<double>(slam.LoopScanBytes()) / 1048576.0);
  return g_interrupted ? 130 : 0;
}
