// Reads a node's frame_prefix and shared_frames (frame_names.h) from the parameter server.
#ifndef MINIBOT3D_ROS_FRAMES_H_
#define MINIBOT3D_ROS_FRAMES_H_

#include <string>

#include <ros/ros.h>

#include "minibot3d_ros/frame_names.h"
#include "minibot3d_ros/params.h"

namespace minibot3d_ros {

// Reads frame_prefix and shared_frames, each from the nearest namespace that has it, searching
// from nh's namespace upwards. The report names each bad value by its full parameter name and
// counts both keys as read (a private ~frame_prefix is no misspelt key).
inline ParamReport LoadFrameOptions(const ros::NodeHandle& nh, FrameOptions* options) {
  ParamReport report;
  report.ns = nh.getNamespace();
  for (const std::string& name : FrameOptionTable().Names()) {
    report.Known(name);
    std::string key;
    XmlRpc::XmlRpcValue value;
    if (!nh.searchParam(name, key) || !nh.getParam(key, value)) continue;
    const std::string ns = key.substr(0, key.rfind('/'));
    const ParamReport one = ApplyTable(ns, {{name, value}}, FrameOptionTable(), options);
    report.problems.insert(report.problems.end(), one.problems.begin(), one.problems.end());
    if (!one.problems.empty()) continue;
    const std::string why = name == "frame_prefix" ? FramePrefixProblem(options->frame_prefix)
                                                   : SharedFramesProblem(options->shared_frames);
    if (!why.empty()) report.problems.push_back(key + ": " + why);
  }
  return report;
}

}  // namespace minibot3d_ros

#endif  // MINIBOT3D_ROS_FRAMES_H_
