// Odometry motion models: the prediction step of Monte Carlo localization.
//
// Implements sample_motion_model_odometry (Thrun, Burgard & Fox,
// "Probabilistic Robotics", table 5.6) with the semantics of ROS amcl's
// AMCLOdom::UpdateAction, so that tuned odom_alpha values carry over:
//
//  * "diff": the odometry increment between two odometry poses is decomposed
//    into rot1 (turn towards the direction of travel), trans, rot2.  Each is
//    perturbed by zero-mean Gaussian noise whose *standard deviation* is
//      rot:   alpha1*rot^2 + alpha2*trans^2
//      trans: alpha3*trans^2 + alpha4*(rot1^2 + rot2^2)
//    i.e. the book's variance expression used as a standard deviation - the
//    historical ROS behaviour that the default alphas (0.2) were tuned for.
//  * "diff-corrected": the same, with the standard deviation being the square
//    root of those expressions (the book's model).  Needs much smaller alphas.
//  * "omni": increment = trans along the bearing of travel + rot, plus a
//    sideways "strafe" noise term; standard deviations (ROS, uncorrected)
//      trans: alpha3*trans^2 + alpha1*rot^2
//      rot:   alpha4*rot^2 + alpha2*trans^2
//      strafe: alpha1*rot^2 + alpha5*trans^2
//  * "omni-corrected": standard deviations sqrt(alpha3*t^2 + alpha4*r^2),
//    sqrt(alpha1*r^2 + alpha2*t^2), sqrt(alpha4*r^2 + alpha5*t^2).
//
// In the diff models rot1/rot2 noise uses min(|rot|, |pi - rot|) so driving
// backwards (rot1 ~ pi) is not treated as a half-turn; rot1 is 0 for
// translations below 1 cm (bearing undefined during in-place rotation).
#ifndef MINIBOT3D_NAVIGATION_AMCL_MOTION_MODEL_H_
#define MINIBOT3D_NAVIGATION_AMCL_MOTION_MODEL_H_

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "minibot3d_navigation/amcl/amcl_options.h"
#include "minibot3d_navigation/amcl/types.h"

namespace minibot3d_navigation {
namespace amcl {

struct OdomAlphas {
  double alpha1 = 0.2;
  double alpha2 = 0.2;
  double alpha3 = 0.2;
  double alpha4 = 0.2;
  double alpha5 = 0.2;
};

class MotionModel {
 public:
  virtual ~MotionModel() = default;

  // Moves every particle by the odometry increment from old_odom to new_odom
  // (both odometry-frame poses of the robot base), each with its own noise
  // sample.  Weights are left untouched; yaws are normalised to [-pi, pi).
  virtual void SamplePoses(const Pose2& old_odom, const Pose2& new_odom,
                           std::mt19937_64* rng,
                           std::vector<Particle>* particles) const = 0;

  // The odom_model_type name this model was created for.
  virtual std::string name() const = 0;
};

// type: "diff", "diff-corrected", "omni", "omni-corrected".  Throws
// std::invalid_argument for another name or a negative / non-finite alpha.
std::unique_ptr<MotionModel> CreateMotionModel(const std::string& type,
                                               const OdomAlphas& alphas);
// From odom_model_type and odom_alpha1..5.
std::unique_ptr<MotionModel> CreateMotionModel(const AmclOptions& options);

}  // namespace amcl
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_AMCL_MOTION_MODEL_H_
