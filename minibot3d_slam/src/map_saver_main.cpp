// map_saver: writes the first nav_msgs/OccupancyGrid seen on `map` to NAME.pgm + NAME.yaml in
// map_server's format, as ROS map_server's map_saver does, then exits. Unlike it, it gives up
// after --timeout seconds of wall time with a message instead of waiting forever.
//
//   rosrun minibot3d_slam map_saver [-f NAME] [--occ 65] [--free 25] [--timeout 30] [map:=/topic]
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "minibot3d_ros/conversions.h"
#include "minibot3d_slam/map_files.h"
#include "minibot3d_slam/types.h"

namespace {

constexpr char kUsage[] =
    "Usage: map_saver [-f NAME] [--occ PERCENT] [--free PERCENT] [--timeout SECONDS] "
    "[map:=/topic]\n"
    "  Writes the first map received on 'map' to NAME.pgm and NAME.yaml (NAME defaults to\n"
    "  'map'). Cells >= --occ (default 65) are written occupied, cells in 0..--free (default 25)\n"
    "  free, others unknown. Gives up with exit code 1 after --timeout s (default 30) of wall\n"
    "  time without a map. Exit codes: 0 saved, 1 no map or write failed, 2 bad arguments.\n";

struct Options {
  std::string name = "map";
  int occupied_percent = 65;
  int free_percent = 25;
  double timeout_s = 30.0;
};

// Full-token integer / number parsing: "65x" and "" are errors, not 65 and 0.
bool ParseInt(const char* s, int* out) {
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  if (end == s || *end != '\0' || v < -1000000 || v > 1000000) return false;
  *out = static_cast<int>(v);
  return true;
}

bool ParseDouble(const char* s, double* out) {
  char* end = nullptr;
  const double v = std::strtod(s, &end);
  if (end == s || *end != '\0' || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

// Returns "" when the arguments are valid, else what is wrong with them.
std::string ParseArgs(int argc, char** argv, Options* options, bool* help) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      *help = true;
      return "";
    }
    const bool takes_value = arg == "-f" || arg == "--occ" || arg == "--free" || arg == "--timeout";
    if (!takes_value) return "unknown argument '" + arg + "'";
    if (i + 1 >= argc) return arg + " needs a value";
    const char* value = argv[++i];
    if (arg == "-f") {
      options->name = value;
      if (options->name.empty()) return "-f needs a non-empty map name";
    } else if (arg == "--occ") {
      if (!ParseInt(value, &options->occupied_percent) || options->occupied_percent < 1 ||
          options->occupied_percent > 100) {
        return std::string("--occ must be an integer in 1..100, got '") + value + "'";
      }
    } else if (arg == "--free") {
      if (!ParseInt(value, &options->free_percent) || options->free_percent < 0 ||
          options->free_percent > 100) {
        return std::string("--free must be an integer in 0..100, got '") + value + "'";
      }
    } else {
      if (!ParseDouble(value, &options->timeout_s) || options->timeout_s <= 0.0) {
        return std::string("--timeout must be a positive number of seconds, got '") + value + "'";
      }
    }
  }
  if (options->free_percent >= options->occupied_percent) {
    return "--free (" + std::to_string(options->free_percent) + ") must be below --occ (" +
           std::to_string(options->occupied_percent) + ")";
  }
  return "";
}

std::string Seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", s);
  return buf;
}

// OccupancyGrid's resolution is a float32: take the shortest decimal that is that float, so a
// map published at 0.05 is saved as 0.05 and not 0.05000000074505806.
double FloatToDouble(float f) {
  char buf[32];
  for (int precision = 1; precision <= 9; ++precision) {
    std::snprintf(buf, sizeof(buf), "%.*g", precision, static_cast<double>(f));
    if (std::strtof(buf, nullptr) == f) return std::strtod(buf, nullptr);
  }
  return static_cast<double>(f);
}

// The message's grid with the numbers the files should show: the float32 resolution as its
// shortest decimal, and the yaw without the last-bit noise of the yaw -> quaternion -> yaw round
// trip (snapped to 1e-12 rad), so a map served with yaw 0.1 is saved with 0.1 rather than
// 0.09999999999999999.
minibot3d_slam::GridMap ToGridMap(const nav_msgs::OccupancyGrid& msg) {
  minibot3d_slam::GridMap map = minibot3d_ros::GridFromMsg(msg);
  map.resolution = FloatToDouble(msg.info.resolution);
  map.origin_theta = std::round(map.origin_theta * 1e12) / 1e12;
  return map;
}

class MapSaver {
 public:
  explicit MapSaver(const Options& options) : options_(options) {
    ros::NodeHandle nh;
    sub_ = nh.subscribe("map", 1, &MapSaver::OnMap, this);
  }

  bool done() const { return done_; }
  bool ok() const { return ok_; }

 private:
  void OnMap(const nav_msgs::OccupancyGridConstPtr& msg) {
    if (done_) return;
    done_ = true;
    ROS_INFO("Received a %u x %u map @ %.3f m/cell from %s", msg->info.width, msg->info.height,
             msg->info.resolution, sub_.getTopic().c_str());
    try {
      const minibot3d_slam::GridMap map = ToGridMap(*msg);
      minibot3d_map_io::SaveMap(map, options_.name,
                                minibot3d_slam::SlamMapSaveOptions(map, options_.occupied_percent,
                                                                   options_.free_percent));
      ROS_INFO("Wrote %s.pgm and %s.yaml (occupied >= %d, free <= %d, others unknown)",
               options_.name.c_str(), options_.name.c_str(), options_.occupied_percent,
               options_.free_percent);
      ok_ = true;
    } catch (const minibot3d_map_io::MapIoError& e) {
      ROS_ERROR("%s", e.what());
    }
  }

  Options options_;
  ros::Subscriber sub_;
  bool done_ = false;
  bool ok_ = false;
};

}  // namespace

int main(int argc, char** argv) {
  // ros::init consumes the remapping arguments (map:=/other) and leaves ours in argv.
  ros::init(argc, argv, "map_saver", ros::init_options::AnonymousName);
  Options options;
  bool help = false;
  const std::string error = ParseArgs(argc, argv, &options, &help);
  if (help) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (!error.empty()) {
    std::fprintf(stderr, "map_saver: %s\n%s", error.c_str(), kUsage);
    return 2;
  }

  const std::string topic = ros::names::resolve("map");
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(options.timeout_s);
  // Without a master, subscribing would block forever retrying: check for it within the timeout.
  while (!ros::master::check()) {
    if (ros::WallTime::now() >= deadline) {
      std::fprintf(stderr,
                   "map_saver: no ROS master at %s within %s s — start roscore (and "
                   "slam_gmapping) first\n",
                   ros::master::getURI().c_str(), Seconds(options.timeout_s).c_str());
      return 1;
    }
    ros::WallDuration(0.1).sleep();
  }

  MapSaver saver(options);
  ROS_INFO("Waiting for a map on %s (up to %s s)", topic.c_str(),
           Seconds(options.timeout_s).c_str());
  while (ros::ok() && !saver.done() && ros::WallTime::now() < deadline) {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  if (!saver.done()) {
    if (!ros::ok()) return 1;  // interrupted (Ctrl-C): roscpp has said so
    std::fprintf(stderr,
                 "map_saver: no map received on %s within %s s — is slam_gmapping running?\n",
                 topic.c_str(), Seconds(options.timeout_s).c_str());
    return 1;
  }
  return saver.ok() ? 0 : 1;
}
