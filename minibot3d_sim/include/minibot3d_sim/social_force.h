// Pedestrians that react: the social force model (Helbing & Molnár 1995, "Social force model for
// pedestrian dynamics", Phys. Rev. E 51), in the circular form with anisotropy of Helbing, Farkas
// & Vicsek 2000 as pedestrian simulators (pedsim, PedSim ROS, crowd studies) use it.
//
// Each pedestrian i walks towards its current goal with a desired speed v0, relaxing its velocity
// towards v0 e_i in tau seconds, and is pushed away from other pedestrians j, from robots and from
// walls by forces that fall off exponentially with the gap between the bodies:
//   f_goal = (v0 e_i - v_i) / tau
//   f_ij   = A exp((r_i + r_j - d_ij) / B) n_ij w(phi),   w = lambda + (1 - lambda)(1 + cos phi) / 2
//   f_iW   = A_w exp((r_i - d_iW) / B_w) n_iW
// (n: unit vector from the other towards i; phi: angle between i's heading and -n, so what is
// ahead weighs more than what is behind), plus, where bodies overlap, the body force k (overlap) n
// of Helbing, Farkas & Vicsek 2000 ("Simulating dynamical features of escape panic", Nature 407)
// with their k / m = 1500 s^-2, so bodies stay apart in a dense crowd. The velocity is integrated with semi-implicit Euler in
// fixed steps and capped at 1.3 v0. A goal is reached within `goal_radius`; the pedestrian then
// heads for the next one, cycling through its list. A fluctuation force (Helbing & Molnár's
// xi: Gaussian, `fluctuation` m/s^2 per axis, drawn each step from the crowd's seeded stream)
// breaks the symmetric standoffs a deterministic model locks into; the same seed replays the
// crowd exactly.
#ifndef MINIBOT3D_SIM_SOCIAL_FORCE_H_
#define MINIBOT3D_SIM_SOCIAL_FORCE_H_

#include <functional>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace minibot3d_sim {

// One pedestrian's settings, from its <actor>'s social-force <plugin> (see world_loader.h).
struct SocialForceAgentOptions {
  std::vector<Eigen::Vector2d> goals;  // visited in order, then again from the first
  double desired_speed = 1.0;          // m/s
  double relaxation_time = 0.5;        // tau, s
  double goal_radius = 0.3;            // m
};

// The model's constants, per unit mass: the circular specification calibrated on video of
// pedestrians (Johansson, Helbing & Shukla 2007, as tabulated by Helbing & Johansson 2009: A 0.42
// m/s^2, B 1.65 m, lambda 0.12), the walls' 10 m/s^2 and 0.2 m of Helbing & Molnár and the body
// force of Helbing, Farkas & Vicsek. Walkers meeting head-on swerve early and may brush shoulders,
// as people do.
struct SocialForceParams {
  double agent_strength = 0.42;  // A, m/s^2
  double agent_range = 1.65;     // B, m
  double wall_strength = 10.0;   // A_w, m/s^2
  double wall_range = 0.2;       // B_w, m
  double anisotropy = 0.12;      // lambda
  double body_stiffness = 1500;  // k / m, 1/s^2
  double fluctuation = 0.3;      // standard deviation of xi, m/s^2 per axis
  double step = 0.01;            // s of sim time per integration step
  double max_speed_factor = 1.3;
};

// A disc another pedestrian must keep away from (a robot's bounding circle).
struct SocialForceObstacle {
  Eigen::Vector2d position;
  double radius = 0.0;
};

struct SocialForceAgent {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();
  double radius = 0.25;
  size_t goal = 0;  // index into options.goals
  SocialForceAgentOptions options;
};

class SocialForceCrowd {
 public:
  // `wall_distance(p, reach, &gradient)`: distance from p to the nearest wall (+inf where there is
  // none) and, when it is below `reach`, its unit gradient (pointing away from the wall). Walls
  // farther than the radius plus ten wall ranges push with less than 5e-4 of their strength and
  // are left out.
  using WallDistance = std::function<double(const Eigen::Vector2d&, double, Eigen::Vector2d*)>;

  SocialForceCrowd(std::vector<SocialForceAgent> agents, const SocialForceParams& params,
                   WallDistance wall_distance, unsigned seed = 1);

  // Advances every pedestrian by params.step, all from the same previous state.
  void Step(const std::vector<SocialForceObstacle>& obstacles);
  const std::vector<SocialForceAgent>& agents() const { return agents_; }
  const SocialForceParams& params() const { return params_; }

 private:
  Eigen::Vector2d Force(size_t i, const std::vector<SocialForceObstacle>& obstacles) const;

  std::vector<SocialForceAgent> agents_;
  SocialForceParams params_;
  WallDistance wall_distance_;
  std::mt19937 rng_;
};

// Throws std::invalid_argument naming `what` and the value at fault.
void ValidateSocialForceAgent(const SocialForceAgentOptions& options, const std::string& what);

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_SOCIAL_FORCE_H_
