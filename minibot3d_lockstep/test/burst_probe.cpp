// Test participant for test_lockstep_loop.py: the C++ side of lockstep_probe.py's burst. Joins,
// lets 0.5 s of sim time pass, then publishes 1..N on /probe_burst (std_msgs/UInt32) in one tick
// through a publisher whose queue holds 1 message, prints "burst T", lets 0.5 s more pass and
// leaves.
//
//   burst_probe N
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include <ros/ros.h>
#include <std_msgs/UInt32.h>

#include "minibot3d_lockstep/participant.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "burst_probe");
  const long n = argc > 1 ? std::atol(argv[1]) : 0;
  if (n <= 0) {
    std::fprintf(stderr, "usage: burst_probe N\n");
    return 2;
  }
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<std_msgs::UInt32>("/probe_burst", 1);
  minibot3d_lockstep::Participant lockstep(nh, minibot3d_lockstep::ParticipantOptions());
  int calls = 0;  // the job runs at its first tick, 0.5 s later (the burst) and 1 s later
  lockstep.AddPeriodic(0.5, [&](const ros::Time& now) {
    ++calls;
    if (calls == 2) {
      for (long i = 1; i <= n; ++i) {
        std_msgs::UInt32 m;
        m.data = static_cast<std::uint32_t>(i);
        pub.publish(m);
      }
      std::printf("burst %.3f\n", now.toSec());
      std::fflush(stdout);
    } else if (calls == 3) {
      lockstep.Leave();
      ros::shutdown();
    }
  });
  return lockstep.Spin() ? 0 : 1;
}
