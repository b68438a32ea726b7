// slam_offline: runs the RBPF SLAM core (rbpf_slam.h) on a CARMEN log or a ROS bag without a
// roscore and writes the best particle's map (map_server format) and trajectory.
//
//   slam_offline --log FILE | --bag FILE [--scan-topic /scan] [--odom-topic T] [--base-frame F]
//                [--odom-frame F]  [--out DIR] [--particles N] [--param-file YAML]
//                [--param NAME=VALUE ...] [--odometry-between] [--quiet]
//
// DIR/trajectory.txt has one line "timestamp x y theta" for every laser reading fed to the filter:
// the final best particle's pose at processed readings; for the readings in between, the pose at
// the previous processed reading composed with the odometry increment since it, with the gap
// between where that odometry puts the next processed reading and where the filter put it
// spread over them by how far the odometry had moved (none after the last processed reading),
// then (unless --odometry-between) matched against the final map (RbpfSlam::Localize). Timestamps
// are the log's ipc_timestamp. SIGINT stops the run early; what was processed is still written.
//
// The log is streamed (log_reader.h), twice: the filter's pass keeps one bit per reading
// (processed or not) and the odometry of each processed one, and the trajectory's pass reads the
// log again, so memory does not grow with the log's length beyond that bit and the filter's own
// per-processed-scan state.
#include <sys/resource.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "minibot3d_slam/bag_log.h"
#include "minibot3d_slam/between_processed.h"
#include "minibot3d_slam/carmen_log.h"
#include "minibot3d_slam/gmapping_options.h"
#include "minibot3d_slam/log_reader.h"
#include "minibot3d_slam/map_files.h"
#include "minibot3d_slam/node_options.h"
#include "minibot3d_slam/rbpf_slam.h"
#include "parallel_for.h"

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
    "  --odometry-between  readings between processed scans take the odometry between the\n"
    "                      processed poses around them instead of being matched against the\n"
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
      // The slam_gmapping node's own parameters (node_options.h): its frames are used for bags,
      // the rest ignored.
      const std::string file = next();
      try {
        const YAML::Node root = YAML::LoadFile(file);
        if (!root.IsMap()) UsageError(file + ": not a YAML mapping of parameters");
        for (const auto& kv : root) {
          const std::string name = kv.first.as<std::string>();
          const std::string value = kv.second.as<std::string>();
          if (!minibot3d_slam::SlamGmappingNodeOptionTable().Has(name)) {
            file_params.emplace_back(name, value);
          } else if (name == "base_frame" && base_frame.empty()) {
            base_frame = value;
          } else if (name == "odom_frame" && odom_frame.empty()) {
            odom_frame = value;
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

// Writes each warning the reader has added since `*shown` of them were written.
void ShowWarnings(const minibot3d_slam::LogReader& reader, bool quiet, std::size_t* shown) {
  const std::vector<std::string>& w = reader.report().warnings;
  for (; *shown < w.size(); ++*shown) {
    if (!quiet) std::cerr << "slam_offline: warning: " << w[*shown] << "\n";
  }
}

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Opens the log or the bag; nullptr (having said why) when it cannot be read.
std::unique_ptr<minibot3d_slam::LogReader> OpenLog(const Args& args) {
  try {
    return args.bag.empty() ? minibot3d_slam::OpenCarmenLog(args.log)
                            : minibot3d_slam::OpenBagLog(args.bag, args.bag_options);
  } catch (const std::exception& e) {
    std::cerr << "slam_offline: " << e.what() << "\n";
    return nullptr;
  }
}

bool CreateOutputFolder(const std::string& out) {
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) {
    std::cerr << "slam_offline: cannot create output folder " << out << ": " << ec.message() << "\n";
    return false;
  }
  return true;
}

// What the filter's pass keeps of the log: one bit per reading (processed or not) and the
// odometry of each processed one; the readings themselves are read again for the trajectory.
struct FilterPass {
  std::vector<bool> processed_flags;
  std::vector<Pose2> processed_odom;  // the odometry at each processed reading
  std::size_t fed = 0;
  int processed = 0;
  std::size_t peak_map_bytes = 0;  // map cells of all particles, sampled every 10 processed scans
  double first_time = 0.0, last_time = 0.0;
};

// Pass 1: the filter, one reading at a time, until the log ends or SIGINT. Throws what the
// reader or the filter throws.
FilterPass RunFilter(minibot3d_slam::LogReader* reader, minibot3d_slam::RbpfSlam* slam, bool quiet,
                     std::chrono::steady_clock::time_point start) {
  FilterPass pass;
  double last_report = 0.0;
  minibot3d_slam::LogScan s;
  while (!g_interrupted && reader->Next(&s)) {
    if (pass.fed == 0) pass.first_time = s.timestamp;
    pass.last_time = s.timestamp;
    const bool used = slam->AddScan(s.scan, s.odom);
    pass.processed_flags.push_back(used);
    if (used) pass.processed_odom.push_back(s.odom);
    ++pass.fed;
    if (used && ++pass.processed % 10 == 0) {
      pass.peak_map_bytes = std::max(pass.peak_map_bytes, slam->MapMemoryBytes());
    }
    if (!quiet && SecondsSince(start) - last_report >= 1.0) {
      last_report = SecondsSince(start);
      std::fprintf(stderr, "\rslam_offline: scans %zu  processed %d  log %.0f s  %.0f scans/s   ", pass.fed,
                   pass.processed, pass.last_time - pass.first_time,
                   static_cast<double>(pass.fed) / std::max(SecondsSince(start), 1e-9));
    }
  }
  if (!quiet) std::fprintf(stderr, "\rslam_offline: scans %zu  processed %d  log %.0f s\n", pass.fed,
                           pass.processed, pass.last_time - pass.first_time);
  return pass;
}

// Readings of the trajectory's pass, a batch at a time.
struct Batch {
  std::vector<minibot3d_slam::LogScan> readings;
  std::vector<Pose2> poses;
  std::vector<std::size_t> to_localize;  // indices into readings

  std::size_t Bytes() const {
    std::size_t bytes = 0;
    for (const auto& b : readings) {
      bytes += sizeof(b) + (b.scan.ranges.capacity() + b.scan.angles.capacity()) * sizeof(double);
    }
    return bytes;
  }
};

// Matches the batch's readings to localize against the final map — independent matches against a
// map no longer changing, so on `threads` threads — and writes every reading's pose.
void FlushBatch(const minibot3d_slam::RbpfSlam& slam, int threads, std::FILE* out, Batch* batch) {
  minibot3d_slam::ParallelFor(batch->to_localize.size(), threads, [&](std::size_t j) {
    const std::size_t i = batch->to_localize[j];
    batch->poses[i] = slam.Localize(batch->readings[i].scan, batch->poses[i]);
  });
  for (std::size_t i = 0; i < batch->readings.size(); ++i) {
    std::fprintf(out, "%.6f %.6f %.6f %.6f\n", batch->readings[i].timestamp, batch->poses[i].x,
                 batch->poses[i].y, batch->poses[i].yaw);
  }
  batch->readings.clear();
  batch->poses.clear();
  batch->to_localize.clear();
}

// Pass 2: processed readings take the best particle's poses `best`; the others are first placed
// by odometry between the processed ones around them, then (with `localize`) matched against the
// final map. Throws std::runtime_error when the log no longer matches pass 1.
void PlaceReadings(minibot3d_slam::LogReader* reader, const minibot3d_slam::RbpfSlam& slam,
                   const std::vector<minibot3d_slam::StampedPose>& best, const FilterPass& pass,
                   bool localize, int threads, std::FILE* out, std::size_t* peak_batch_bytes) {
  constexpr std::size_t kBatch = 256;
  Batch batch;
  batch.readings.reserve(kBatch);
  Pose2 anchor_pose, anchor_odom;  // best pose and odometry at the last processed reading
  std::size_t k = 0;               // processed readings so far (index into best)
  reader->Rewind();
  for (std::size_t i = 0; i < pass.fed; ++i) {
    batch.readings.emplace_back();
    if (!reader->Next(&batch.readings.back())) {
      throw std::runtime_error("the log ended after " + std::to_string(i) + " readings in the second pass, " +
                               std::to_string(pass.fed) + " in the first");
    }
    const minibot3d_slam::LogScan& r = batch.readings.back();
    if (pass.processed_flags[i]) {
      if (k >= best.size()) throw std::runtime_error("more processed readings than trajectory poses");
      anchor_pose = best[k++].pose;
      anchor_odom = r.odom;
    } else if (localize) {
      batch.to_localize.push_back(batch.readings.size() - 1);
    }
    const bool next = k < best.size();
    batch.poses.push_back(pass.processed_flags[i]
                              ? anchor_pose
                              : minibot3d_slam::PoseBetweenProcessed(anchor_pose, anchor_odom, r.odom, next ? &best[k].pose : nullptr,
                                                 next ? &pass.processed_odom[k] : nullptr));
    if (batch.readings.size() == kBatch) {
      *peak_batch_bytes = std::max(*peak_batch_bytes, batch.Bytes());
      FlushBatch(slam, threads, out, &batch);
    }
  }
  FlushBatch(slam, threads, out, &batch);
}

// Writes OUT/trajectory.txt (through a temporary file, renamed when complete). Returns false,
// having said why, when it could not.
bool WriteTrajectory(minibot3d_slam::LogReader* reader, const minibot3d_slam::RbpfSlam& slam,
                     const FilterPass& pass, const Args& args, std::size_t* peak_batch_bytes) {
  const std::vector<minibot3d_slam::StampedPose> best = slam.BestTrajectory();
  if (best.size() != pass.processed_odom.size()) {
    std::cerr << "slam_offline: " << best.size() << " trajectory poses for " << pass.processed_odom.size()
              << " processed readings\n";
    return false;
  }
  const std::string traj_path = args.out + "/trajectory.txt";
  const std::string traj_tmp = traj_path + ".tmp";
  std::FILE* out = std::fopen(traj_tmp.c_str(), "w");
  if (out == nullptr) {
    std::cerr << "slam_offline: cannot write " << traj_tmp << ": " << std::strerror(errno) << "\n";
    return false;
  }
  try {
    PlaceReadings(reader, slam, best, pass, args.localize, minibot3d_slam::ResolveThreads(args.options.threads),
                  out, peak_batch_bytes);
  } catch (const std::exception& e) {
    std::fclose(out);
    std::remove(traj_tmp.c_str());
    std::cerr << "slam_offline: " << e.what() << "\n";
    return false;
  }
  if (std::fclose(out) != 0 || std::rename(traj_tmp.c_str(), traj_path.c_str()) != 0) {
    std::cerr << "slam_offline: cannot write " << traj_path << ": " << std::strerror(errno) << "\n";
    return false;
  }
  return true;
}

bool SaveCroppedMap(const minibot3d_slam::RbpfSlam& slam, const std::string& out) {
  try {
    const minibot3d_slam::GridMap map = CropToKnown(slam.Map());
    minibot3d_map_io::SaveMap(map, out + "/map", minibot3d_slam::SlamMapSaveOptions(map));
  } catch (const std::exception& e) {
    std::cerr << "slam_offline: " << e.what() << "\n";
    return false;
  }
  return true;
}

void PrintSummary(const FilterPass& pass, const minibot3d_slam::RbpfSlam& slam, std::size_t peak_batch_bytes,
                  double wall_s) {
  // What the run held because of the log: one bit per reading and the second pass's batch.
  const std::size_t log_bytes = pass.processed_flags.capacity() / 8 + peak_batch_bytes;
  std::printf("scans %zu processed %d wall_s %.2f log_s %.1f peak_mem_mb %.1f loop_closures %d loop_constraints %d "
              "map_peak_mb %.1f log_mb %.1f loop_scans_mb %.1f\n",
              pass.fed, pass.processed, wall_s, pass.last_time - pass.first_time, PeakMemoryMb(),
              slam.loop_closures(), slam.loop_constraints(), static_cast<double>(pass.peak_map_bytes) / 1048576.0,
              static_cast<double>(log_bytes) / 1048576.0, static_cast<double>(slam.LoopScanBytes()) / 1048576.0);
}

}  // namespace

int main(int argc, char** argv) {
  const Args args = ParseArgs(argc, argv);
  const auto start = std::chrono::steady_clock::now();
  const std::unique_ptr<minibot3d_slam::LogReader> reader = OpenLog(args);
  if (reader == nullptr) return 1;
  std::size_t warnings_shown = 0;
  ShowWarnings(*reader, args.quiet, &warnings_shown);
  if (!CreateOutputFolder(args.out)) return 1;

  std::signal(SIGINT, OnSigint);
  minibot3d_slam::RbpfSlam slam(args.options);
  FilterPass pass;
  try {
    pass = RunFilter(reader.get(), &slam, args.quiet, start);
  } catch (const std::exception& e) {
    std::cerr << "\nslam_offline: " << e.what() << "\n";
    return 1;
  }
  ShowWarnings(*reader, args.quiet, &warnings_shown);
  if (g_interrupted) {
    std::cerr << "slam_offline: interrupted after " << pass.fed << " scans; writing what was processed\n";
  }
  if (pass.fed == 0) {
    std::cerr << "slam_offline: no scan could be used\n";
    return 1;
  }

  slam.FinishLoops();
  std::size_t peak_batch_bytes = 0;
  if (!WriteTrajectory(reader.get(), slam, pass, args, &peak_batch_bytes)) return 1;
  if (!SaveCroppedMap(slam, args.out)) return 1;
  PrintSummary(pass, slam, peak_batch_bytes, SecondsSince(start));
  return g_interrupted ? 130 : 0;
}
