// Poses of the readings the filter did not process, from the processed ones around them: how
// slam_offline writes a pose for every reading of a log (and so how a trajectory is scored against
// relations that name any reading's time). No ROS here.
#ifndef MINIBOT3D_SLAM_BETWEEN_PROCESSED_H_
#define MINIBOT3D_SLAM_BETWEEN_PROCESSED_H_

#include "minibot3d_slam/types.h"

namespace minibot3d_slam {

// The pose of a reading between two processed ones: the first processed pose (`pose0`, odometry
// `odom0`) moved by the odometry increment to the reading's `odom`, plus the share of the gap at
// the second (where the filter put it, `*pose1`, against where that odometry puts it, from
// `*odom1`) proportional to how far the odometry had moved (translation + rotation; a reading at
// the second's odometry gets all of it). Without a second (pose1 and odom1 null: after the last
// processed reading) the odometry alone. Spread linearly in that measure: odometry errors grow
// with the motion (the motion model's assumption too), and a reading's own match
// (RbpfSlam::Localize) corrects what is left.
Pose2 PoseBetweenProcessed(const Pose2& pose0, const Pose2& odom0, const Pose2& odom,
                           const Pose2* pose1, const Pose2* odom1);

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_BETWEEN_PROCESSED_H_
