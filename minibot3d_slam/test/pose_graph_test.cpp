// The 2D pose-graph optimiser on tiny graphs whose optimum is known in closed form.
#include "pose_graph.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace minibot3d_slam {
namespace {

PoseGraphEdge Edge(int from, int to, double x, double y, double theta, double sigma_xy = 0.1,
                   double sigma_theta = 0.1, bool robust = false) {
  PoseGraphEdge e;
  e.from = from;
  e.to = to;
  e.measurement = Pose2{x, y, theta};
  e.sigma_xy = sigma_xy;
  e.sigma_theta = sigma_theta;
  e.robust = robust;
  return e;
}

TEST(PoseGraphTest, TwoMeasurementsOfOneEdgeGiveTheirInverseVarianceWeightedMean) {
  // x1 = (1/1² · 1 + 1/2² · 2) / (1/1² + 1/2²) = 1.5 / 1.25 = 1.2; node 0 is fixed.
  const std::vector<Pose2> initial = {Pose2{0, 0, 0}, Pose2{0.3, -0.4, 0.2}};
  const std::vector<PoseGraphEdge> edges = {Edge(0, 1, 1.0, 0.0, 0.0, 1.0, 0.1),
                                            Edge(0, 1, 2.0, 0.0, 0.0, 2.0, 0.1)};
  const PoseGraphResult r = OptimizePoseGraph(initial, edges);
  ASSERT_EQ(r.poses.size(), 2u);
  EXPECT_NEAR(r.poses[0].x, 0.0, 1e-12);
  EXPECT_NEAR(r.poses[1].x, 1.2, 1e-6);
  EXPECT_NEAR(r.poses[1].y, 0.0, 1e-6);
  EXPECT_NEAR(r.poses[1].yaw, 0.0, 1e-6);
}

TEST(PoseGraphTest, SquareLoopWithBiasedOdometryIsClosedByOneLoopEdge) {
  // The truth: a 4 m square driven counter-clockwise, nodes every 1 m, at 16 nodes. Odometry edges
  // carry a yaw bias; the loop edge (last node seen from node 0, exact) and a strong weight on it
  // spread the bias over the loop. The optimum of consistent exact edges is the truth; here the
  // odometry edges are all wrong by the same small yaw, so the answer is the truth up to an error
  // far smaller than the dead-reckoned drift.
  std::vector<Pose2> truth;
  for (int side = 0; side < 4; ++side) {
    for (int k = 0; k < 4; ++k) {
      const double a = side * M_PI / 2;
      const Pose2 corner[4] = {{0, 0, 0}, {4, 0, M_PI / 2}, {4, 4, M_PI}, {0, 4, -M_PI / 2}};
      Pose2 p = corner[side];
      p.x += k * std::cos(a);
      p.y += k * std::sin(a);
      truth.push_back(p);
    }
  }
  truth.push_back(Pose2{0, 0, 0});  // back at the start: node 16
  std::vector<PoseGraphEdge> edges;
  std::vector<Pose2> dead{truth[0]};
  for (std::size_t i = 1; i < truth.size(); ++i) {
    Pose2 z = Between(truth[i - 1], truth[i]);
    z.yaw += 0.03;  // yaw bias
    edges.push_back(Edge(static_cast<int>(i - 1), static_cast<int>(i), z.x, z.y, z.yaw, 0.05, 0.02));
    dead.push_back(Compose(dead.back(), z));
  }
  const double drift = std::hypot(dead.back().x - truth.back().x, dead.back().y - truth.back().y);
  ASSERT_GT(drift, 0.5);
  const Pose2 z_loop = Between(truth[0], truth.back());
  edges.push_back(Edge(0, 16, z_loop.x, z_loop.y, z_loop.yaw, 0.01, 0.005, /*robust=*/true));
  PoseGraphOptions options;
  options.huber_scale = 1e3;  // quadratic here: the loop edge is correct
  const PoseGraphResult r = OptimizePoseGraph(dead, edges, options);
  EXPECT_EQ(r.outliers, 0);
  double worst = 0.0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    worst = std::max(worst, std::hypot(r.poses[i].x - truth[i].x, r.poses[i].y - truth[i].y));
  }
  EXPECT_NEAR(r.poses.back().x, 0.0, 0.03);
  EXPECT_NEAR(r.poses.back().y, 0.0, 0.03);
  EXPECT_LT(worst, 0.25 * drift);
}

TEST(PoseGraphTest, AFalseLoopEdgeIsDroppedAndDoesNotBendTheGraph) {
  // A straight line of 10 nodes, consistent odometry, one true loop edge 0→9 and one false one
  // claiming node 5 is 3 m to the side of node 0.
  std::vector<Pose2> initial;
  std::vector<PoseGraphEdge> edges;
  for (int i = 0; i < 10; ++i) initial.push_back(Pose2{static_cast<double>(i), 0.0, 0.0});
  for (int i = 1; i < 10; ++i) edges.push_back(Edge(i - 1, i, 1.0, 0.0, 0.0, 0.02, 0.005));
  edges.push_back(Edge(0, 9, 9.0, 0.0, 0.0, 0.03, 0.01, true));
  edges.push_back(Edge(0, 5, 5.0, 3.0, 0.0, 0.03, 0.01, true));
  const PoseGraphResult r = OptimizePoseGraph(initial, edges);
  EXPECT_EQ(r.outliers, 1);
  EXPECT_TRUE(r.edge_inlier[9]);
  EXPECT_FALSE(r.edge_inlier[10]);
  for (int i = 0; i < 10; ++i) {
    EXPECT_NEAR(r.poses[i].x, i, 1e-3) << i;
    EXPECT_NEAR(r.poses[i].y, 0.0, 1e-3) << i;
  }
}

TEST(PoseGraphTest, AnEdgeWeakAlongItsAxisFixesOnlyTheOtherDirections) {
  // Node 1 is held by a loose edge from node 0 at (1, 0). A second edge, weak along the direction
  // 45° in node 0's frame and tight across it, says (3, 1): across the axis its word wins (the
  // optimum lies on the line through (3, 1) along 45°), along it the loose edge's does. The
  // closed form: minimise |p − (1, 0)|²/1² + (n·(p − (3, 1)))²/0.01² + (u·(p − (3, 1)))²/100²,
  // u = (1, 1)/√2, n = (−1, 1)/√2. Across: n·p ≈ n·(3, 1) = −√2; along: u·p ≈ u·(1, 0) = 1/√2
  // (the weak term moves it by ~1e-4), so p ≈ (u·p) u + (n·p) n = (1.5, −0.5).
  const std::vector<Pose2> initial = {Pose2{}, Pose2{0.5, 0.5, 0.1}};
  PoseGraphEdge weak = Edge(0, 1, 3.0, 1.0, 0.0, 0.01, 0.01);
  weak.axis = M_PI / 4;
  weak.sigma_along = 100.0;
  const std::vector<PoseGraphEdge> edges = {Edge(0, 1, 1.0, 0.0, 0.0, 1.0, 1.0), weak};
  const PoseGraphResult r = OptimizePoseGraph(initial, edges);
  EXPECT_NEAR(r.poses[1].x, 1.5, 1e-3);
  EXPECT_NEAR(r.poses[1].y, -0.5, 1e-3);
  EXPECT_NEAR(r.poses[1].yaw, 0.0, 1e-6);
  // The same edge, isotropic (sigma_along 0 means sigma_xy), puts node 1 at (3, 1).
  PoseGraphEdge tight = weak;
  tight.sigma_along = 0.0;
  const PoseGraphResult t = OptimizePoseGraph(initial, {edges[0], tight});
  EXPECT_NEAR(t.poses[1].x, 3.0, 1e-3);
  EXPECT_NEAR(t.poses[1].y, 1.0, 1e-3);
}

TEST(PoseGraphTest, BadGraphsAreRejected) {
  EXPECT_THROW(OptimizePoseGraph({}, {}), std::invalid_argument);
  const std::vector<Pose2> two = {Pose2{}, Pose2{1, 0, 0}};
  EXPECT_THROW(OptimizePoseGraph(two, {Edge(0, 2, 1, 0, 0)}), std::invalid_argument);
  EXPECT_THROW(OptimizePoseGraph(two, {Edge(0, 1, 1, 0, 0, 0.0, 0.1)}), std::invalid_argument);
  EXPECT_THROW(OptimizePoseGraph(two, {Edge(1, 1, 1, 0, 0)}), std::invalid_argument);
  PoseGraphEdge bad_axis = Edge(0, 1, 1, 0, 0);
  bad_axis.axis = std::nan("");
  EXPECT_THROW(OptimizePoseGraph(two, {bad_axis}), std::invalid_argument);
}

}  // namespace
}  // namespace minibot3d_slam
