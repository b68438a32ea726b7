// Moment tests for the odometry motion models: many particles start at the
// same pose, one odometry increment is applied, and the sample mean and
// variances are compared with values derived by hand from the model's noise
// formulas (motion_model.h).  Distinct alphas catch swapped coefficients.
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "minibot3d_navigation/amcl/motion_model.h"

namespace minibot3d_navigation {
namespace amcl {
namespace {

constexpr int kSamples = 200000;
constexpr double kRelTol = 0.03;  // "within a few %"

OdomAlphas DistinctAlphas() {
  OdomAlphas a;
  a.alpha1 = 0.10;
  a.alpha2 = 0.02;
  a.alpha3 = 0.05;
  a.alpha4 = 0.03;
  a.alpha5 = 0.04;
  return a;
}

// Sample moments of the particles' displacement expressed in the start
// pose's frame (forward / left), and of the yaw change.
struct Moments {
  double mean_fwd = 0, mean_left = 0, mean_dyaw = 0;
  double var_fwd = 0, var_left = 0, var_dyaw = 0;
};

Moments SampleMoments(const std::string& type, const OdomAlphas& alphas,
            const Pose2& start, const Pose2& old_odom,
            const Pose2& new_odom, uint64_t seed = 7) {
  auto model = CreateMotionModel(type, alphas);
  std::vector<Particle> particles(kSamples);
  for (Particle& p : particles) {
    p.pose = start;
    p.weight = 1.0 / kSamples;
  }
  std::mt19937_64 rng(seed);
  model->SamplePoses(old_odom, new_odom, &rng, &particles);
  Moments m;
  std::vector<Pose2> local(kSamples);
  for (int k = 0; k < kSamples; ++k) {
    local[k] = Between(start, particles[k].pose);
    m.mean_fwd += local[k].x;
    m.mean_left += local[k].y;
    m.mean_dyaw += local[k].yaw;
  }
  m.mean_fwd /= kSamples;
  m.mean_left /= kSamples;
  m.mean_dyaw /= kSamples;
  for (int k = 0; k < kSamples; ++k) {
    m.var_fwd += std::pow(local[k].x - m.mean_fwd, 2);
    m.var_left += std::pow(local[k].y - m.mean_left, 2);
    m.var_dyaw += std::pow(local[k].yaw - m.mean_dyaw, 2);
  }
  m.var_fwd /= kSamples - 1;
  m.var_left /= kSamples - 1;
  m.var_dyaw /= kSamples - 1;
  return m;
}

void ExpectRel(double actual, double expected, const char* what) {
  EXPECT_NEAR(actual, expected, kRelTol * std::fabs(expected))
      << what << ": actual " << actual << " expected " << expected;
}

// Odometry frame deliberately differs from the particle's map frame: only
// the increment, expressed in the robot frame, may matter.
const Pose2 kOldOdom{1.0, 2.0, 0.3};
const Pose2 kStart{3.0, -1.0, 1.2};

// For r ~ N(0, s^2): E[cos r], E[cos^2 r], E[sin^2 r].
double ECos(double s) { return std::exp(-s * s / 2); }
double ECos2(double s) { return 0.5 * (1 + std::exp(-2 * s * s)); }
double ESin2(double s) { return 0.5 * (1 - std::exp(-2 * s * s)); }

// Diff model, straight-line motion of length t: rot1 = rot2 = 0, so
// forward = T cos(R1), left = T sin(R1), dyaw = R1 + R2, with T ~ N(t, st^2),
// R1, R2 ~ N(0, sr^2) independent.  These are exact moments.
void CheckDiffStraight(const std::string& type, double t, double sr,
                       double st) {
  const Pose2 new_odom = Compose(kOldOdom, {t, 0.0, 0.0});
  const Moments m =
      SampleMoments(type, DistinctAlphas(), kStart, kOldOdom, new_odom);
  const double et2 = t * t + st * st;
  ExpectRel(m.mean_fwd, t * ECos(sr), "mean forward");
  EXPECT_NEAR(m.mean_left, 0.0, 5 * std::sqrt(et2 * ESin2(sr) / kSamples));
  EXPECT_NEAR(m.mean_dyaw, 0.0, 5 * std::sqrt(2 * sr * sr / kSamples));
  ExpectRel(m.var_fwd, et2 * ECos2(sr) - std::pow(t * ECos(sr), 2),
            "var forward");
  ExpectRel(m.var_left, et2 * ESin2(sr), "var left");
  ExpectRel(m.var_dyaw, 2 * sr * sr, "var yaw");
}

TEST(AmclMotionModelTest, DiffStraightUsesVarianceFormulaAsStdDev) {
  const double t = 0.5;
  const OdomAlphas a = DistinctAlphas();
  // ROS "diff": the book's variance expressions are used as std devs.
  CheckDiffStraight("diff", t, a.alpha2 * t * t, a.alpha3 * t * t);
}

TEST(AmclMotionModelTest, DiffCorrectedStraightUsesSqrtOfVariance) {
  const double t = 0.5;
  const OdomAlphas a = DistinctAlphas();
  CheckDiffStraight("diff-corrected", t, std::sqrt(a.alpha2 * t * t),
                    std::sqrt(a.alpha3 * t * t));
}

// In-place rotation: rot1 = 0 with zero noise (no translation), trans = 0
// with noise from alpha4 * rot2^2, rot2 = the turn with noise from alpha1.
TEST(AmclMotionModelTest, DiffCorrectedInPlaceRotation) {
  const double turn = 0.8;
  const OdomAlphas a = DistinctAlphas();
  const Moments m = SampleMoments("diff-corrected", a, kStart, kOldOdom,
                        Compose(kOldOdom, {0.0, 0.0, turn}));
  const double s_trans = std::sqrt(a.alpha4 * turn * turn);
  const double s_rot2 = std::sqrt(a.alpha1 * turn * turn);
  ExpectRel(m.mean_dyaw, turn, "mean yaw change");
  ExpectRel(m.var_dyaw, s_rot2 * s_rot2, "var yaw");
  // The (noisy, zero-mean) translation acts along the start heading.
  ExpectRel(m.var_fwd, s_trans * s_trans, "var forward");
  EXPECT_LT(m.var_left, 1e-20);
  EXPECT_NEAR(m.mean_fwd, 0.0, 5 * s_trans / std::sqrt(kSamples));
}

// General increment: rot1 = atan2(dy, dx), rot2 = dyaw - rot1; the yaw change
// is rot1_hat + rot2_hat so its variance is the sum of both rot variances.
TEST(AmclMotionModelTest, DiffCorrectedGeneralIncrementYawMoments) {
  const Pose2 local{0.4, 0.1, 0.3};
  const OdomAlphas a = DistinctAlphas();
  const Moments m =
      SampleMoments("diff-corrected", a, kStart, kOldOdom,
                    Compose(kOldOdom, local));
  const double t = std::hypot(local.x, local.y);
  const double rot1 = std::atan2(local.y, local.x);
  const double rot2 = local.yaw - rot1;
  const double v1 = a.alpha1 * rot1 * rot1 + a.alpha2 * t * t;
  const double v2 = a.alpha1 * rot2 * rot2 + a.alpha2 * t * t;
  ExpectRel(m.mean_dyaw, local.yaw, "mean yaw change");
  ExpectRel(m.var_dyaw, v1 + v2, "var yaw");
  // Mean end point: t * E[cos R1] along rot1 (R1 noise shrinks the mean).
  const double s1 = std::sqrt(v1);
  ExpectRel(m.mean_fwd, t * ECos(s1) * std::cos(rot1), "mean forward");
  ExpectRel(m.mean_left, t * ECos(s1) * std::sin(rot1), "mean left");
}

// Reversing: rot1 = pi but its noise magnitude is min(|rot1|, |pi-rot1|) = 0,
// so the yaw noise comes from alpha2 * t^2 only and the robot moves back.
TEST(AmclMotionModelTest, DiffBackwardMotionIsNotAHalfTurn) {
  const double t = 0.3;
  const OdomAlphas a = DistinctAlphas();
  const Moments m = SampleMoments("diff-corrected", a, kStart, kOldOdom,
                        Compose(kOldOdom, {-t, 0.0, 0.0}));
  const double sr = std::sqrt(a.alpha2 * t * t);
  ExpectRel(m.mean_fwd, -t * ECos(sr), "mean forward");
  EXPECT_NEAR(m.mean_dyaw, 0.0, 5 * std::sqrt(2 * sr * sr / kSamples));
  ExpectRel(m.var_dyaw, 2 * sr * sr, "var yaw");
}

// Omni: displacement along the (deterministic) bearing of travel with noise
// trans_hat, perpendicular strafe noise, yaw noise rot_hat; all linear, so
// along/cross-track and yaw variances are exactly the squared std devs.
void CheckOmni(const std::string& type, double sd_trans, double sd_rot,
               double sd_strafe, const Pose2& local) {
  const Moments m =
      SampleMoments(type, DistinctAlphas(), kStart, kOldOdom,
                    Compose(kOldOdom, local));
  const double bearing = std::atan2(local.y, local.x);
  // Along-track (va) and cross-track (vc) noises are independent, so in the
  // start frame var_fwd = c^2 va + s^2 vc and var_left = s^2 va + c^2 vc.
  const double c = std::cos(bearing), s = std::sin(bearing);
  const double va = sd_trans * sd_trans, vc = sd_strafe * sd_strafe;
  ExpectRel(m.mean_fwd, local.x, "mean forward");
  ExpectRel(m.mean_left, local.y, "mean left");
  ExpectRel(m.mean_dyaw, local.yaw, "mean yaw change");
  ExpectRel(m.var_fwd, c * c * va + s * s * vc, "var forward");
  ExpectRel(m.var_left, s * s * va + c * c * vc, "var left");
  ExpectRel(m.var_dyaw, sd_rot * sd_rot, "var yaw");
}

TEST(AmclMotionModelTest, OmniMoments) {
  const Pose2 local{0.3, 0.2, 0.4};
  const OdomAlphas a = DistinctAlphas();
  const double t2 = local.x * local.x + local.y * local.y;
  const double r2 = local.yaw * local.yaw;
  CheckOmni("omni", a.alpha3 * t2 + a.alpha1 * r2,
            a.alpha4 * r2 + a.alpha2 * t2, a.alpha1 * r2 + a.alpha5 * t2,
            local);
}

TEST(AmclMotionModelTest, OmniCorrectedMoments) {
  const Pose2 local{0.3, 0.2, 0.4};
  const OdomAlphas a = DistinctAlphas();
  const double t2 = local.x * local.x + local.y * local.y;
  const double r2 = local.yaw * local.yaw;
  CheckOmni("omni-corrected", std::sqrt(a.alpha3 * t2 + a.alpha4 * r2),
            std::sqrt(a.alpha1 * r2 + a.alpha2 * t2),
            std::sqrt(a.alpha4 * r2 + a.alpha5 * t2), local);
}

TEST(AmclMotionModelTest, ZeroAlphasAreDeterministicAndExact) {
  OdomAlphas zero{0, 0, 0, 0, 0};
  const Pose2 local{0.4, -0.15, -0.7};
  for (const char* type :
       {"diff", "diff-corrected", "omni", "omni-corrected"}) {
    auto model = CreateMotionModel(type, zero);
    std::vector<Particle> p(1);
    p[0].pose = kStart;
    std::mt19937_64 rng(1);
    model->SamplePoses(kOldOdom, Compose(kOldOdom, local), &rng, &p);
    const Pose2 expected = Compose(kStart, local);
    EXPECT_NEAR(p[0].pose.x, expected.x, 1e-12) << type;
    EXPECT_NEAR(p[0].pose.y, expected.y, 1e-12) << type;
    EXPECT_NEAR(AngleDiff(p[0].pose.yaw, expected.yaw), 0.0, 1e-12) << type;
    EXPECT_EQ(model->name(), type);
  }
}

TEST(AmclMotionModelTest, FactoryRejectsUnknownTypeAndNegativeAlpha) {
  EXPECT_THROW(CreateMotionModel("ackermann", DistinctAlphas()),
               std::invalid_argument);
  OdomAlphas bad = DistinctAlphas();
  bad.alpha3 = -0.1;
  try {
    CreateMotionModel("diff", bad);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("odom_alpha3=-0.1"), std::string::npos)
        << e.what();
  }
  AmclOptions o;
  o.odom_model_type = "omni-corrected";
  EXPECT_EQ(CreateMotionModel(o)->name(), "omni-corrected");
}

}  // namespace
}  // namespace amcl
}  // namespace minibot3d_navigation
