// Reading a node's parameters through its components' option tables (minibot3d_common/options.h).
//
// A node names the namespace a component's keys live in (its private namespace, or
// ~TrajectoryPlannerROS, ~global_costmap, ...) and the component's table; every direct key of
// that namespace the table knows is parsed into the options struct, every bad value is collected
// (all of them, each with its full parameter name), and the keys that no table of the namespace
// knows are returned so the node can warn about them once: a misspelt parameter is reported, not
// silently ignored.
//
//   AmclOptions o;
//   minibot3d_ros::ParamReport r = minibot3d_ros::LoadTable(pnh, AmclOptionTable(), &o);
//   r.Also(minibot3d_ros::LoadTable(pnh, AmclNodeOptionTable(), &node));
//   r.WarnUnknown("amcl");
//   r.ThrowIfBad();
#ifndef MINIBOT3D_ROS_PARAMS_H_
#define MINIBOT3D_ROS_PARAMS_H_

#include <algorithm>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <ros/ros.h>

#include "minibot3d_common/options.h"

namespace minibot3d_ros {

// A parameter value as the text the option tables parse. Arrays become "[a, b, ...]"
// (footprints, lists); a struct in a list contributes its "name" member (move_base's
// recovery_behaviors: [{name: ..., type: ...}]). False for types a table cannot take (a struct).
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

// The direct keys of a namespace (sub-namespaces are not keys) with their values.
using NamedValues = std::vector<std::pair<std::string, XmlRpc::XmlRpcValue>>;

inline NamedValues DirectParams(const ros::NodeHandle& nh) {
  std::vector<std::string> names;
  nh.getParamNames(names);
  std::sort(names.begin(), names.end());
  const std::string prefix = nh.getNamespace() + "/";
  NamedValues out;
  std::set<std::string> seen;
  for (const std::string& full : names) {
    if (full.compare(0, prefix.size(), prefix) != 0) continue;
    std::string name = full.substr(prefix.size());
    const size_t slash = name.find('/');
    if (slash != std::string::npos) {
      // A sub-namespace: reported as a key (a struct) only once, so a table can claim it.
      name = name.substr(0, slash);
      if (!seen.insert(name).second) continue;
      XmlRpc::XmlRpcValue v;
      nh.getParam(name, v);
      out.emplace_back(name, v);
      continue;
    }
    if (!seen.insert(name).second) continue;
    XmlRpc::XmlRpcValue v;
    nh.getParam(name, v);
    out.emplace_back(name, v);
  }
  return out;
}

// What loading a namespace found: bad values (each "ns/name: why") and keys no table read.
struct ParamReport {
  std::string ns;
  std::vector<std::string> problems;
  std::set<std::string> keys;  // every key of the namespace
  std::set<std::string> read;  // the keys some table (or the node itself) took

  // Merges the report of another table over the same namespace.
  void Also(const ParamReport& other) {
    if (ns.empty()) ns = other.ns;
    problems.insert(problems.end(), other.problems.begin(), other.problems.end());
    keys.insert(other.keys.begin(), other.keys.end());
    read.insert(other.read.begin(), other.read.end());
  }
  // Marks a key the node reads outside the tables (a sub-namespace it walks itself).
  void Known(const std::string& key) { read.insert(key); }
  std::vector<std::string> Unknown() const {
    std::vector<std::string> out;
    for (const auto& k : keys) {
      if (!read.count(k)) out.push_back(k);
    }
    return out;
  }
  // One warning per key nobody reads.
  void WarnUnknown(const std::string& node) const {
    for (const auto& u : Unknown()) {
      ROS_WARN("%s: unknown parameter %s/%s (ignored; a misspelling?)", node.c_str(), ns.c_str(),
               u.c_str());
    }
  }
  // Throws std::invalid_argument listing every bad value, one per line.
  void ThrowIfBad() const {
    if (problems.empty()) return;
    std::string msg;
    for (const auto& p : problems) msg += (msg.empty() ? "" : "\n  ") + p;
    throw std::invalid_argument(msg);
  }
};

// Parses every value of `values` (the keys of namespace `ns`) that `table` knows into *options.
template <typename T>
ParamReport ApplyTable(const std::string& ns, const NamedValues& values,
                       const minibot3d_common::options::OptionTable<T>& table, T* options) {
  ParamReport report;
  report.ns = ns;
  for (const auto& kv : values) {
    report.keys.insert(kv.first);
    if (!table.Has(kv.first)) continue;
    report.read.insert(kv.first);
    std::string text;
    try {
      if (!XmlToText(kv.second, &text)) throw std::invalid_argument("unsupported parameter type");
      table.Set(kv.first, text, options);
    } catch (const std::invalid_argument& e) {
      report.problems.push_back(ns + "/" + kv.first + ": " + e.what());
    }
  }
  return report;
}

// ApplyTable on the parameters of nh's namespace.
template <typename T>
ParamReport LoadTable(const ros::NodeHandle& nh,
                      const minibot3d_common::options::OptionTable<T>& table, T* options) {
  return ApplyTable(nh.getNamespace(), DirectParams(nh), table, options);
}

}  // namespace minibot3d_ros

#endif  // MINIBOT3D_ROS_PARAMS_H_
