// The simulated robot, as read from a URDF with Gazebo extension tags.
//
// urdfdom gives the kinematic tree, link masses and collision geometry; the <gazebo> blocks give
// what Gazebo's ROS plugins would have read, with the plugins' own tag names and defaults: one drive
// plugin (skid-steer, diff-drive, planar-move, or gazebo_ros_control with a diff_drive_controller
// configured on the parameter server), per-link wheel friction (mu1, mu2, kp, kd), and any number of
// sensors (ray / gpu_ray lasers, IMUs, depth and colour cameras, ground truth). Each plugin and
// sensor reads its tags through an option table (gazebo_plugins.h), which also writes the plugin
// reference of the docs; a tag no table reads is named once in a warning.
//
// The model is taken at zero joint positions: a mobile base whose wheels and casters turn about
// their axles keeps its shape.
#ifndef MINIBOT3D_SIM_ROBOT_MODEL_H_
#define MINIBOT3D_SIM_ROBOT_MODEL_H_

#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "minibot3d_sim/gazebo_plugins.h"
#include "minibot3d_sim/world.h"

namespace minibot3d_sim {

class RobotModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A driven wheel.
struct WheelSpec {
  std::string joint;                                   // e.g. front_left_wheel_hinge
  std::string link;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // wheel centre in the root frame (m)
  bool left = true;                                    // on the robot's left (+y) side
  double radius = 0.0;
  double width = 0.0;
  double mass = 0.0;
  double inertia_axle = 0.0;    // moment of inertia about the axle (kg m^2)
  double mu1 = 1.0, mu2 = 1.0;  // friction along / across the rolling direction
  double kp = 1e6, kd = 1.0;    // contact stiffness / damping (Gazebo/ODE meaning)
  double effort_limit = 0.0;    // from <limit effort>, N m (0: none given)
  double velocity_limit = 0.0;  // from <limit velocity>, rad/s (0: none given)
  double torque = 0.0;          // the motor's torque limit the drive sets (N m)
};

// A link touching the floor that is not driven (a caster ball or wheel): it carries load, not
// traction.
struct SupportPoint {
  std::string link;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // root frame (m)
};

// One collision shape of one link, in the root frame at zero joint positions.
struct CollisionShape {
  std::string link;
  Shape shape;  // its pose is the root frame's, not the world's
  // Extent seen from above (convex, root frame, counter-clockwise) and in height.
  std::vector<Eigen::Vector2d> outline;
  double z_min = 0.0, z_max = 0.0;
};

// A movable joint robot_state_publisher needs a state for.
struct JointSpec {
  std::string name;
  std::string type;  // revolute, continuous, prismatic
};

struct RobotModel {
  std::string name;
  std::string root_link;  // usually base_footprint
  double total_mass = 0.0;
  // Yaw inertia of the whole robot about the vertical axis through the root (kg m^2).
  double body_inertia_z = 0.0;
  // Everything but the driven wheels as one box in the root frame (the body's extent).
  Eigen::Vector3d body_size = Eigen::Vector3d::Zero();
  Eigen::Isometry3d body_pose = Eigen::Isometry3d::Identity();
  double body_mass = 0.0;
  std::vector<WheelSpec> wheels;  // in the drive plugin's order
  std::vector<SupportPoint> supports;
  std::vector<CollisionShape> collisions;
  std::vector<JointSpec> joints;
  // Root-frame pose of every link at zero joint positions.
  std::map<std::string, Eigen::Isometry3d> link_poses;
  // Convex outline of every collision shape seen from above, root frame, counter-clockwise.
  std::vector<Eigen::Vector2d> footprint;

  DrivePluginSpec drive;
  std::vector<LaserSpec> lasers;
  std::vector<ImuSpec> imus;
  std::vector<CameraSpec> cameras;
  std::vector<GroundTruthSpec> ground_truths;
  std::vector<JointStatePublisherSpec> joint_state_publishers;

  // Non-fatal findings (a tag or plugin nothing reads), one line each, to be logged once.
  std::vector<std::string> warnings;

  // Root-frame pose of a link; throws RobotModelError naming it when there is none.
  const Eigen::Isometry3d& LinkPose(const std::string& link) const;
  bool HasLink(const std::string& link) const { return link_poses.count(link) > 0; }
};

// One piece of the robot's body as the physics backends see it: a collision shape's outline from
// above (convex, root frame, counter-clockwise) over its height band above the floor.
struct BodyPart {
  std::string link;
  std::vector<Eigen::Vector2d> outline;
  double z_min = 0.0, z_max = 0.0;
};

// Height (m) under which obstacles pass below the robot (its wheels climb them): a quarter of the
// smallest wheel radius, at least 5 mm.
double FloorClearance(const RobotModel& robot);

// Every link's collision shapes as body parts, each band starting at FloorClearance; a shape that
// lies wholly below it is left out. A model without collision shapes (made by hand) gives one part:
// its footprint (or body box) over the body's and wheels' height.
std::vector<BodyPart> BodyParts(const RobotModel& robot);

// Where gazebo_ros_control's controllers are configured: for each controller namespace under
// the robot's namespace, its keys as text (nested keys joined with '/', e.g. "linear/x/max_velocity";
// lists as "[a, b]"). The simulator node fills it from the parameter server.
using ControllerParams = std::map<std::string, std::map<std::string, std::string>>;

// ControllerParams from a YAML file laid out as the parameter server holds it (the controllers'
// namespaces at its top, as control.yaml files are loaded into the robot's namespace). Throws
// RobotModelError naming the file.
ControllerParams LoadControllerParams(const std::string& yaml_path);

struct RobotModelOptions {
  // The namespace given to every plugin without a <robotNamespace>, as Gazebo's spawn_model does;
  // to every plugin when replace_namespaces (spawn_model -robot_namespace: one robot of several).
  std::string spawn_namespace = "/";
  bool replace_namespaces = false;
  // Controllers on the parameter server (gazebo_ros_control only).
  ControllerParams controllers;
  // Turns a collision mesh's URL into a file path; empty: package:// through ROS_PACKAGE_PATH,
  // file:// and plain paths as they are.
  std::function<std::string(const std::string& url)> resolve_mesh_url;
};

// Parses an expanded URDF document. Throws RobotModelError naming the tag, link, joint or plugin
// at fault (no drive plugin, two drive plugins, a joint or link the URDF lacks, a camera wider than
// 2^15 pixels, a mesh that will not load, a controller missing its wheels, ...).
RobotModel ParseRobotModel(const std::string& urdf_xml,
                           const RobotModelOptions& options = RobotModelOptions());

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_ROBOT_MODEL_H_
