// 2D pose-graph optimisation, the back-end of SLAM loop closure: Lu & Milios, "Globally consistent
// range scan alignment for environment mapping" (Autonomous Robots 1997), in the sparse
// least-squares form of Grisetti, Kümmerle, Stachniss & Burgard, "A tutorial on graph-based SLAM"
// (IEEE ITS Magazine 2010), solved with Ceres (Levenberg-Marquardt, sparse normal Cholesky).
//
// Nodes are poses (x, y, θ) in one frame; an edge (i, j, z) says "node j seen from node i is z",
// with standard deviations (σ_xy, σ_θ). Its whitened residual is
//   r = [R(θ_i)ᵀ (t_j − t_i) − z_t] / σ_xy,   [wrap(θ_j − θ_i − z_θ)] / σ_θ.
// An edge may be weak along one direction (a scan matched in a corridor fixes where across the
// corridor and which way the robot is, not how far along it): then the translation residual's
// component along `axis` (an angle in node i's frame) is divided by `sigma_along` instead.
// Edges flagged `robust` (loop closures) go through a Huber loss of scale `huber_scale` (in σ): a
// wrong loop closure then pulls on the graph with a bounded force instead of a quadratic one, and
// after the solve, robust edges whose residual exceeds `outlier_chi2` (squared whitened norm) are
// switched off and the graph is solved again, so one false match cannot bend a building. Node 0 is
// held fixed (the graph's gauge).
#ifndef MINIBOT3D_SLAM_SRC_POSE_GRAPH_H_
#define MINIBOT3D_SLAM_SRC_POSE_GRAPH_H_

#include <vector>

#include "minibot3d_slam/types.h"

namespace minibot3d_slam {

struct PoseGraphEdge {
  int from = 0, to = 0;
  Pose2 measurement;  // pose of `to` in the frame of `from`
  double sigma_xy = 0.05, sigma_theta = 0.02;
  // The direction (angle in the frame of `from`) whose translation has standard deviation
  // sigma_along rather than sigma_xy; sigma_along <= 0 means sigma_xy (an isotropic edge).
  double axis = 0.0, sigma_along = 0.0;
  bool robust = false;
};

struct PoseGraphOptions {
  double huber_scale = 3.0;    // in standard deviations
  double outlier_chi2 = 25.0;  // squared whitened residual above which a robust edge is dropped
  int max_iterations = 50;
  int outlier_rounds = 2;      // solve → drop outliers → solve again, at most this many times
};

struct PoseGraphResult {
  std::vector<Pose2> poses;
  std::vector<bool> edge_inlier;  // per edge: false for robust edges dropped as outliers
  int outliers = 0;
  double final_cost = 0.0;
  bool converged = false;
};

// Optimises `initial` (node poses) under `edges`. Throws std::invalid_argument for an edge naming
// a node out of range, a non-positive sigma_xy or sigma_theta, a non-finite axis or an empty graph.
PoseGraphResult OptimizePoseGraph(const std::vector<Pose2>& initial,
                                  const std::vector<PoseGraphEdge>& edges,
                                  const PoseGraphOptions& options = PoseGraphOptions());

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_SRC_POSE_GRAPH_H_
