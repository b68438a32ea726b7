// Test participant for test_lockstep_loop.py: checks that a participant ticked only every 2 s of
// sim time has every /tf message in its buffer. lockstep_probe.py zigzag publishes
// probe_parent -> probe_zigzag every 10 ms at x = +1 and -1 in turn; at each of its ticks this
// node looks the transform up at every 10 ms stamp of the last 1.9 s and counts the lookups that
// do not give that stamp's own value (a dropped message: interpolated between its neighbours, or
// no transform at all).
//
//   tf_listener_probe lockstep|tf2_ros ROUNDS
//     lockstep: minibot3d_lockstep::TransformListener; tf2_ros: tf2_ros::TransformListener on the
//     participant's tf node handle, as a node would make it. Prints
//     "tf_probe MODE checked N wrong M" after ROUNDS ticks and leaves.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "minibot3d_lockstep/participant.h"
#include "minibot3d_lockstep/transform_listener.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "tf_listener_probe");
  ros::NodeHandle nh;
  const std::string mode = argc > 1 ? argv[1] : "";
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 0;
  if ((mode != "lockstep" && mode != "tf2_ros") || rounds <= 0) {
    std::fprintf(stderr, "usage: tf_listener_probe lockstep|tf2_ros ROUNDS\n");
    return 2;
  }
  minibot3d_lockstep::Participant lockstep(nh, minibot3d_lockstep::ParticipantOptions());
  tf2_ros::Buffer buffer;
  std::unique_ptr<minibot3d_lockstep::TransformListener> ours;
  std::unique_ptr<tf2_ros::TransformListener> theirs;
  if (mode == "lockstep") {
    ours = std::make_unique<minibot3d_lockstep::TransformListener>(buffer, lockstep);
  } else {
    theirs = std::make_unique<tf2_ros::TransformListener>(buffer, lockstep.tf_node_handle(),
                                                          !lockstep.enabled());
  }
  int done = 0;
  long checked = 0, wrong = 0;
  lockstep.AddPeriodic(2.0, [&](const ros::Time& now) {
    if (now.toSec() > 2.5) {  // the zigzag has been publishing for a while
      // Its samples are stamped with its ticks, on the same grid as this node's: now - 10 ms * j.
      for (int j = 5; j <= 195; ++j) {
        const ros::Time stamp = now - ros::Duration(0.01 * j);
        const double expected = std::lround(stamp.toSec() * 100.0) % 2 == 0 ? 1.0 : -1.0;
        ++checked;
        try {
          const auto t = buffer.lookupTransform("probe_parent", "probe_zigzag", stamp);
          if (std::fabs(t.transform.translation.x - expected) > 1e-9) ++wrong;
        } catch (const tf2::TransformException&) {
          ++wrong;
        }
      }
      ++done;
    }
    if (done >= rounds) {
      std::printf("tf_probe %s checked %ld wrong %ld\n", mode.c_str(), checked, wrong);
      std::fflush(stdout);
      lockstep.Leave();
      ros::shutdown();
    }
  });
  lockstep.Spin();
  return 0;
}
