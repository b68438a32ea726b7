// The frames of one robot among several on one tf tree (ROS-free; frames.h reads the parameters).
//
// Several robots share one /tf when the frames of each carry its name: robot NAME's are
// NAME/odom, NAME/base_footprint, NAME/laser, ... (tf2's convention, robot_state_publisher's
// tf_prefix), while the frames all robots share keep their names (by default the map, so that
// several localizers place their robots on one map). A node's frame parameters stay unprefixed,
// as the robot's config set gives them, so one config set serves every robot; the node resolves
// each frame parameter once, at start-up:
//
//   minibot3d_ros::FrameOptions frames;
//   report.Also(minibot3d_ros::LoadFrameOptions(pnh, &frames));  // frame_prefix, shared_frames
//   ...report.ThrowIfBad();
//   const minibot3d_ros::FrameNames names(frames);
//   node.base_frame_id = names.Resolve(node.base_frame_id);  // base_footprint -> r1/base_footprint
//
// frame_prefix and shared_frames are looked up from the node's private namespace upwards
// (ros::NodeHandle::searchParam), so setting them once in the robot's namespace
// (/NAME/frame_prefix: NAME) serves every node of that robot. Without frame_prefix every frame
// stays as it is.
//
// Resolve(frame): "" stays "" (no frame given: the message's own is used); "/name" is a full
// name, used as "name" and never prefixed (tf2 frame ids have no leading slash); a shared frame
// stays; any other frame becomes "PREFIX/frame".
#ifndef MINIBOT3D_ROS_FRAME_NAMES_H_
#define MINIBOT3D_ROS_FRAME_NAMES_H_

#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <string>
#include <vector>

#include "minibot3d_common/options.h"
#include "minibot3d_common/parameter_docs.h"

namespace minibot3d_ros {

struct FrameOptions {
  std::string frame_prefix;                      // "" : no prefix
  std::vector<std::string> shared_frames{"map"};  // frames no robot prefixes
};

inline const minibot3d_common::options::OptionTable<FrameOptions>& FrameOptionTable() {
  using minibot3d_common::options::Field;
  static const minibot3d_common::options::OptionTable<FrameOptions> table(
      "frames",
      {Field("frame_prefix", &FrameOptions::frame_prefix,
             "The robot's name on the tf tree shared by several robots: every frame parameter "
             "of the node (except those in shared_frames and those starting with /) is read as "
             "frame_prefix/frame, e.g. robot1/odom. Found in the node's namespace or the nearest "
             "one above it, so setting it once in the robot's namespace serves all its nodes; "
             "\"\": frames as given."),
       Field("shared_frames", &FrameOptions::shared_frames,
             "Frames every robot shares, never prefixed (found like frame_prefix): the map, so "
             "that each robot's localizer places it on one map. Empty for robots that map on "
             "their own (each has its own map frame, frame_prefix/map).")});
  return table;
}

// The "Robot frames" section of a node's page in docs/parameters/; `frames` names the node's
// frame parameters that take the prefix.
inline minibot3d_common::ParameterSection FrameOptionsSection(const std::string& frames) {
  return minibot3d_common::Section(
      "Robot frames",
      "For several robots on one tf tree: " + frames + " take the robot's name as a prefix. "
      "Both keys are looked up from the node's private namespace upwards, so they are usually "
      "set once in the robot's namespace (the launch files' `robot` argument does).",
      FrameOptionTable());
}

// "" when `prefix` is usable, else why not. A prefix is a ROS name (segments of letters,
// digits and underscores, each starting with a letter, joined by '/'); leading and trailing
// slashes are ignored.
inline std::string FramePrefixProblem(const std::string& prefix) {
  size_t b = prefix.find_first_not_of('/');
  if (b == std::string::npos) return "";  // "" or "/": no prefix
  const size_t e = prefix.find_last_not_of('/');
  const std::string p = prefix.substr(b, e - b + 1);
  size_t start = 0;
  while (start <= p.size()) {
    size_t end = p.find('/', start);
    if (end == std::string::npos) end = p.size();
    const std::string segment = p.substr(start, end - start);
    if (segment.empty()) return "'" + prefix + "' has an empty segment (two slashes)";
    if (!std::isalpha(static_cast<unsigned char>(segment[0]))) {
      return "'" + prefix + "' is not a ROS name: '" + segment + "' does not start with a letter";
    }
    for (char c : segment) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') {
        return "'" + prefix + "' is not a ROS name: '" + segment +
               "' holds a character other than letters, digits and _";
      }
    }
    start = end + 1;
  }
  return "";
}

// "" when every shared frame is usable, else why not.
inline std::string SharedFramesProblem(const std::vector<std::string>& frames) {
  for (const std::string& f : frames) {
    const size_t b = f.find_first_not_of('/');
    if (b == std::string::npos) return "a shared frame is empty";
    const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    if (std::any_of(f.begin(), f.end(), space)) return "shared frame '" + f + "' holds white space";
  }
  return "";
}

// Resolves a robot's frame names (see the file comment). ROS-free.
class FrameNames {
 public:
  FrameNames() = default;
  // Throws std::invalid_argument naming frame_prefix or shared_frames when one is unusable.
  explicit FrameNames(const FrameOptions& options) {
    const std::string p = FramePrefixProblem(options.frame_prefix);
    if (!p.empty()) throw std::invalid_argument("frame_prefix: " + p);
    const std::string s = SharedFramesProblem(options.shared_frames);
    if (!s.empty()) throw std::invalid_argument("shared_frames: " + s);
    const size_t b = options.frame_prefix.find_first_not_of('/');
    if (b != std::string::npos) {
      prefix_ = options.frame_prefix.substr(b, options.frame_prefix.find_last_not_of('/') - b + 1);
    }
    shared_.clear();
    for (const std::string& f : options.shared_frames) {
      shared_.push_back(f.substr(f.find_first_not_of('/')));
    }
  }

  // The robot's name on the tf tree ("" : none).
  const std::string& prefix() const { return prefix_; }
  const std::vector<std::string>& shared() const { return shared_; }

  std::string Resolve(const std::string& frame) const {
    if (frame.empty()) return frame;
    if (frame[0] == '/') return frame.substr(std::min(frame.find_first_not_of('/'), frame.size()));
    if (prefix_.empty() || std::find(shared_.begin(), shared_.end(), frame) != shared_.end()) {
      return frame;
    }
    return prefix_ + "/" + frame;
  }

 private:
  std::string prefix_;
  std::vector<std::string> shared_{"map"};
};

}  // namespace minibot3d_ros

#endif  // MINIBOT3D_ROS_FRAME_NAMES_H_
