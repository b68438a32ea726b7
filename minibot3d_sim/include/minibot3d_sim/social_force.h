// Pedestrians that react: the social force model (Helbing & Molnár 1995, "Social force model for
// pedestrian dynamics", Phys. Rev. E 51), with the interaction between walkers that Moussaïd,
// Helbing, Garnier, Johansson, Combe & Theraulaz measured on pairs of people avoiding each other
// ("Experimental study of the behavioural mechanisms underlying self-organization in human
// crowds", Proc. R. Soc. B 276, 2009), as PedSim and pedsim_ros use it.
//
// Each pedestrian i walks towards its current goal with a desired speed v0, relaxing its velocity
// towards v0 e_i in tau seconds, and reacts to each other walker or robot j and to the walls:
//   f_goal = (v0 e_i - v_i) / tau
//   f_ij   = -A exp(-d_ij / B) [exp(-(n' B theta)^2) t_ij + K exp(-(n B theta)^2) n_ij]
//   f_iW   = A_w exp((r_i - d_iW) / B_w) n_iW
// where e_ij points from i to j at the distance d_ij between their centres; the interaction
// direction t_ij is that of D = lambda (v_i - v_j) + e_ij (what i is heading into, given how fast
// they close), n_ij its left normal, B = gamma |D|, theta the angle from t_ij to e_ij and K its
// sign: a walker slows along t_ij and turns away from the side the other is on, the more the
// faster they close and the more head-on they meet. Dead ahead (theta = 0) the tie is broken by
// adding B / 200 to theta, so both step aside, to their right unless the fluctuation tips them
// the other way, and pass, as people do, instead of pressing into each other. Where bodies overlap, the body force k (overlap) of Helbing, Farkas &
// Vicsek 2000 ("Simulating dynamical features of escape panic", Nature 407) with their k / m = 1500
// s^-2 pushes them apart. The velocity is integrated with semi-implicit Euler in fixed steps and
// capped at 1.3 v0. A goal is reached within `goal_radius`; the pedestrian then heads for the next
// one, cycling through its list. A fluctuation force (Helbing & Molnár's xi: Gaussian,
// `fluctuation` m/s^2 per axis, drawn each step from the crowd's seeded stream) varies the walks;
// the same seed replays the crowd exactly.
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

// The model's constants, per unit mass: Moussaïd et al. 2009's interaction (A 4.5 m/s^2, gamma
// 0.35, lambda 2, n 2, n' 3, fitted to their experiments), the walls' 10 m/s^2 and 0.2 m of Helbing
// & Molnár and the body force of Helbing, Farkas & Vicsek.
struct SocialForceParams {
  double interaction_strength = 4.5;  // A, m/s^2
  double interaction_gamma = 0.35;    // gamma
  double interaction_lambda = 2.0;    // lambda: weight of the relative velocity, s/m
  double interaction_n = 2.0;         // n: angular reach of the turning term
  double interaction_n_prime = 3.0;   // n': angular reach of the slowing term
  double wall_strength = 10.0;        // A_w, m/s^2
  double wall_range = 0.2;            // B_w, m
  double body_stiffness = 1500;       // k / m, 1/s^2
  double fluctuation = 0.3;           // standard deviation of xi, m/s^2 per axis
  double step = 0.01;                 // s of sim time per integration step
  double max_speed_factor = 1.3;
};

// A disc another pedestrian must keep away from (a robot's bounding circle), and its velocity.
struct SocialForceObstacle {
  Eigen::Vector2d position;
  double radius = 0.0;
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();
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
