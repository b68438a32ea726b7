#include "minibot3d_sim/social_force.h"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace minibot3d_sim {
namespace {

constexpr double kNegligible = 1e-3;  // m/s^2

}  // namespace

void ValidateSocialForceAgent(const SocialForceAgentOptions& o, const std::string& what) {
  auto bad = [&](const std::string& m) { throw std::invalid_argument(what + ": " + m); };
  if (o.goals.empty()) bad("no <goal>: a pedestrian needs at least one");
  for (const auto& g : o.goals) {
    if (!std::isfinite(g.x()) || !std::isfinite(g.y())) bad("a <goal> is not finite");
  }
  if (!(o.desired_speed > 0.0 && o.desired_speed <= 5.0)) {
    bad("<desired_speed> must be in (0, 5] m/s, got " + std::to_string(o.desired_speed));
  }
  if (!(o.relaxation_time > 0.0)) {
    bad("<relaxation_time> must be > 0 s, got " + std::to_string(o.relaxation_time));
  }
  if (!(o.goal_radius > 0.0)) bad("<goal_radius> must be > 0 m, got " + std::to_string(o.goal_radius));
}

SocialForceCrowd::SocialForceCrowd(std::vector<SocialForceAgent> agents,
                                   const SocialForceParams& params, WallDistance wall_distance,
                                   unsigned seed)
    : agents_(std::move(agents)),
      params_(params),
      wall_distance_(std::move(wall_distance)),
      rng_(seed) {}

Eigen::Vector2d SocialForceCrowd::Force(size_t i,
                                        const std::vector<SocialForceObstacle>& obstacles) const {
  const SocialForceAgent& a = agents_[i];
  const Eigen::Vector2d to_goal = a.options.goals[a.goal] - a.position;
  const double goal_distance = to_goal.norm();
  const Eigen::Vector2d e = goal_distance > 1e-9 ? Eigen::Vector2d(to_goal / goal_distance)
                                                 : Eigen::Vector2d::Zero();
  Eigen::Vector2d f = (a.options.desired_speed * e - a.velocity) / a.options.relaxation_time;
  // Pairs whose force is below kNegligible are skipped: exp(-d/B) A < kNegligible where
  // d / B > log(A / kNegligible).
  const double cutoff = std::log(params_.interaction_strength / kNegligible);
  const auto interact = [&](const Eigen::Vector2d& other, const Eigen::Vector2d& other_velocity,
                            double other_radius) {
    const Eigen::Vector2d to = other - a.position;
    const double dist = to.norm();
    if (dist < 1e-9) return;
    const Eigen::Vector2d e_ij = to / dist;
    const double overlap = a.radius + other_radius - dist;
    if (overlap > 0.0) f -= params_.body_stiffness * overlap * e_ij;
    const Eigen::Vector2d d = params_.interaction_lambda * (a.velocity - other_velocity) + e_ij;
    const double d_norm = d.norm();
    const double b = params_.interaction_gamma * d_norm;
    if (!(dist < cutoff * b)) return;
    const Eigen::Vector2d t = d / d_norm;
    const Eigen::Vector2d n(-t.y(), t.x());
    const double theta =
        std::atan2(t.x() * e_ij.y() - t.y() * e_ij.x(), t.dot(e_ij)) + 0.005 * b;
    const double k = theta >= 0.0 ? 1.0 : -1.0;
    const double slow = params_.interaction_n_prime * b * theta;
    const double turn = params_.interaction_n * b * theta;
    const double near = -dist / b;
    f -= params_.interaction_strength *
         (std::exp(near - slow * slow) * t + k * std::exp(near - turn * turn) * n);
  };
  for (size_t j = 0; j < agents_.size(); ++j) {
    if (j != i) interact(agents_[j].position, agents_[j].velocity, agents_[j].radius);
  }
  for (const SocialForceObstacle& o : obstacles) interact(o.position, o.velocity, o.radius);
  if (wall_distance_) {
    Eigen::Vector2d away = Eigen::Vector2d::Zero();
    const double reach = a.radius + 10.0 * params_.wall_range;
    const double dw = wall_distance_(a.position, reach, &away);
    if (dw < reach) {
      f += params_.wall_strength * std::exp((a.radius - dw) / params_.wall_range) * away;
      if (dw < a.radius) f += params_.body_stiffness * (a.radius - dw) * away;
    }
  }
  return f;
}

void SocialForceCrowd::Step(const std::vector<SocialForceObstacle>& obstacles) {
  const double dt = params_.step;
  std::vector<Eigen::Vector2d> forces(agents_.size());
  std::normal_distribution<double> xi(0.0, 1.0);
  for (size_t i = 0; i < agents_.size(); ++i) {
    forces[i] = Force(i, obstacles);
    if (params_.fluctuation > 0.0) {
      const double fx = xi(rng_), fy = xi(rng_);
      forces[i] += params_.fluctuation * Eigen::Vector2d(fx, fy);
    }
  }
  for (size_t i = 0; i < agents_.size(); ++i) {
    SocialForceAgent& a = agents_[i];
    a.velocity += dt * forces[i];
    const double cap = params_.max_speed_factor * a.options.desired_speed;
    const double speed = a.velocity.norm();
    if (speed > cap) a.velocity *= cap / speed;
    a.position += dt * a.velocity;
    if ((a.options.goals[a.goal] - a.position).norm() <= a.options.goal_radius) {
      a.goal = (a.goal + 1) % a.options.goals.size();
    }
  }
}

}  // namespace minibot3d_sim
