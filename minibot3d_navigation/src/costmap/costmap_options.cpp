#include "minibot3d_navigation/costmap/costmap_options.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "minibot3d_common/options.h"

namespace options = minibot3d_common::options;

namespace minibot3d_navigation {
namespace nav {
namespace {

using options::Field;
using options::Num;
using O = CostmapOptions;

const options::OptionTable<O>& Table() {
  static const options::OptionTable<O> table(
      "costmap",
      {Field("global_frame", &O::global_frame),
       Field("robot_base_frame", &O::robot_base_frame),
       Field("update_frequency", &O::update_frequency),
       Field("publish_frequency", &O::publish_frequency),
       Field("transform_tolerance", &O::transform_tolerance),
       Field("rolling_window", &O::rolling_window),
       Field("width", &O::width),
       Field("height", &O::height),
       Field("resolution", &O::resolution),
       Field("origin_x", &O::origin_x),
       Field("origin_y", &O::origin_y),
       Field("static_map", &O::static_map),
       Field("track_unknown_space", &O::track_unknown_space),
       Field("unknown_cost_value", &O::unknown_cost_value),
       Field("lethal_cost_threshold", &O::lethal_cost_threshold),
       Field("trinary_costmap", &O::trinary_costmap),
       Field("footprint", &O::footprint),
       Field("robot_radius", &O::robot_radius),
       Field("footprint_padding", &O::footprint_padding),
       Field("obstacle_range", &O::obstacle_range),
       Field("raytrace_range", &O::raytrace_range),
       Field("inf_is_valid", &O::inf_is_valid),
       Field("inflation_radius", &O::inflation_radius),
       Field("cost_scaling_factor", &O::cost_scaling_factor)});
  return table;
}

bool Finite(double v) { return std::isfinite(v); }

// Inscribed radius of the effective footprint, NaN if it cannot be built.
double InscribedRadiusOrNaN(const CostmapOptions& o) {
  try {
    double inscribed, circumscribed;
    FootprintRadii(EffectiveFootprint(o), &inscribed, &circumscribed);
    return inscribed;
  } catch (const std::invalid_argument&) {
    return std::numeric_limits<double>::quiet_NaN();
  }
}

}  // namespace

int CostmapCells(double metres, double resolution) {
  const double cells = std::round(metres / resolution);
  if (!(cells >= 1.0)) return 1;
  if (cells > std::numeric_limits<int>::max()) return std::numeric_limits<int>::max();
  return static_cast<int>(cells);
}

Footprint EffectiveFootprint(const CostmapOptions& o) {
  Footprint fp;
  if (!options::Trim(o.footprint).empty()) {
    fp = ParseFootprint(o.footprint);  // throws naming the footprint text
  } else if (Finite(o.robot_radius) && o.robot_radius > 0.0) {
    fp = MakeCircleFootprint(o.robot_radius);
  } else {
    throw std::invalid_argument("costmap: no robot shape: footprint is empty and robot_radius=" +
                                Num(o.robot_radius) + " is not > 0; set one of them");
  }
  return PadFootprint(fp, o.footprint_padding);
}

void ValidateCostmapOptions(const CostmapOptions& o) {
  options::Problems p("costmap");

  p.Require(!options::Trim(o.global_frame).empty(), "global_frame must not be empty");
  p.Require(!options::Trim(o.robot_base_frame).empty(), "robot_base_frame must not be empty");
  p.NonNegative("update_frequency", o.update_frequency);
  p.NonNegative("publish_frequency", o.publish_frequency);
  p.NonNegative("transform_tolerance", o.transform_tolerance);
  p.Positive("resolution", o.resolution);
  p.Finite("origin_x", o.origin_x);
  p.Finite("origin_y", o.origin_y);
  // A rolling window, or a fixed costmap with no map to take its size from,
  // is sized by width x height.
  if (o.rolling_window || !o.static_map) {
    const char* why = o.rolling_window ? " (rolling_window)" : " (static_map is false)";
    p.Require(Finite(o.width) && o.width > 0.0,
              "width=" + Num(o.width) + " must be > 0" + why);
    p.Require(Finite(o.height) && o.height > 0.0,
              "height=" + Num(o.height) + " must be > 0" + why);
    if (Finite(o.width) && Finite(o.height) && Finite(o.resolution) && o.resolution > 0.0) {
      const double cells = std::round(o.width / o.resolution) * std::round(o.height / o.resolution);
      p.Require(cells <= 2.0e8, "width=" + Num(o.width) + " x height=" + Num(o.height) +
                                    " at resolution=" + Num(o.resolution) + " is " + Num(cells) +
                                    " cells (more than 2e8)");
    }
  }
  p.Require(o.unknown_cost_value >= -1 && o.unknown_cost_value <= 255,
            "unknown_cost_value=" + std::to_string(o.unknown_cost_value) +
                " must be in [-1, 255] (-1 and 255 both mean the map's unknown value)");
  p.Require(o.lethal_cost_threshold >= 1 && o.lethal_cost_threshold <= 100,
            "lethal_cost_threshold=" + std::to_string(o.lethal_cost_threshold) +
                " must be in [1, 100]");

  const bool has_footprint = !options::Trim(o.footprint).empty();
  if (has_footprint) {
    try {
      ParseFootprint(o.footprint);
    } catch (const std::invalid_argument& e) {
      p.Add(e.what());  // already names the footprint and its text
    }
    p.Require(Finite(o.robot_radius) && o.robot_radius >= 0.0,
              "robot_radius=" + Num(o.robot_radius) + " must be >= 0");
  } else {
    p.Require(Finite(o.robot_radius) && o.robot_radius > 0.0,
              "robot_radius=" + Num(o.robot_radius) +
                  " must be > 0 when no footprint is given (set footprint or robot_radius)");
  }
  p.NonNegative("footprint_padding", o.footprint_padding);
  p.NonNegative("obstacle_range", o.obstacle_range);
  p.NonNegative("raytrace_range", o.raytrace_range);
  p.NonNegative("inflation_radius", o.inflation_radius);
  p.NonNegative("cost_scaling_factor", o.cost_scaling_factor);
  p.ThrowIfAny();
}

std::vector<std::string> CostmapOptionWarnings(const CostmapOptions& o) {
  std::vector<std::string> warnings;
  const double inscribed = InscribedRadiusOrNaN(o);
  if (Finite(inscribed) && Finite(o.inflation_radius) && o.inflation_radius < inscribed) {
    warnings.push_back("inflation_radius=" + Num(o.inflation_radius) +
                       " is smaller than the padded footprint's inscribed radius " +
                       Num(inscribed) +
                       ": paths will graze obstacles; raise inflation_radius to at least the "
                       "robot's circumscribed radius");
  }
  if (Finite(o.raytrace_range) && Finite(o.obstacle_range) &&
      o.raytrace_range < o.obstacle_range) {
    warnings.push_back("raytrace_range=" + Num(o.raytrace_range) + " < obstacle_range=" +
                       Num(o.obstacle_range) +
                       ": obstacles marked beyond raytrace_range are never cleared");
  }
  if (!options::Trim(o.footprint).empty() && o.robot_radius != CostmapOptions().robot_radius) {
    warnings.push_back("both footprint and robot_radius=" + Num(o.robot_radius) +
                       " are set: the footprint is used and robot_radius is ignored");
  }
  return warnings;
}

void SetCostmapOption(const std::string& name, const std::string& text, CostmapOptions* o) {
  Table().Set(name, text, o);
}
bool IsCostmapOptionName(const std::string& name) { return Table().Has(name); }
std::vector<std::string> CostmapOptionNames() { return Table().Names(); }

}  // namespace nav
}  // namespace minibot3d_navigation
