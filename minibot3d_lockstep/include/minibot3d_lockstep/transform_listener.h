// tf2_ros::TransformListener for a lock-step participant.
//
//   minibot3d_lockstep::Participant lockstep(nh, options);
//   minibot3d_lockstep::TransformListener tf(buffer, lockstep);
//
// tf2_ros's listener keeps at most 100 /tf messages waiting for its callback. A participant runs
// its callbacks only at its ticks, and one woken once a second receives a few hundred /tf
// messages in between (the simulator's odometry at 100 Hz, SLAM's map->odom, the wheels from
// robot_state_publisher): the oldest were dropped, and which ones depended on how the publishers'
// messages interleaved on arrival, a wall-clock matter. A lookup that fell between the survivors
// then interpolated between other samples in another run. Under lock-step this listener keeps
// every message until the tick (an unbounded queue on the participant's tf queue), so the buffer
// holds the same transforms in every run. With lock-step off it is tf2_ros's listener with its
// own spinning thread, as before.
#ifndef MINIBOT3D_LOCKSTEP_TRANSFORM_LISTENER_H
#define MINIBOT3D_LOCKSTEP_TRANSFORM_LISTENER_H

#include <memory>

#include <ros/message_event.h>
#include <ros/subscriber.h>
#include <ros/time.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "minibot3d_lockstep/participant.h"

namespace minibot3d_lockstep {

class TransformListener {
 public:
  TransformListener(tf2_ros::Buffer& buffer, Participant& participant);
  TransformListener(const TransformListener&) = delete;
  TransformListener& operator=(const TransformListener&) = delete;

 private:
  void OnTf(const ros::MessageEvent<tf2_msgs::TFMessage const>& event, bool is_static);

  tf2_ros::Buffer& buffer_;
  std::unique_ptr<tf2_ros::TransformListener> plain_;  // lock-step off
  ros::Subscriber tf_sub_, static_sub_;
  ros::Time last_update_;
};

}  // namespace minibot3d_lockstep

#endif  // MINIBOT3D_LOCKSTEP_TRANSFORM_LISTENER_H
