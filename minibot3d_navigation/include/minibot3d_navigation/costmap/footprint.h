// Robot footprints and footprint collision checks on a costmap
// (costmap_2d/footprint.h and base_local_planner's CostmapModel).
//
// A footprint is a polygon in the robot frame (x forward, y left), metres.
// A circular robot (robot_radius) is represented by a 16-gon whose
// circumscribed radius is the robot radius.  FootprintCost walks the polygon's
// outline over the costmap (Bresenham per edge) and returns the worst cell
// cost, so a pose is in collision when any outline cell is lethal; because the
// outline alone would miss an obstacle wholly inside a large footprint, the
// check also looks at the cell under the robot's centre.
#ifndef MINIBOT3D_NAVIGATION_COSTMAP_FOOTPRINT_H_
#define MINIBOT3D_NAVIGATION_COSTMAP_FOOTPRINT_H_

#include <string>
#include <vector>

#include "minibot3d_navigation/costmap/costmap_2d.h"
#include "minibot3d_navigation/nav_types.h"

namespace minibot3d_navigation {
namespace nav {

using Footprint = std::vector<Point2>;

// Parses costmap_2d's string form "[[x0, y0], [x1, y1], ...]" (at least three
// points, finite).  Throws std::invalid_argument naming the problem.
Footprint ParseFootprint(const std::string& text);

// "[[x0, y0], ...]" with enough digits to round-trip.
std::string FootprintToString(const Footprint& footprint);

// A 16-gon approximating a circle of `radius` (vertices on the circle).
Footprint MakeCircleFootprint(double radius);

// Moves every vertex `padding` metres away from the origin along each axis
// (costmap_2d's padFootprint: x += sign(x) * padding, same for y).
Footprint PadFootprint(const Footprint& footprint, double padding);

// Inscribed radius: the smallest distance from the origin to an edge.
// Circumscribed radius: the largest distance from the origin to a vertex.
void FootprintRadii(const Footprint& footprint, double* inscribed,
                    double* circumscribed);

// The footprint placed at `pose` (vertices in the pose's frame).
Footprint TransformFootprint(const Footprint& footprint, const Pose2& pose);

// Worst cost under the footprint's outline placed at `pose` (and the cell under
// the centre).  Returns -1 if any of those cells is outside the costmap, else
// 0..255 (254 = lethal: collision; 255 = unknown).
int FootprintCost(const Costmap2D& costmap, const Footprint& footprint,
                  const Pose2& pose);

// Cells of a closed polygon's outline (Bresenham per edge), in map cells.
// Used to mark the robot's own footprint and by FootprintCost.
void PolygonOutlineCells(const Costmap2D& costmap, const Footprint& polygon,
                         std::vector<std::pair<int, int>>* cells);

}  // namespace nav
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_COSTMAP_FOOTPRINT_H_
