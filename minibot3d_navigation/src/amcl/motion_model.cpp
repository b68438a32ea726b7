#include "minibot3d_navigation/amcl/motion_model.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace minibot3d_navigation {
namespace amcl {
namespace {

// Below this translation the direction of travel is numerically meaningless
// (in-place rotation), so all rotation is attributed to rot2 (as amcl).
constexpr double kMinTransForBearing = 0.01;

// Distance of a rotation from "straight ahead or straight back": the noise
// magnitude of rot1/rot2 must not explode when the robot reverses.
double RotNoiseMagnitude(double rot) {
  return std::min(std::fabs(AngleDiff(rot, 0.0)),
                  std::fabs(AngleDiff(rot, kPi)));
}

class DiffMotionModel : public MotionModel {
 public:
  DiffMotionModel(const OdomAlphas& a, bool corrected)
      : a_(a), corrected_(corrected) {}

  void SamplePoses(const Pose2& old_odom, const Pose2& new_odom,
                   std::mt19937_64* rng,
                   std::vector<Particle>* particles) const override {
    const double dx = new_odom.x - old_odom.x;
    const double dy = new_odom.y - old_odom.y;
    const double dyaw = AngleDiff(new_odom.yaw, old_odom.yaw);
    const double trans = std::hypot(dx, dy);
    const double rot1 = trans < kMinTransForBearing
                            ? 0.0
                            : AngleDiff(std::atan2(dy, dx), old_odom.yaw);
    const double rot2 = AngleDiff(dyaw, rot1);
    const double n1 = RotNoiseMagnitude(rot1), n2 = RotNoiseMagnitude(rot2);
    const double t2 = trans * trans;

    double sd_rot1 = a_.alpha1 * n1 * n1 + a_.alpha2 * t2;
    double sd_trans = a_.alpha3 * t2 + a_.alpha4 * (n1 * n1 + n2 * n2);
    double sd_rot2 = a_.alpha1 * n2 * n2 + a_.alpha2 * t2;
    if (corrected_) {
      sd_rot1 = std::sqrt(sd_rot1);
      sd_trans = std::sqrt(sd_trans);
      sd_rot2 = std::sqrt(sd_rot2);
    }

    std::normal_distribution<double> gauss(0.0, 1.0);
    for (Particle& p : *particles) {
      const double rot1_hat = AngleDiff(rot1, sd_rot1 * gauss(*rng));
      const double trans_hat = trans - sd_trans * gauss(*rng);
      const double rot2_hat = AngleDiff(rot2, sd_rot2 * gauss(*rng));
      const double heading = p.pose.yaw + rot1_hat;
      p.pose.x += trans_hat * std::cos(heading);
      p.pose.y += trans_hat * std::sin(heading);
      p.pose.yaw = NormalizeAngle(p.pose.yaw + rot1_hat + rot2_hat);
    }
  }

  std::string name() const override {
    return corrected_ ? "diff-corrected" : "diff";
  }

 private:
  OdomAlphas a_;
  bool corrected_;
};

class OmniMotionModel : public MotionModel {
 public:
  OmniMotionModel(const OdomAlphas& a, bool corrected)
      : a_(a), corrected_(corrected) {}

  void SamplePoses(const Pose2& old_odom, const Pose2& new_odom,
                   std::mt19937_64* rng,
                   std::vector<Particle>* particles) const override {
    const double dx = new_odom.x - old_odom.x;
    const double dy = new_odom.y - old_odom.y;
    const double rot = AngleDiff(new_odom.yaw, old_odom.yaw);
    const double trans = std::hypot(dx, dy);
    const double t2 = trans * trans, r2 = rot * rot;
    // Direction of travel relative to the robot heading at the old pose.
    const double bearing = AngleDiff(std::atan2(dy, dx), old_odom.yaw);

    double sd_trans, sd_rot, sd_strafe;
    if (corrected_) {
      sd_trans = std::sqrt(a_.alpha3 * t2 + a_.alpha4 * r2);
      sd_rot = std::sqrt(a_.alpha1 * r2 + a_.alpha2 * t2);
      sd_strafe = std::sqrt(a_.alpha4 * r2 + a_.alpha5 * t2);
    } else {
      // ROS amcl's original omni model: variance-like sums used as standard
      // deviations, with its own assignment of alpha1/alpha4.
      sd_trans = a_.alpha3 * t2 + a_.alpha1 * r2;
      sd_rot = a_.alpha4 * r2 + a_.alpha2 * t2;
      sd_strafe = a_.alpha1 * r2 + a_.alpha5 * t2;
    }

    std::normal_distribution<double> gauss(0.0, 1.0);
    for (Particle& p : *particles) {
      const double heading = p.pose.yaw + bearing;
      const double c = std::cos(heading), s = std::sin(heading);
      const double trans_hat = trans + sd_trans * gauss(*rng);
      const double rot_hat = rot + sd_rot * gauss(*rng);
      const double strafe_hat = sd_strafe * gauss(*rng);
      p.pose.x += trans_hat * c + strafe_hat * s;
      p.pose.y += trans_hat * s - strafe_hat * c;
      p.pose.yaw = NormalizeAngle(p.pose.yaw + rot_hat);
    }
  }

  std::string name() const override {
    return corrected_ ? "omni-corrected" : "omni";
  }

 private:
  OdomAlphas a_;
  bool corrected_;
};

}  // namespace

std::unique_ptr<MotionModel> CreateMotionModel(const std::string& type,
                                               const OdomAlphas& alphas) {
  const double values[] = {alphas.alpha1, alphas.alpha2, alphas.alpha3,
                           alphas.alpha4, alphas.alpha5};
  std::string bad;
  for (int k = 0; k < 5; ++k) {
    if (!(std::isfinite(values[k]) && values[k] >= 0.0)) {
      std::ostringstream os;
      os << (bad.empty() ? "" : "; ") << "odom_alpha" << (k + 1) << "="
         << values[k] << " must be >= 0";
      bad += os.str();
    }
  }
  if (!bad.empty()) throw std::invalid_argument("invalid motion model: " + bad);
  if (type == "diff") return std::make_unique<DiffMotionModel>(alphas, false);
  if (type == "diff-corrected") {
    return std::make_unique<DiffMotionModel>(alphas, true);
  }
  if (type == "omni") return std::make_unique<OmniMotionModel>(alphas, false);
  if (type == "omni-corrected") {
    return std::make_unique<OmniMotionModel>(alphas, true);
  }
  throw std::invalid_argument("odom_model_type='" + type +
                              "' is not one of diff, diff-corrected, omni, "
                              "omni-corrected");
}

std::unique_ptr<MotionModel> CreateMotionModel(const AmclOptions& options) {
  OdomAlphas a;
  a.alpha1 = options.odom_alpha1;
  a.alpha2 = options.odom_alpha2;
  a.alpha3 = options.odom_alpha3;
  a.alpha4 = options.odom_alpha4;
  a.alpha5 = options.odom_alpha5;
  return CreateMotionModel(options.odom_model_type, a);
}

}  // namespace amcl
}  // namespace minibot3d_navigation
