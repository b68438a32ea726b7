// Validation and by-name setting of the gmapping options (gmapping_options.h).
#include "minibot3d_slam/gmapping_options.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace minibot3d_slam {

namespace {

class Problems {
 public:
  template <class T>
  void Check(bool ok, const char* name, T value, const char* requirement) {
    if (ok) return;
    std::ostringstream s;
    s << name << " = " << value << " (must be " << requirement << ")";
    items_.push_back(s.str());
  }
  void ThrowIfAny() const {
    if (items_.empty()) return;
    std::string msg = "invalid gmapping options: ";
    for (std::size_t i = 0; i < items_.size(); ++i) msg += (i ? "; " : "") + items_[i];
    throw std::invalid_argument(msg);
  }

 private:
  std::vector<std::string> items_;
};

bool Finite(double v) { return std::isfinite(v); }

}  // namespace

void ValidateOptions(const GmappingOptions& o) {
  Problems p;
  p.Check(o.particles >= 1, "particles", o.particles, ">= 1");
  p.Check(o.resampleThreshold > 0.0 && o.resampleThreshold <= 1.0, "resampleThreshold",
          o.resampleThreshold, "in (0, 1]");
  p.Check(o.srr >= 0.0 && Finite(o.srr), "srr", o.srr, ">= 0");
  p.Check(o.srt >= 0.0 && Finite(o.srt), "srt", o.srt, ">= 0");
  p.Check(o.str >= 0.0 && Finite(o.str), "str", o.str, ">= 0");
  p.Check(o.stt >= 0.0 && Finite(o.stt), "stt", o.stt, ">= 0");
  p.Check(o.linearUpdate >= 0.0 && Finite(o.linearUpdate), "linearUpdate", o.linearUpdate, ">= 0");
  p.Check(o.angularUpdate >= 0.0 && Finite(o.angularUpdate), "angularUpdate", o.angularUpdate, ">= 0");
  p.Check(Finite(o.temporalUpdate), "temporalUpdate", o.temporalUpdate, "finite (< 0 disables)");
  p.Check(o.sigma > 0.0 && Finite(o.sigma), "sigma", o.sigma, "> 0");
  p.Check(o.kernelSize >= 0 && o.kernelSize <= 100, "kernelSize", o.kernelSize, "in [0, 100]");
  p.Check(o.lstep >= 0.0 && Finite(o.lstep), "lstep", o.lstep, ">= 0");
  p.Check(o.astep >= 0.0 && Finite(o.astep), "astep", o.astep, ">= 0");
  p.Check(o.iterations >= 0 && o.iterations <= 100, "iterations", o.iterations, "in [0, 100]");
  p.Check(o.lsigma > 0.0 && Finite(o.lsigma), "lsigma", o.lsigma, "> 0");
  p.Check(o.ogain > 0.0 && Finite(o.ogain), "ogain", o.ogain, "> 0");
  p.Check(o.lskip >= 0, "lskip", o.lskip, ">= 0");
  p.Check(o.subcellMatch == 0 || o.subcellMatch == 1, "subcellMatch", o.subcellMatch, "0 or 1");
  p.Check(o.sampleProposal == 0 || o.sampleProposal == 1, "sampleProposal", o.sampleProposal, "0 or 1");
  p.Check(Finite(o.minimumScore), "minimumScore", o.minimumScore, "finite");
  p.Check(o.llsamplerange >= 0.0 && Finite(o.llsamplerange), "llsamplerange", o.llsamplerange, ">= 0");
  p.Check(o.lasamplerange >= 0.0 && Finite(o.lasamplerange), "lasamplerange", o.lasamplerange, ">= 0");
  // A step must be positive when it is used, and small enough that the sampled grid stays small.
  p.Check(o.llsamplerange == 0.0 || (o.llsamplestep > 0.0 && o.llsamplerange / o.llsamplestep <= 50.0),
          "llsamplestep", o.llsamplestep, "> 0 and >= llsamplerange / 50");
  p.Check(o.lasamplerange == 0.0 || (o.lasamplestep > 0.0 && o.lasamplerange / o.lasamplestep <= 50.0),
          "lasamplestep", o.lasamplestep, "> 0 and >= lasamplerange / 50");
  p.Check(o.delta > 0.0 && Finite(o.delta), "delta", o.delta, "> 0");
  p.Check(o.maxUrange > 0.0 && Finite(o.maxUrange), "maxUrange", o.maxUrange, "> 0");
  p.Check(o.maxRange == 0.0 || (o.maxRange >= o.maxUrange && Finite(o.maxRange)), "maxRange",
          o.maxRange, "0 (the sensor's range_max) or >= maxUrange");
  p.Check(o.clearMaxRange == 0 || o.clearMaxRange == 1, "clearMaxRange", o.clearMaxRange, "0 or 1");
  p.Check(Finite(o.xmin) && Finite(o.xmax) && o.xmin < o.xmax, "xmin", o.xmin, "< xmax");
  p.Check(Finite(o.xmin) && Finite(o.xmax) && o.xmin < o.xmax, "xmax", o.xmax, "> xmin");
  p.Check(Finite(o.ymin) && Finite(o.ymax) && o.ymin < o.ymax, "ymin", o.ymin, "< ymax");
  p.Check(Finite(o.ymin) && Finite(o.ymax) && o.ymin < o.ymax, "ymax", o.ymax, "> ymin");
  if (o.delta > 0.0 && Finite(o.delta) && o.xmin < o.xmax && o.ymin < o.ymax && Finite(o.xmax - o.xmin) &&
      Finite(o.ymax - o.ymin)) {
    // The initial extent is what Map() returns at least; keep it allocatable.
    const double cells = (o.xmax - o.xmin) / o.delta * ((o.ymax - o.ymin) / o.delta);
    p.Check(cells <= 4e8, "delta", o.delta, "large enough that (xmax-xmin)·(ymax-ymin)/delta² <= 4e8 cells");
  }
  p.Check(o.loopClosure == 0 || o.loopClosure == 1, "loopClosure", o.loopClosure, "0 or 1");
  p.Check(o.loopSearchWindow > 0.0 && o.loopSearchWindow <= 50.0, "loopSearchWindow", o.loopSearchWindow,
          "in (0, 50] m");
  p.Check(o.loopDriftRate >= 0.0 && o.loopDriftRate <= 1.0, "loopDriftRate", o.loopDriftRate, "in [0, 1] m per m");
  p.Check(o.loopMaxSearchWindow >= o.loopSearchWindow && o.loopMaxSearchWindow <= 100.0, "loopMaxSearchWindow",
          o.loopMaxSearchWindow, "in [loopSearchWindow, 100] m");
  p.Check(o.loopCorridors == 0 || o.loopCorridors == 1, "loopCorridors", o.loopCorridors, "0 or 1");
  p.Check(o.loopSearchAngle > 0.0 && o.loopSearchAngle <= M_PI, "loopSearchAngle", o.loopSearchAngle,
          "in (0, pi] rad");
  p.Check(o.loopMinScore > 0.0 && o.loopMinScore <= 1.0, "loopMinScore", o.loopMinScore, "in (0, 1]");
  p.Check(o.loopSubmapScans >= 2 && o.loopSubmapScans <= 1000, "loopSubmapScans", o.loopSubmapScans,
          "in [2, 1000]");
  p.Check(o.loopMinTravel >= 0.0 && Finite(o.loopMinTravel), "loopMinTravel", o.loopMinTravel, ">= 0 m");
  p.Check(o.occ_thresh >= 0.0 && o.occ_thresh <= 1.0, "occ_thresh", o.occ_thresh, "in [0, 1]");
  p.Check(o.threads >= 0 && o.threads <= 256, "threads", o.threads, "in [0, 256] (0: one per CPU core)");
  p.ThrowIfAny();
}

namespace {

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

[[noreturn]] void BadValue(const std::string& name, const std::string& value, const char* what) {
  throw std::invalid_argument("gmapping option " + name + ": cannot use value '" + value + "' (" +
                              what + ")");
}

double ParseDouble(const std::string& name, const std::string& value) {
  const std::string v = Trim(value);
  if (v.empty()) BadValue(name, value, "expected a number");
  char* end = nullptr;
  errno = 0;
  const double d = std::strtod(v.c_str(), &end);
  if (end != v.c_str() + v.size()) BadValue(name, value, "expected a number");
  if (errno == ERANGE || !std::isfinite(d)) BadValue(name, value, "out of range");
  return d;
}

long long ParseInteger(const std::string& name, const std::string& value, long long lo, long long hi) {
  const std::string v = Trim(value);
  if (v.empty()) BadValue(name, value, "expected an integer");
  char* end = nullptr;
  errno = 0;
  const long long i = std::strtoll(v.c_str(), &end, 10);
  if (end != v.c_str() + v.size()) BadValue(name, value, "expected an integer");
  if (errno == ERANGE || i < lo || i > hi) BadValue(name, value, "out of range");
  return i;
}

}  // namespace

void SetOption(GmappingOptions* o, const std::string& name, const std::string& value) {
  auto as_int = [&]() {
    return static_cast<int>(ParseInteger(name, value, std::numeric_limits<int>::min(),
                                         std::numeric_limits<int>::max()));
  };
  auto as_double = [&]() { return ParseDouble(name, value); };
  struct Field {
    const char* name;
    double GmappingOptions::*d;
    int GmappingOptions::*i;
  };
  static const Field kFields[] = {
      {"particles", nullptr, &GmappingOptions::particles},
      {"resampleThreshold", &GmappingOptions::resampleThreshold, nullptr},
      {"srr", &GmappingOptions::srr, nullptr},
      {"srt", &GmappingOptions::srt, nullptr},
      {"str", &GmappingOptions::str, nullptr},
      {"stt", &GmappingOptions::stt, nullptr},
      {"linearUpdate", &GmappingOptions::linearUpdate, nullptr},
      {"angularUpdate", &GmappingOptions::angularUpdate, nullptr},
      {"temporalUpdate", &GmappingOptions::temporalUpdate, nullptr},
      {"sigma", &GmappingOptions::sigma, nullptr},
      {"kernelSize", nullptr, &GmappingOptions::kernelSize},
      {"lstep", &GmappingOptions::lstep, nullptr},
      {"astep", &GmappingOptions::astep, nullptr},
      {"iterations", nullptr, &GmappingOptions::iterations},
      {"lsigma", &GmappingOptions::lsigma, nullptr},
      {"ogain", &GmappingOptions::ogain, nullptr},
      {"lskip", nullptr, &GmappingOptions::lskip},
      {"minimumScore", &GmappingOptions::minimumScore, nullptr},
      {"subcellMatch", nullptr, &GmappingOptions::subcellMatch},
      {"sampleProposal", nullptr, &GmappingOptions::sampleProposal},
      {"llsamplerange", &GmappingOptions::llsamplerange, nullptr},
      {"llsamplestep", &GmappingOptions::llsamplestep, nullptr},
      {"lasamplerange", &GmappingOptions::lasamplerange, nullptr},
      {"lasamplestep", &GmappingOptions::lasamplestep, nullptr},
      {"delta", &GmappingOptions::delta, nullptr},
      {"maxUrange", &GmappingOptions::maxUrange, nullptr},
      {"maxRange", &GmappingOptions::maxRange, nullptr},
      {"clearMaxRange", nullptr, &GmappingOptions::clearMaxRange},
      {"xmin", &GmappingOptions::xmin, nullptr},
      {"ymin", &GmappingOptions::ymin, nullptr},
      {"xmax", &GmappingOptions::xmax, nullptr},
      {"ymax", &GmappingOptions::ymax, nullptr},
      {"occ_thresh", &GmappingOptions::occ_thresh, nullptr},
      {"loopClosure", nullptr, &GmappingOptions::loopClosure},
      {"loopSearchWindow", &GmappingOptions::loopSearchWindow, nullptr},
      {"loopDriftRate", &GmappingOptions::loopDriftRate, nullptr},
      {"loopMaxSearchWindow", &GmappingOptions::loopMaxSearchWindow, nullptr},
      {"loopCorridors", nullptr, &GmappingOptions::loopCorridors},
      {"loopSearchAngle", &GmappingOptions::loopSearchAngle, nullptr},
      {"loopMinScore", &GmappingOptions::loopMinScore, nullptr},
      {"loopSubmapScans", nullptr, &GmappingOptions::loopSubmapScans},
      {"loopMinTravel", &GmappingOptions::loopMinTravel, nullptr},
      {"threads", nullptr, &GmappingOptions::threads},
  };
  if (name == "seed") {
    o->seed = static_cast<unsigned>(ParseInteger(name, value, 0, std::numeric_limits<unsigned>::max()));
    return;
  }
  for (const Field& f : kFields) {
    if (name != f.name) continue;
    if (f.d != nullptr) {
      o->*(f.d) = as_double();
    } else {
      o->*(f.i) = as_int();
    }
    return;
  }
  throw std::invalid_argument("unknown gmapping option '" + name + "'");
}

}  // namespace minibot3d_slam
