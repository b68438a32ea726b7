// Runs the SLAM core on the first scans of the Intel Research Lab log when the shared data set is
// present (../shared/datasets/intel/intel.clf beside the repository), and skips otherwise.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "minibot3d_slam/carmen_log.h"
#include "minibot3d_slam/rbpf_slam.h"

namespace minibot3d_slam {
namespace {

const std::string kIntelLog = std::string(MINIBOT3D_SLAM_SOURCE_DIR) + "/../../shared/datasets/intel/intel.clf";

TEST(IntelLogTest, FirstScansGiveASaneMapAndASmoothTrajectory) {
  if (!std::ifstream(kIntelLog).good()) GTEST_SKIP() << "Intel log absent: " << kIntelLog;
  const CarmenLog log = ReadCarmenLog(kIntelLog);
  ASSERT_EQ(log.scans.size(), 13631u);
  EXPECT_TRUE(log.warnings.empty());
  EXPECT_DOUBLE_EQ(log.scans[0].scan.range_max, 81.83);  // the saturation value was found
  GmappingOptions o;  // defaults: 30 particles
  RbpfSlam slam(o);
  const std::size_t n = 500;
  std::vector<Pose2> odom_at_processed;
  for (std::size_t i = 0; i < n; ++i) {
    if (slam.AddScan(log.scans[i].scan, log.scans[i].odom)) odom_at_processed.push_back(log.scans[i].odom);
  }
  EXPECT_GT(slam.processed_scans(), 10);
  const std::vector<StampedPose> traj = slam.BestTrajectory();
  ASSERT_EQ(static_cast<int>(traj.size()), slam.processed_scans());
  // Smooth: between consecutive processed scans (about linearUpdate = 1 m apart) the estimate
  // moves as the odometry does, give or take the odometry's error — no jumps.
  for (std::size_t i = 1; i < traj.size(); ++i) {
    const Pose2 step = Between(traj[i - 1].pose, traj[i].pose);
    const Pose2 odom_step = Between(odom_at_processed[i - 1], odom_at_processed[i]);
    EXPECT_LT(std::hypot(step.x, step.y), 1.5) << i;
    EXPECT_LT(std::hypot(step.x - odom_step.x, step.y - odom_step.y), 0.3)
        << "jump between processed scans " << i - 1 << " and " << i;
    EXPECT_LT(std::fabs(NormalizeAngle(step.yaw - odom_step.yaw)), 0.2) << i;
  }
  // The map has walls: a sane number of occupied cells, and many more free ones.
  const GridMap map = slam.Map();
  int occupied = 0, free_cells = 0;
  for (auto v : map.data) {
    occupied += v == 100;
    free_cells += v == 0;
  }
  EXPECT_GT(occupied, 1000);
  EXPECT_LT(occupied, 20000);
  EXPECT_GT(free_cells, 5 * occupied);
}

}  // namespace
}  // namespace minibot3d_slam
