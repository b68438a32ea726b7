// Post-processing of grid paths: cost-aware line-of-sight shortcutting,
// resampling, and the yaw of each pose.
//
// An 8-connected grid path zig-zags (only 45-degree headings).  We shorten it
// with greedy line-of-sight shortcutting, as in post-smoothed A* (Botea,
// Mueller & Schaeffer, "Near optimal hierarchical path-finding", 2004; Daniel
// et al., "Theta*", JAIR 2010), with one change so the smoothed path is never
// closer to obstacles than the raw one: a shortcut from raw point i to raw
// point j is accepted only if every cell the straight segment enters (exact
// grid traversal, Amanatides & Woo 1987) is traversable and has cost <= the
// highest cost among the raw cells i..j it replaces.  Passing exactly through
// a cell corner, as the grid path's own diagonal steps do, enters neither
// side cell.  From each kept point a galloping search (j = i+2, i+3, i+5,
// i+9, ... while accepted, then bisection) picks a far acceptable j in
// O(L log n) cell checks; the pass is repeated over the kept points (still
// bounded by the raw cells' costs) until nothing changes (at most 4 passes).
// Each shortcut replaces a polyline by a chord, so the result is never longer
// than the raw path.  The kept corners are then resampled: every segment is
// cut into equal pieces of at most `spacing` metres, corners kept exactly, so
// every pose lies on a checked segment.
#ifndef MINIBOT3D_NAVIGATION_PLANNER_PATH_SMOOTHING_H_
#define MINIBOT3D_NAVIGATION_PLANNER_PATH_SMOOTHING_H_

#include <cstdint>
#include <vector>

#include "minibot3d_navigation/costmap/costmap_2d.h"
#include "minibot3d_navigation/nav_types.h"
#include "minibot3d_navigation/planner/planner_options.h"

namespace minibot3d_navigation {
namespace nav {

// True if every cell whose interior the segment a-b crosses is on the map, traversable under
// `options` and of cost <= max_cost (255 ranks above every other cost, so
// max_cost = 255 admits unknown cells when allow_unknown is set).
bool SegmentCostsAtMost(const Costmap2D& costmap, const Point2& a,
                        const Point2& b, int max_cost,
                        const GlobalPlannerOptions& options);

// The shortcut raw path (see the file comment); raw[k] must lie in the k-th
// cell of the grid path (first and last may be the exact start and goal).
std::vector<Point2> ShortcutPath(const Costmap2D& costmap,
                                  const std::vector<Point2>& raw,
                                  const GlobalPlannerOptions& options);

// Cuts every segment into equal pieces no longer than `spacing` (> 0),
// keeping all input points.
std::vector<Point2> ResamplePolyline(const std::vector<Point2>& points,
                                      double spacing);

double PolylineLength(const std::vector<Point2>& points);
double PathLength(const Path& path);

// Poses at `points` with yaw per options.orientation_mode (0 None: 0;
// 1 Forward: towards the next distinct point; 2 Interpolate: start_yaw to
// goal.yaw in proportion to the distance travelled).  The last pose's yaw is
// goal.yaw; if the last point equals goal's position, the last pose is `goal`
// exactly.
Path MakePathPoses(const std::vector<Point2>& points, double start_yaw,
                   const Pose2& goal, int orientation_mode);

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_PLANNER_PATH_SMOOTHING_H_
