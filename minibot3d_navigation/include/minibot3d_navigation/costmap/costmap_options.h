// Parameters of one layered costmap (the global or the local one).
//
// Names and defaults are costmap_2d's (Costmap2DROS plus the static, obstacle
// and inflation layers, ROS 1 navigation), in the "old style" flat form that
// the move_base tutorials' costmap_common_params.yaml use, so those YAML files
// load parameter by parameter through CostmapOptionTable().  The algorithm they
// configure is described in layered_costmap.h (Lu, Hershberger & Smart,
// "Layered costmaps for context-sensitive navigation", IROS 2014).
#ifndef MINIBOT3D_NAVIGATION_COSTMAP_COSTMAP_OPTIONS_H_
#define MINIBOT3D_NAVIGATION_COSTMAP_COSTMAP_OPTIONS_H_

#include <string>
#include <vector>

#include "minibot3d_common/options.h"
#include "minibot3d_navigation/costmap/footprint.h"

namespace minibot3d_navigation {
namespace nav {

struct CostmapOptions {
  // --- Costmap2DROS ---
  std::string global_frame = "map";
  std::string robot_base_frame = "base_link";
  double update_frequency = 5.0;     // Hz; the node's update loop
  double publish_frequency = 0.0;    // Hz; 0 = never publish
  double transform_tolerance = 0.3;  // s
  // A window of width x height metres that follows the robot (local costmap)
  // instead of a fixed map (global costmap).
  bool rolling_window = false;
  // Metres.  The grid has lround(width / resolution) cells.  Ignored by a
  // fixed (non-rolling) costmap once the static layer has a map: the costmap
  // then takes the map's size, resolution and origin.
  double width = 10.0;
  double height = 10.0;
  double resolution = 0.05;  // m per cell
  double origin_x = 0.0;     // corner of cell (0, 0), fixed costmap only
  double origin_y = 0.0;
  // Old-style flag: true adds a static layer fed from the map.
  bool static_map = true;
  // Unknown space is kept as cost 255 (NO_INFORMATION) instead of free.
  bool track_unknown_space = false;

  // --- Static layer (interpretation of nav_msgs/OccupancyGrid values) ---
  int unknown_cost_value = -1;      // map value meaning unknown (-1 == 255)
  int lethal_cost_threshold = 100;  // map values >= this are lethal
  bool trinary_costmap = true;      // below the threshold: free, not scaled

  // --- Footprint ---
  // costmap_2d's "[[x0, y0], [x1, y1], ...]" (robot frame, metres); when
  // empty the robot is a circle of robot_radius.
  std::string footprint;
  double robot_radius = 0.46;
  double footprint_padding = 0.01;  // m added around the footprint

  // --- Obstacle layer (defaults of every observation source) ---
  double obstacle_range = 2.5;  // only hits closer than this mark
  double raytrace_range = 3.0;  // rays clear free space up to this
  // Laser readings of +inf mean "nothing within range_max": clear along the
  // whole beam instead of dropping it.
  bool inf_is_valid = false;
  // Seconds after which an obstacle no observation has marked again is
  // forgotten (not in costmap_2d; the spatio-temporal voxel layer's
  // voxel_decay): a person who walked off where no ray reaches leaves no
  // obstacle behind.  0 = never (costmap_2d).
  double obstacle_decay_time = 0.0;

  // --- Inflation layer ---
  double inflation_radius = 0.55;
  double cost_scaling_factor = 10.0;
};

// Throws std::invalid_argument whose message lists every offending parameter
// with its value, e.g. "invalid costmap parameters: resolution=0 must be > 0;
// raytrace_range=-1 must be >= 0".
void ValidateCostmapOptions(const CostmapOptions& options);

// Legal but suspicious settings, one sentence each, saying what to check:
// inflation_radius below the robot's inscribed radius (the planner will then
// graze walls), raytrace_range < obstacle_range (obstacles are marked where
// they can never be cleared), footprint and a non-default robot_radius both
// given (robot_radius is ignored).  Empty when nothing is suspicious.
std::vector<std::string> CostmapOptionWarnings(const CostmapOptions& options);

// The costmap_2d names of CostmapOptions, each with its documentation (parsing
// by name, the docs' reference).  Setting does not validate ranges; call
// ValidateCostmapOptions() once all are set.
const minibot3d_common::options::OptionTable<CostmapOptions>& CostmapOptionTable();

// Thin wrappers of CostmapOptionTable(): Set throws std::invalid_argument for an
// unknown name or text that does not parse ("0.05", "true", "[[0.2, 0.15], ...]").
void SetCostmapOption(const std::string& name, const std::string& text,
                      CostmapOptions* options);
bool IsCostmapOptionName(const std::string& name);
std::vector<std::string> CostmapOptionNames();  // declaration order

// The keys of a costmap's namespace that say where its obstacles come from,
// read by the ROS node (costmap_2d's old-style observation sources).
struct CostmapSensorOptions {
  // Space-separated names of the observation sources; each names a
  // sub-namespace with ObservationSourceOptions.
  std::string observation_sources;
  // costmap_2d's layer list ([{name, type}, ...]): accepted, not used; the
  // layers are the static (with static_map), obstacle and inflation layers.
  std::vector<std::string> plugins;
};

const minibot3d_common::options::OptionTable<CostmapSensorOptions>& CostmapSensorOptionTable();

// Throws std::invalid_argument when observation_sources is not names
// separated by spaces (a YAML list, say).
void ValidateCostmapSensorOptions(const CostmapSensorOptions& options);

// One observation source (a sub-namespace named in observation_sources).
struct ObservationSourceOptions {
  std::string topic;         // DefaultObservationSource: the source's name
  std::string sensor_frame;  // empty: the scan's own frame
  std::string data_type = "LaserScan";
  bool marking = true;
  bool clearing = true;
  // Defaults: the costmap's obstacle_range, raytrace_range and inf_is_valid.
  double obstacle_range = 2.5;
  double raytrace_range = 3.0;
  bool inf_is_valid = false;
  // PointCloud2 sources: only points this high above the costmap's frame count (m).
  double min_obstacle_height = 0.0;
  double max_obstacle_height = 2.0;
  // PointCloud2 sources: every n-th row and column of an organised cloud (a depth camera's).
  int subsample = 1;
};

const minibot3d_common::options::OptionTable<ObservationSourceOptions>&
ObservationSourceOptionTable();

// The settings of source `name` before its own keys are read: topic `name`,
// ranges and inf_is_valid from the costmap.
ObservationSourceOptions DefaultObservationSource(const std::string& name,
                                                  const CostmapOptions& costmap);

// The names in observation_sources ("a b" -> {a, b}).
std::vector<std::string> ObservationSourceNames(const CostmapSensorOptions& options);

// The footprint the costmap uses: `footprint` parsed if given, else a circle
// of robot_radius (MakeCircleFootprint), then padded by footprint_padding
// (costmap_2d pads the circle too).  Throws std::invalid_argument naming the
// parameter if neither is usable.
Footprint EffectiveFootprint(const CostmapOptions& options);

// Grid size in cells for a window of `metres` (lround(metres / resolution),
// at least 1).
int CostmapCells(double metres, double resolution);

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_COSTMAP_COSTMAP_OPTIONS_H_
