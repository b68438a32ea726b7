// 2D pose-graph optimisation with Ceres (see pose_graph.h).
#include "pose_graph.h"

#include <ceres/ceres.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace minibot3d_slam {

namespace {

template <typename T>
T WrapAngle(const T& a) {
  // atan2(sin, cos) wraps to (−π, π] and has a well-defined derivative for Jets.
  using std::atan2;
  using std::cos;
  using std::sin;
  return atan2(sin(a), cos(a));
}

struct EdgeCost {
  explicit EdgeCost(const PoseGraphEdge& e)
      : zx(e.measurement.x),
        zy(e.measurement.y),
        zt(e.measurement.yaw),
        ca(std::cos(e.axis)),
        sa(std::sin(e.axis)),
        inv_along(1.0 / (e.sigma_along > 0.0 ? e.sigma_along : e.sigma_xy)),
        inv_xy(1.0 / e.sigma_xy),
        inv_t(1.0 / e.sigma_theta) {}

  template <typename T>
  bool operator()(const T* const a, const T* const b, T* r) const {
    using std::cos;
    using std::sin;
    const T c = cos(a[2]), s = sin(a[2]);
    const T dx = b[0] - a[0], dy = b[1] - a[1];
    const T ex = c * dx + s * dy - T(zx), ey = -s * dx + c * dy - T(zy);
    // Along the edge's axis and across it (for an isotropic edge the split changes nothing).
    r[0] = (T(ca) * ex + T(sa) * ey) * T(inv_along);
    r[1] = (-T(sa) * ex + T(ca) * ey) * T(inv_xy);
    r[2] = WrapAngle(b[2] - a[2] - T(zt)) * T(inv_t);
    return true;
  }

  double zx, zy, zt, ca, sa, inv_along, inv_xy, inv_t;
};

double SquaredResidual(const Pose2& a, const Pose2& b, const PoseGraphEdge& e) {
  const EdgeCost cost(e);
  const double pa[3] = {a.x, a.y, a.yaw}, pb[3] = {b.x, b.y, b.yaw};
  double r[3];
  cost(pa, pb, r);
  return r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
}

}  // namespace

PoseGraphResult OptimizePoseGraph(const std::vector<Pose2>& initial, const std::vector<PoseGraphEdge>& edges,
                                  const PoseGraphOptions& options) {
  if (initial.empty()) throw std::invalid_argument("OptimizePoseGraph: no nodes");
  const int n = static_cast<int>(initial.size());
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const PoseGraphEdge& e = edges[k];
    if (e.from < 0 || e.from >= n || e.to < 0 || e.to >= n || e.from == e.to) {
      throw std::invalid_argument("OptimizePoseGraph: edge " + std::to_string(k) + " joins nodes " +
                                  std::to_string(e.from) + " and " + std::to_string(e.to) + " of " +
                                  std::to_string(n));
    }
    if (!(e.sigma_xy > 0.0) || !(e.sigma_theta > 0.0)) {
      throw std::invalid_argument("OptimizePoseGraph: edge " + std::to_string(k) + " has sigma_xy " +
                                  std::to_string(e.sigma_xy) + ", sigma_theta " + std::to_string(e.sigma_theta) +
                                  " (must be > 0)");
    }
    if (!std::isfinite(e.axis) || std::isnan(e.sigma_along)) {
      throw std::invalid_argument("OptimizePoseGraph: edge " + std::to_string(k) + " has axis " +
                                  std::to_string(e.axis) + ", sigma_along " + std::to_string(e.sigma_along) +
                                  " (axis must be finite, sigma_along a number)");
    }
  }
  PoseGraphResult result;
  result.edge_inlier.assign(edges.size(), true);
  std::vector<double> params(3 * static_cast<std::size_t>(n));
  for (int round = 0; round <= options.outlier_rounds; ++round) {
    for (int i = 0; i < n; ++i) {
      params[3 * i] = initial[i].x;
      params[3 * i + 1] = initial[i].y;
      params[3 * i + 2] = initial[i].yaw;
    }
    ceres::Problem problem;
    for (std::size_t k = 0; k < edges.size(); ++k) {
      if (!result.edge_inlier[k]) continue;
      const PoseGraphEdge& e = edges[k];
      auto* cost = new ceres::AutoDiffCostFunction<EdgeCost, 3, 3, 3>(
          new EdgeCost(e));
      ceres::LossFunction* loss = e.robust ? new ceres::HuberLoss(options.huber_scale) : nullptr;
      problem.AddResidualBlock(cost, loss, &params[3 * e.from], &params[3 * e.to]);
    }
    if (problem.HasParameterBlock(&params[0])) problem.SetParameterBlockConstant(&params[0]);
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    so.max_num_iterations = options.max_iterations;
    so.num_threads = 1;
    so.function_tolerance = 1e-10;
    so.parameter_tolerance = 1e-10;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    result.converged = summary.termination_type == ceres::CONVERGENCE;
    result.final_cost = summary.final_cost;
    result.poses.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      result.poses[i] = Pose2{params[3 * i], params[3 * i + 1], NormalizeAngle(params[3 * i + 2])};
    }
    // Drop the robust edges the solution disagrees with, and solve again without them.
    int dropped = 0;
    for (std::size_t k = 0; k < edges.size(); ++k) {
      const PoseGraphEdge& e = edges[k];
      if (!e.robust || !result.edge_inlier[k]) continue;
      if (SquaredResidual(result.poses[e.from], result.poses[e.to], e) > options.outlier_chi2) {
        result.edge_inlier[k] = false;
        ++dropped;
      }
    }
    result.outliers += dropped;
    if (dropped == 0) break;
  }
  return result;
}

}  // namespace minibot3d_slam
