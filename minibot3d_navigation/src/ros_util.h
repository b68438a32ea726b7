// Conversions shared by the navigation nodes (amcl, move_base): parameter
// values to the text the ROS-free option tables parse, tf <-> Pose2, and
// OccupancyGrid messages to the core's grid.  Node-side only (includes ROS).
#ifndef MINIBOT3D_NAVIGATION_SRC_ROS_UTIL_H_
#define MINIBOT3D_NAVIGATION_SRC_ROS_UTIL_H_

#include <functional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <tf2/LinearMath/Quaternion.h>
#include <tf2/LinearMath/Transform.h>
#include <tf2/utils.h>

#include "minibot3d_navigation/amcl/occupancy_map.h"
#include "minibot3d_navigation/amcl/types.h"

namespace minibot3d_navigation {
namespace ros_util {

// XmlRpc parameter value -> the text the option tables parse.  Arrays become
// "[a, b, ...]" (footprints, recovery lists); a struct in a list contributes its
// "name" member (move_base's recovery_behaviors: [{name: ..., type: ...}]).
inline bool XmlToText(const XmlRpc::XmlRpcValue& value, std::string* out) {
  XmlRpc::XmlRpcValue& v = const_cast<XmlRpc::XmlRpcValue&>(value);
  std::ostringstream s;
  s.precision(17);
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      *out = static_cast<bool>(v) ? "true" : "false";
      return true;
    case XmlRpc::XmlRpcValue::TypeInt:
      s << static_cast<int>(v);
      break;
    case XmlRpc::XmlRpcValue::TypeDouble:
      s << static_cast<double>(v);
      break;
    case XmlRpc::XmlRpcValue::TypeString:
      s << static_cast<std::string>(v);
      break;
    case XmlRpc::XmlRpcValue::TypeArray: {
      s << "[";
      for (int i = 0; i < v.size(); ++i) {
        std::string item;
        if (v[i].getType() == XmlRpc::XmlRpcValue::TypeStruct && v[i].hasMember("name")) {
          if (!XmlToText(v[i]["name"], &item)) return false;
        } else if (!XmlToText(v[i], &item)) {
          return false;
        }
        s << (i ? ", " : "") << item;
      }
      s << "]";
      break;
    }
    default:
      return false;
  }
  *out = s.str();
  return true;
}

// Loads every parameter of `nh`'s namespace that `has(name)` accepts through
// `set(name, text)` (which throws std::invalid_argument on bad text).  Returns
// the problems found ("~ns/name: message").  Keys of that namespace that no
// table knows (and that are not listed in `also_known` or are sub-namespaces)
// are returned in *unknown so the node can warn about misspellings.
inline std::vector<std::string> LoadParams(
    const ros::NodeHandle& nh, const std::function<bool(const std::string&)>& has,
    const std::function<void(const std::string&, const std::string&)>& set,
    std::vector<std::string>* loaded = nullptr) {
  std::vector<std::string> problems;
  std::vector<std::string> names;
  nh.getParamNames(names);
  const std::string prefix = nh.getNamespace() + "/";
  for (const std::string& full : names) {
    if (full.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string name = full.substr(prefix.size());
    if (name.find('/') != std::string::npos || !has(name)) continue;
    XmlRpc::XmlRpcValue v;
    nh.getParam(name, v);
    std::string text;
    try {
      if (!XmlToText(v, &text)) throw std::invalid_argument("unsupported parameter type");
      set(name, text);
      if (loaded) loaded->push_back(name);
    } catch (const std::invalid_argument& e) {
      problems.push_back(full + ": " + e.what());
    }
  }
  return problems;
}

// Direct keys of nh's namespace (no sub-namespaces) for which known(name) is
// false: the misspellings a user should hear about.
inline std::vector<std::string> UnknownParams(
    const ros::NodeHandle& nh, const std::function<bool(const std::string&)>& known) {
  std::vector<std::string> names, out;
  nh.getParamNames(names);
  const std::string prefix = nh.getNamespace() + "/";
  std::set<std::string> seen;
  for (const std::string& full : names) {
    if (full.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string name = full.substr(prefix.size());
    if (name.find('/') != std::string::npos) continue;
    if (!known(name) && seen.insert(name).second) out.push_back(full);
  }
  return out;
}

inline amcl::Pose2 PoseFromTf(const tf2::Transform& t) {
  return {t.getOrigin().x(), t.getOrigin().y(), tf2::getYaw(t.getRotation())};
}

inline tf2::Transform TfFromPose(const amcl::Pose2& p) {
  tf2::Quaternion q;
  q.setRPY(0, 0, p.yaw);
  return tf2::Transform(q, tf2::Vector3(p.x, p.y, 0.0));
}

inline amcl::OccupancyGrid GridFromMsg(const nav_msgs::OccupancyGrid& m) {
  amcl::OccupancyGrid g;
  g.resolution = m.info.resolution;
  g.origin_x = m.info.origin.position.x;
  g.origin_y = m.info.origin.position.y;
  g.origin_theta = tf2::getYaw(m.info.origin.orientation);
  g.width = static_cast<int>(m.info.width);
  g.height = static_cast<int>(m.info.height);
  g.data.assign(m.data.begin(), m.data.end());
  return g;
}

}  // namespace ros_util
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_SRC_ROS_UTIL_H_
