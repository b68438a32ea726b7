#include "minibot3d_navigation/costmap/costmap_options.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "minibot3d_common/options.h"

namespace options = minibot3d_common::options;

namespace minibot3d_navigation {
namespace nav {
namespace {

using options::Field;
using options::Num;
using O = CostmapOptions;

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

const options::OptionTable<CostmapOptions>& CostmapOptionTable() {
  static const options::OptionTable<O> table(
      "costmap",
      {Field("global_frame", &O::global_frame,
             "Frame the costmap is kept in (map for a global costmap on a map, odom for a local "
             "one); the global costmap's is the frame of goals and plans."),
       Field("robot_base_frame", &O::robot_base_frame,
             "The robot's base frame: its pose in global_frame places the footprint and a rolling "
             "window."),
       Field("update_frequency", &O::update_frequency,
             "Rate (Hz) at which the layers are updated from the map and the sensors, checked on "
             "each control cycle; 0: every control cycle."),
       Field("publish_frequency", &O::publish_frequency,
             "Rate (Hz) at which the costmap (an OccupancyGrid on costmap in the costmap's "
             "namespace) and the footprint (on footprint) are published to subscribers; 0: "
             "never."),
       Field("transform_tolerance", &O::transform_tolerance,
             "Largest age (s) of the global_frame -> robot_base_frame transform; an older one "
             "leaves the robot's pose unknown and move_base stops the robot."),
       Field("rolling_window", &O::rolling_window,
             "A window of width x height centred on the robot and moving with it (a local "
             "costmap) instead of a fixed grid."),
       Field("width", &O::width,
             "Size in x (m) of a rolling window, or of a fixed costmap without static_map; a "
             "fixed costmap with a static map takes the map's size."),
       Field("height", &O::height,
             "Size in y (m) of a rolling window, or of a fixed costmap without static_map; a "
             "fixed costmap with a static map takes the map's size."),
       Field("resolution", &O::resolution,
             "Cell size (m); a fixed costmap with a static map takes the map's resolution."),
       Field("origin_x", &O::origin_x,
             "x (m, global_frame) of the outer corner of cell (0, 0) of a fixed costmap without a "
             "static map."),
       Field("origin_y", &O::origin_y,
             "y (m, global_frame) of the outer corner of cell (0, 0) of a fixed costmap without a "
             "static map."),
       Field("static_map", &O::static_map,
             "Add a static layer fed from the map topic (costmap_2d's old-style flag); the "
             "costmap is not used until a map has arrived."),
       Field("track_unknown_space", &O::track_unknown_space,
             "Keep space neither the map nor a sensor has shown as unknown (cost 255) instead of "
             "free."),
       Field("unknown_cost_value", &O::unknown_cost_value,
             "Map value that means unknown (-1 and 255 both mean the OccupancyGrid's -1)."),
       Field("lethal_cost_threshold", &O::lethal_cost_threshold,
             "Map values (0..100) at or above this are lethal obstacles."),
       Field("trinary_costmap", &O::trinary_costmap,
             "Map values below lethal_cost_threshold are free; false: scaled to costs "
             "proportionally (value / lethal_cost_threshold x 254)."),
       Field("footprint", &O::footprint,
             "The robot's outline, \"[[x0, y0], [x1, y1], ...]\" (m, robot frame, at least three "
             "points); empty: a circle of robot_radius."),
       Field("robot_radius", &O::robot_radius,
             "Radius (m) of a round robot, used when footprint is empty."),
       Field("footprint_padding", &O::footprint_padding,
             "Distance (m) each footprint vertex is moved outwards in x and in y (costmap_2d's "
             "padding)."),
       Field("obstacle_range", &O::obstacle_range,
             "Default of every observation source: only returns closer than this (m) to the "
             "sensor mark obstacles."),
       Field("raytrace_range", &O::raytrace_range,
             "Default of every observation source: beams clear free space up to this distance "
             "(m)."),
       Field("inf_is_valid", &O::inf_is_valid,
             "Default of every observation source: a reading of +inf means nothing within "
             "range_max and clears the whole beam; false: it is dropped."),
       Field("obstacle_decay_time", &O::obstacle_decay_time,
             "An obstacle no observation has marked for this long (s, by the sensors' stamps) "
             "is forgotten: its cell returns to unknown (track_unknown_space) or free, so "
             "someone who walked off where no beam reaches (behind another person, beyond "
             "raytrace_range) leaves no obstacle behind; 0: obstacles stay until a beam clears "
             "them (costmap_2d). Not in costmap_2d: the spatio-temporal voxel layer's "
             "voxel_decay."),
       Field("inflation_radius", &O::inflation_radius,
             "Distance (m) from an obstacle up to which costs are inflated."),
       Field("cost_scaling_factor", &O::cost_scaling_factor,
             "Decay rate (1/m) of the inflated cost beyond the inscribed radius: cost = 252 "
             "exp(-factor (d - inscribed radius)).")});
  return table;
}

const options::OptionTable<CostmapSensorOptions>& CostmapSensorOptionTable() {
  using S = CostmapSensorOptions;
  static const options::OptionTable<S> table(
      "costmap",
      {Field("observation_sources", &S::observation_sources,
             "Space-separated names of the sensors that mark and clear obstacles; each has its "
             "keys in the sub-namespace of its name (below)."),
       Field("plugins", &S::plugins,
             "costmap_2d's layer list: accepted and not used; the layers are static (with "
             "static_map), obstacle and inflation.")});
  return table;
}

const options::OptionTable<ObservationSourceOptions>& ObservationSourceOptionTable() {
  using S = ObservationSourceOptions;
  static const options::OptionTable<S> table(
      "observation source",
      {Field("topic", &S::topic, "Topic of the source's scans; default: the source's name."),
       Field("sensor_frame", &S::sensor_frame,
             "Frame of the sensor, used instead of the scan's frame_id; empty: the scan's "
             "frame_id."),
       Field("data_type", &S::data_type,
             "Message type: LaserScan or PointCloud2 (a depth camera's, a 3-D laser's)."),
       Field("marking", &S::marking, "The source's returns mark obstacles."),
       Field("clearing", &S::clearing, "The source's beams clear free space."),
       Field("obstacle_range", &S::obstacle_range,
             "Only returns closer than this (m) to the sensor mark; default: the costmap's "
             "obstacle_range."),
       Field("raytrace_range", &S::raytrace_range,
             "Beams clear free space up to this distance (m); default: the costmap's "
             "raytrace_range."),
       Field("inf_is_valid", &S::inf_is_valid,
             "A reading of +inf clears the whole beam up to range_max; default: the costmap's "
             "inf_is_valid."),
       Field("min_obstacle_height", &S::min_obstacle_height,
             "PointCloud2: points lower than this (m, in the costmap's frame) are ignored."),
       Field("max_obstacle_height", &S::max_obstacle_height,
             "PointCloud2: points higher than this (m) are ignored."),
       Field("subsample", &S::subsample,
             "PointCloud2: use every n-th row and column of an organised cloud (not in "
             "costmap_2d; 1: every point).")});
  return table;
}

ObservationSourceOptions DefaultObservationSource(const std::string& name,
                                                  const CostmapOptions& costmap) {
  ObservationSourceOptions s;
  s.topic = name;
  s.obstacle_range = costmap.obstacle_range;
  s.raytrace_range = costmap.raytrace_range;
  s.inf_is_valid = costmap.inf_is_valid;
  return s;
}

void ValidateCostmapSensorOptions(const CostmapSensorOptions& o) {
  options::Problems p("costmap");
  p.Require(o.observation_sources.find_first_of("[],") == std::string::npos,
            "observation_sources='" + o.observation_sources +
                "' must be source names separated by spaces (costmap_2d's form), not a list");
  p.ThrowIfAny();
}

std::vector<std::string> ObservationSourceNames(const CostmapSensorOptions& options) {
  std::vector<std::string> names;
  std::istringstream in(options.observation_sources);
  std::string name;
  while (in >> name) names.push_back(name);
  return names;
}

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
  p.NonNegative("obstacle_decay_time", o.obstacle_decay_time);
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
  CostmapOptionTable().Set(name, text, o);
}
bool IsCostmapOptionName(const std::string& name) { return CostmapOptionTable().Has(name); }
std::vector<std::string> CostmapOptionNames() { return CostmapOptionTable().Names(); }

}  // namespace nav
}  // namespace minibot3d_navigation
