// CARMEN log reader (carmen_log.h).
//
// Formats (one message per line, '#' starts a comment line):
//   FLASER n r_1..r_n x y θ odom_x odom_y odom_θ ipc_timestamp ipc_hostname logger_timestamp
//     n beams from −90° on, at the PARAM laser_front_laser_resolution (degrees) when given, else as
//     SICK scanners log them: 181/361 beams cover 180° end to end (step π/(n−1)), 180/360 beams
//     drop the last one (step π/n) — in general π/(n−1) for odd n, π/n for even n (as gmapping).
//   ROBOTLASER1 type start_angle fov angular_res max_range accuracy remission_mode n r_1..r_n
//     m rem_1..rem_m laser_x laser_y laser_θ robot_x robot_y robot_θ tv rv forward_safety
//     side_safety turn_axis ipc_timestamp ipc_hostname logger_timestamp
//   PARAM name value ...   (robot_front_laser_max, robot_frontlaser_offset,
//                           laser_front_laser_resolution are used)
// The odometry is odom_* (FLASER) or robot_* (ROBOTLASER1). The sensor's mounting is the laser
// pose relative to it when that is one rigid offset throughout the log; when the relative pose
// varies (the laser pose fields then hold corrected poses, not a mounting) or is zero, the mounting
// is robot_frontlaser_offset metres ahead of the base.
//
// Streaming (log_reader.h): OpenCarmenLog reads the file once for the facts that need the whole log
// — the no-return value and the mounting — keeping 24 bytes per laser line (its laser pose relative
// to the odometry, for the median; freed when Open returns) and the counts of distinct readings in
// the upper half of the range seen so far (pruned whenever the maximum rises, so exactly the counts
// a whole-log histogram would hold). Next() then parses the file again, one line per call.
//
// No-return detection: laser loggers write a fixed saturation value for beams without echo (81.83
// in the Intel log, 50.0 or 81.9 elsewhere). Among the readings in the upper half of the observed
// range, the most frequent value is taken as that saturation value when it dominates (≥ 10 and
// ≥ 0.05 % of all readings, ≥ 5× the next most frequent value there); readings at or above it, at or
// above robot_front_laser_max, or at or above a ROBOTLASER1's max_range become +inf.
#include "minibot3d_slam/carmen_log.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string_view>
#include <unordered_map>
#include <utility>

namespace minibot3d_slam {

namespace {

constexpr std::size_t kMaxWarnings = 100;

struct RawScan {
  LogScan log;
  Pose2 laser_pose;  // as written in the log (world frame)
  bool has_max = false;
  double max_range = 0.0;
};

// Fields are views into the line (no copy per field: a log has millions of readings, parsed twice).
using Fields = std::vector<std::string_view>;

void SplitFields(const std::string& line, Fields* out) {
  out->clear();
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (i < n) {
    while (i < n && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i >= n) break;
    std::size_t j = i;
    while (j < n && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
    out->emplace_back(line.data() + i, j - i);
    i = j;
  }
}

// strtod's accepted syntax and rounding; std::from_chars (the same correctly rounded value) first
// because it is several times faster, strtod for what from_chars does not take (a leading '+').
bool ToDouble(std::string_view s, double* v) {
  if (s.empty()) return false;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), *v);
  if (ec == std::errc() && ptr == s.data() + s.size()) return !std::isnan(*v);
  const std::string copy(s);
  char* end = nullptr;
  errno = 0;
  *v = std::strtod(copy.c_str(), &end);
  return end == copy.c_str() + copy.size() && errno != ERANGE && !std::isnan(*v);
}

bool ToCount(std::string_view s, int* v) {
  if (s.empty()) return false;
  const std::string copy(s);
  char* end = nullptr;
  errno = 0;
  const long x = std::strtol(copy.c_str(), &end, 10);
  if (end != copy.c_str() + copy.size() || errno == ERANGE || x < 0 || x > 1000000) return false;
  *v = static_cast<int>(x);
  return true;
}

class LineError : public std::exception {
 public:
  explicit LineError(std::string why) : why_(std::move(why)) {}
  const char* what() const noexcept override { return why_.c_str(); }

 private:
  std::string why_;
};

// Reads field `i` as a number or throws LineError naming it.
double Number(const Fields& f, std::size_t i, const char* what) {
  if (i >= f.size()) throw LineError(std::string("truncated: missing ") + what);
  double v;
  if (!ToDouble(f[i], &v)) throw LineError(std::string("not a number for ") + what + ": '" + std::string(f[i]) + "'");
  return v;
}

int Count(const Fields& f, std::size_t i, const char* what) {
  if (i >= f.size()) throw LineError(std::string("truncated: missing ") + what);
  int v;
  if (!ToCount(f[i], &v)) throw LineError(std::string("bad ") + what + ": '" + std::string(f[i]) + "'");
  return v;
}

std::vector<double> Readings(const Fields& f, std::size_t first, int n) {
  if (first + static_cast<std::size_t>(n) > f.size()) {
    throw LineError("fewer readings than the declared " + std::to_string(n));
  }
  std::vector<double> r(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) r[static_cast<std::size_t>(i)] = Number(f, first + i, "a range reading");
  return r;
}

RawScan ParseFlaser(const Fields& f, double resolution_deg) {
  RawScan s;
  const int n = Count(f, 1, "number of readings");
  if (n < 1) throw LineError("no readings");
  s.log.scan.ranges = Readings(f, 2, n);
  std::size_t k = 2 + static_cast<std::size_t>(n);
  if (f.size() < k + 7) throw LineError("truncated after the readings (fewer fields than the poses and timestamp need, or fewer readings than declared)");
  s.laser_pose = Pose2{Number(f, k, "x"), Number(f, k + 1, "y"), Number(f, k + 2, "theta")};
  s.log.odom = Pose2{Number(f, k + 3, "odom_x"), Number(f, k + 4, "odom_y"), Number(f, k + 5, "odom_theta")};
  s.log.timestamp = Number(f, k + 6, "ipc_timestamp");
  s.log.scan.angles.resize(static_cast<std::size_t>(n));
  double step = n % 2 == 1 ? M_PI / std::max(n - 1, 1) : M_PI / n;
  if (resolution_deg > 0.0) step = resolution_deg * M_PI / 180.0;
  for (int i = 0; i < n; ++i) s.log.scan.angles[static_cast<std::size_t>(i)] = -M_PI / 2 + i * step;
  return s;
}

RawScan ParseRobotLaser(const Fields& f) {
  RawScan s;
  const double start = Number(f, 2, "start_angle");
  Number(f, 3, "field_of_view");
  const double res = Number(f, 4, "angular_resolution");
  s.max_range = Number(f, 5, "maximum_range");
  s.has_max = s.max_range > 0.0;
  Number(f, 6, "accuracy");
  Number(f, 7, "remission_mode");
  const int n = Count(f, 8, "number of readings");
  if (n < 1) throw LineError("no readings");
  s.log.scan.ranges = Readings(f, 9, n);
  std::size_t k = 9 + static_cast<std::size_t>(n);
  const int m = Count(f, k, "number of remissions");
  k += 1 + static_cast<std::size_t>(m);
  if (f.size() < k + 12) throw LineError("truncated after the readings (fewer fields than the poses and timestamp need, or fewer readings than declared)");
  s.laser_pose = Pose2{Number(f, k, "laser_x"), Number(f, k + 1, "laser_y"), Number(f, k + 2, "laser_theta")};
  s.log.odom = Pose2{Number(f, k + 3, "robot_x"), Number(f, k + 4, "robot_y"), Number(f, k + 5, "robot_theta")};
  s.log.timestamp = Number(f, k + 11, "ipc_timestamp");
  s.log.scan.angles.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) s.log.scan.angles[static_cast<std::size_t>(i)] = start + i * res;
  return s;
}

// A laser_front_laser_resolution PARAM's value (a bad one is refused and the previous one kept).
double Resolution(const Fields& f) {
  const double v = Number(f, 2, "laser_front_laser_resolution");
  if (v <= 0.0) throw LineError("laser_front_laser_resolution must be > 0");
  return v;
}

// Counts of the finite readings at or above half the largest one seen so far (see file comment).
class SaturationHistogram {
 public:
  void Add(double r) {
    ++total_;
    if (!std::isfinite(r)) return;
    if (r > top_) {
      top_ = r;
      for (auto it = counts_.begin(); it != counts_.end();) {
        it = it->first < 0.5 * top_ ? counts_.erase(it) : std::next(it);
      }
    }
    if (r >= 0.5 * top_) ++counts_[r];
  }

  // The saturation value written for no-returns, or +inf when the log has none: the most frequent
  // value in the upper half when it dominates (ties: the larger value).
  double Saturation() const {
    if (top_ <= 0.0) return std::numeric_limits<double>::infinity();
    double best = 0.0;
    std::size_t best_n = 0, second_n = 0;
    for (const auto& [value, n] : counts_) {
      if (n > best_n || (n == best_n && value > best)) {
        second_n = best_n;
        best_n = n;
        best = value;
      } else {
        second_n = std::max(second_n, n);
      }
    }
    const double needed = std::max(10.0, 5e-4 * static_cast<double>(total_));
    if (static_cast<double>(best_n) >= needed && best_n >= 5 * second_n) return best;
    return std::numeric_limits<double>::infinity();
  }

 private:
  double top_ = 0.0;
  std::size_t total_ = 0;
  std::unordered_map<double, std::size_t> counts_;
};

class CarmenLogReader : public LogReader {
 public:
  explicit CarmenLogReader(const std::string& path) : path_(path) {
    Open();
    Survey();
    Rewind();
  }

  bool Next(LogScan* out) override {
    std::string line;
    while (std::getline(in_, line)) {
      ++line_;
      SplitFields(line, &fields_);
      if (fields_.empty() || fields_[0][0] == '#') continue;
      const std::string type(fields_[0]);
      try {
        if (type == "FLASER" || type == "ROBOTLASER1") {
          RawScan s = type == "FLASER" ? ParseFlaser(fields_, resolution_) : ParseRobotLaser(fields_);
          if (++yielded_ > expected_) Changed();
          Finish(&s);
          *out = std::move(s.log);
          return true;
        }
        if (type == "PARAM" && fields_.size() >= 3 && fields_[1] == "laser_front_laser_resolution") {
          resolution_ = Resolution(fields_);
        }
      } catch (const LineError&) {
        // Reported (with its line) by Survey; skipped again.
      }
    }
    if (in_.bad()) {
      throw std::runtime_error("error reading CARMEN log " + path_ + " at line " + std::to_string(line_));
    }
    if (yielded_ != expected_) Changed();
    return false;
  }

  void Rewind() override {
    in_.clear();
    in_.seekg(0);
    if (!in_) throw std::runtime_error("cannot rewind CARMEN log " + path_);
    line_ = 0;
    yielded_ = 0;
    resolution_ = 0.0;
  }

 private:
  void Open() {
    in_.open(path_);
    if (!in_) throw std::runtime_error("cannot read CARMEN log " + path_ + ": " + std::strerror(errno));
  }

  [[noreturn]] void Changed() const {
    throw std::runtime_error(path_ + ":" + std::to_string(line_) +
                             ": the log changed since it was opened (it held " + std::to_string(expected_) +
                             " laser messages then)");
  }

  // The first pass: PARAMs, the no-return value, the mounting, the malformed lines.
  void Survey() {
    std::vector<Pose2> rel;  // laser pose relative to the odometry, per laser line
    SaturationHistogram histogram;
    double front_laser_resolution = 0.0;  // degrees; 0: from the beam count
    std::size_t dropped_warnings = 0;
    auto warn = [&](int line, const std::string& why) {
      if (report_.warnings.size() < kMaxWarnings) {
        report_.warnings.push_back(path_ + ":" + std::to_string(line) + ": " + why);
      } else {
        ++dropped_warnings;
      }
    };
    std::string line;
    while (std::getline(in_, line)) {
      ++report_.lines;
      SplitFields(line, &fields_);
      if (fields_.empty() || fields_[0][0] == '#') continue;
      const std::string type(fields_[0]);
      try {
        if (type == "FLASER" || type == "ROBOTLASER1") {
          const RawScan s = type == "FLASER" ? ParseFlaser(fields_, front_laser_resolution)
                                             : ParseRobotLaser(fields_);
          for (double r : s.log.scan.ranges) histogram.Add(r);
          rel.push_back(Between(s.log.odom, s.laser_pose));
        } else if (type == "PARAM" && fields_.size() >= 3 && fields_[1] == "robot_front_laser_max") {
          front_laser_max_ = Number(fields_, 2, "robot_front_laser_max");
        } else if (type == "PARAM" && fields_.size() >= 3 && fields_[1] == "laser_front_laser_resolution") {
          front_laser_resolution = Resolution(fields_);
        } else if (type == "PARAM" && fields_.size() >= 3 && fields_[1] == "robot_frontlaser_offset") {
          front_laser_offset_ = Number(fields_, 2, "robot_frontlaser_offset");
        } else {
          ++report_.skipped[type];
        }
      } catch (const LineError& e) {
        warn(report_.lines, type + " line skipped: " + e.what());
        ++report_.skipped[type];
      }
    }
    if (in_.bad()) {
      throw std::runtime_error("error reading CARMEN log " + path_ + " at line " + std::to_string(report_.lines));
    }
    if (dropped_warnings > 0) {
      report_.warnings.push_back(path_ + ": " + std::to_string(dropped_warnings) + " more malformed lines");
    }
    if (rel.empty()) {
      throw std::runtime_error("CARMEN log " + path_ + " holds no laser message (FLASER/ROBOTLASER1) in " +
                               std::to_string(report_.lines) + " lines" +
                               (report_.lines == 0 ? " (empty file)" : ""));
    }
    expected_ = rel.size();
    saturation_ = histogram.Saturation();

    // Sensor mounting: the laser pose relative to the odometry when it is one rigid offset.
    auto median = [&](auto get) {
      std::vector<double> v;
      v.reserve(rel.size());
      for (const Pose2& p : rel) v.push_back(get(p));
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    const Pose2 mount{median([](const Pose2& p) { return p.x; }), median([](const Pose2& p) { return p.y; }),
                      median([](const Pose2& p) { return p.yaw; })};
    bool rigid = true;
    for (const Pose2& p : rel) {
      if (std::hypot(p.x - mount.x, p.y - mount.y) > 0.02 ||
          std::fabs(NormalizeAngle(p.yaw - mount.yaw)) > 0.02) {
        rigid = false;
        break;
      }
    }
    const bool zero = std::hypot(mount.x, mount.y) < 1e-6 && std::fabs(mount.yaw) < 1e-6;
    sensor_in_base_ = Pose2{front_laser_offset_, 0.0, 0.0};
    if (rigid && !zero) sensor_in_base_ = mount;
    if (!rigid) {
      report_.warnings.push_back(path_ + ": the laser pose fields are not a fixed offset from the odometry; "
                                 "using robot_frontlaser_offset = " + std::to_string(front_laser_offset_) +
                                 " m as the sensor mounting");
    }
  }

  // No-returns to +inf, range limits and mounting: what the whole log decided.
  void Finish(RawScan* s) const {
    double limit = std::min(saturation_, front_laser_max_);
    if (s->has_max) limit = std::min(limit, s->max_range);
    for (double& r : s->log.scan.ranges) {
      if (!(r < limit)) r = std::numeric_limits<double>::infinity();
    }
    s->log.scan.time = s->log.timestamp;
    s->log.scan.range_min = 0.0;
    s->log.scan.range_max = limit;
    s->log.scan.sensor_in_base = sensor_in_base_;
  }

  std::string path_;
  std::ifstream in_;
  Fields fields_;
  // Whole-log facts (Survey).
  double front_laser_max_ = std::numeric_limits<double>::infinity();
  double front_laser_offset_ = 0.0;
  double saturation_ = std::numeric_limits<double>::infinity();
  Pose2 sensor_in_base_;
  std::size_t expected_ = 0;  // laser messages
  // Streaming state.
  int line_ = 0;
  std::size_t yielded_ = 0;
  double resolution_ = 0.0;  // laser_front_laser_resolution so far (degrees; 0: from the beam count)
};

}  // namespace

std::unique_ptr<LogReader> OpenCarmenLog(const std::string& path) {
  return std::make_unique<CarmenLogReader>(path);
}

CarmenLog ReadCarmenLog(const std::string& path) {
  std::unique_ptr<LogReader> reader = OpenCarmenLog(path);
  CarmenLog log;
  LogScan s;
  while (reader->Next(&s)) log.scans.push_back(std::move(s));
  log.skipped = reader->report().skipped;
  log.warnings = reader->report().warnings;
  log.lines = reader->report().lines;
  return log;
}

}  // namespace minibot3d_slam
