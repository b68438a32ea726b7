#include "parameter_pages.h"

#include "minibot3d_sim/gazebo_plugins.h"
#include "minibot3d_sim/sim_node_options.h"

namespace minibot3d_sim {

using minibot3d_common::ParameterPage;
using minibot3d_common::Section;

std::vector<ParameterPage> ParameterPages() {
  std::vector<ParameterPage> pages;
  pages.push_back(ParameterPage{
      "simulator.md", "minibot3d_sim",
      "Private parameters of the `minibot3d_sim` node (`~name`); `minibot3d_gazebo.launch` sets "
      "them from its arguments. The robot comes from `robot_description` (its `<gazebo>` plugins: "
      "[robot_plugins.md](robot_plugins.md)). A key the node does not know is reported once at "
      "start-up; a bad value stops it with every offending parameter named.",
      {Section("Node", "The world, the robot's spawn pose, physics, time and lock-step.",
               SimNodeOptionTable()),
       Section("~NAME/ (each robot of ~robots)",
               "A robot's own spawn pose and odometry settings; each defaults to the node's "
               "parameter of the same name.",
               RobotNodeOptionTable())}});
  const std::string spawned =
      " Plugins without a `<robotNamespace>` get the simulator's `~robot_namespace` (`/`), as "
      "Gazebo's spawn_model gives them the spawner's.";
  pages.push_back(ParameterPage{
      "robot_plugins.md", "Robot description (Gazebo plugins)",
      "The `<gazebo>` blocks of `robot_description` the simulator reads, with the tag names and "
      "defaults of ROS Noetic's gazebo_ros_pkgs plugins (and ros_controllers' "
      "diff_drive_controller for `libgazebo_ros_control.so`). A tag, plugin or sensor not listed "
      "here is named once in a warning and ignored; a value out of range, a joint or link the URDF "
      "lacks, or a second drive plugin stops the simulator with a message naming it. A robot has "
      "exactly one drive plugin." + spawned + " Sensor tags are paths below `<sensor>` "
      "(`ray/range/max` is `<ray><range><max>`); an element's `type` attribute counts as a child.",
      {Section("libgazebo_ros_diff_drive.so",
               "`<gazebo><plugin>`: two driven wheels. The simulator's `~cmd_timeout` stops the "
               "robot when commands stop (the plugin has no timeout of its own).",
               DiffDriveTable()),
       Section("libgazebo_ros_skid_steer_drive.so",
               "`<gazebo><plugin>`: four wheels, both of a side alike. The odometry integrates the "
               "wheels' speeds (Gazebo's plugin reports the true pose); the simulator's "
               "`~odom_wheel_separation_multiplier` and `~cmd_wheel_separation_multiplier` "
               "calibrate the track for the slip of skid-steer turning.",
               SkidSteerDriveTable()),
       Section("libgazebo_ros_planar_move.so",
               "`<gazebo><plugin>`: a holonomic base moved at the commanded body velocity.",
               PlanarMoveTable()),
       Section("libgazebo_ros_control.so",
               "`<gazebo><plugin>`: the controllers are read from the parameter server under the "
               "plugin's namespace (every sub-namespace with a `type`): one "
               "`diff_drive_controller/DiffDriveController` and optionally a "
               "`joint_state_controller/JointStateController`; other types are named and ignored. "
               "Velocity joints are driven with their URDF effort limits.",
               RosControlTable()),
       Section("diff_drive_controller/DiffDriveController",
               "Under `<robotNamespace>/<controller>/`: commands on `<controller>/cmd_vel`, "
               "odometry on `<controller>/odom`. Nested keys are paths (`linear/x/max_velocity`).",
               DiffDriveControllerTable()),
       Section("joint_state_controller/JointStateController",
               "Under `<robotNamespace>/<controller>/`: `joint_states` at its rate.",
               JointStateControllerTable()),
       Section("<sensor type=\"ray\"> and <sensor type=\"gpu_ray\">",
               "In `<gazebo reference=\"link\">`: a planar laser, cast against the world's "
               "horizontal slice at the sensor's height; noise is seeded (`~seed`).",
               RaySensorTable()),
       Section("libgazebo_ros_laser.so and libgazebo_ros_gpu_laser.so",
               "Inside a ray sensor: publishes `sensor_msgs/LaserScan`. A ray sensor without it "
               "publishes nothing, as in Gazebo.",
               LaserPluginTable()),
       Section("<sensor type=\"imu\">", "In `<gazebo reference=\"link\">`; noise per axis.",
               ImuSensorTable()),
       Section("libgazebo_ros_imu_sensor.so",
               "Inside an imu sensor: `sensor_msgs/Imu` with gravity in the acceleration (+9.81 "
               "m/s² up at rest).",
               ImuSensorPluginTable()),
       Section("libgazebo_ros_imu.so",
               "`<gazebo><plugin>`: `sensor_msgs/Imu` of a link, acceleration without gravity.",
               ImuModelPluginTable()),
       Section("<sensor type=\"depth\"> and <sensor type=\"camera\">",
               "In `<gazebo reference=\"link\">`: ray cast against the full 3-D world; the camera "
               "looks along the link's +x.",
               CameraSensorTable()),
       Section("libgazebo_ros_openni_kinect.so, libgazebo_ros_depth_camera.so, "
               "libgazebo_ros_camera.so",
               "Inside a depth (or, for libgazebo_ros_camera.so, a camera) sensor: the depth image "
               "(32FC1), its CameraInfo and an organised PointCloud2, and a colour image flat-shaded "
               "by the models' material colours, in the plugin's topics below "
               "`<robotNamespace>/<cameraName>/`.",
               CameraPluginTable()),
       Section("libgazebo_ros_p3d.so", "`<gazebo><plugin>`: a link's true pose and velocity.",
               GroundTruthTable()),
       Section("libgazebo_ros_joint_state_publisher.so",
               "`<gazebo><plugin>`: accepted; the simulator publishes every movable joint on "
               "`joint_states` anyway.",
               JointStatePublisherTable())}});
  return pages;
}

}  // namespace minibot3d_sim
