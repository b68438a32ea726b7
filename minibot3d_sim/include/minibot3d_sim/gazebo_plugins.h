// The Gazebo plugins and sensors the simulator takes from a robot description, each as an options
// struct read through an option table with Gazebo's own tag names and defaults (gazebo_ros_pkgs'
// noetic plugins; ros_controllers' diff_drive_controller for gazebo_ros_control). The same tables
// write the plugin reference in docs/parameters/robot_plugins.md.
//
// A sensor's SDF is read by path: <ray><scan><horizontal><samples> is "ray/scan/horizontal/samples";
// an element's "type" attribute counts as a "type" child (<noise type="gaussian">).
#ifndef MINIBOT3D_SIM_GAZEBO_PLUGINS_H_
#define MINIBOT3D_SIM_GAZEBO_PLUGINS_H_

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "minibot3d_common/options.h"

namespace minibot3d_sim {

namespace options = minibot3d_common::options;

// ---------------------------------------------------------------------------------------------
// Drive plugins: exactly one per robot.

// libgazebo_ros_skid_steer_drive.so: four wheels, both of a side turning alike.
struct SkidSteerDriveOptions {
  std::string robot_namespace;
  std::string left_front_joint = "left_front_joint";
  std::string right_front_joint = "right_front_joint";
  std::string left_rear_joint = "left_rear_joint";
  std::string right_rear_joint = "right_rear_joint";
  double wheel_separation = 0.4;  // m
  double wheel_diameter = 0.15;   // m
  double torque = 5.0;            // N m per wheel
  std::string command_topic = "cmd_vel";
  std::string odometry_topic = "odom";
  std::string odometry_frame = "odom";
  std::string robot_base_frame = "base_footprint";
  double update_rate = 100.0;  // Hz
  bool broadcast_tf = false;
  double covariance_x = 0.0001, covariance_y = 0.0001, covariance_yaw = 0.01;
};
const options::OptionTable<SkidSteerDriveOptions>& SkidSteerDriveTable();

// libgazebo_ros_diff_drive.so: two wheels.
struct DiffDriveOptions {
  std::string robot_namespace;
  std::string left_joint = "left_joint";
  std::string right_joint = "right_joint";
  double wheel_separation = 0.34;    // m
  double wheel_diameter = 0.15;      // m
  double wheel_acceleration = 0.0;   // m/s^2 of rim speed, 0: none
  double wheel_torque = 5.0;         // N m
  std::string command_topic = "cmd_vel";
  std::string odometry_topic = "odom";
  std::string odometry_frame = "odom";
  std::string robot_base_frame = "base_footprint";
  std::string odometry_source = "world";  // world | encoder
  bool publish_tf = true;
  bool publish_odom_tf = true;
  bool publish_wheel_tf = false;
  bool publish_wheel_joint_state = false;
  double update_rate = 100.0;  // Hz
  std::string ros_debug_level = "na";
  bool legacy_mode = false;
};
const options::OptionTable<DiffDriveOptions>& DiffDriveTable();

// libgazebo_ros_planar_move.so: a holonomic base moved at the commanded body velocity.
struct PlanarMoveOptions {
  std::string robot_namespace;
  std::string command_topic = "cmd_vel";
  std::string odometry_topic = "odom";
  std::string odometry_frame = "odom";
  std::string robot_base_frame = "base_footprint";
  double odometry_rate = 20.0;  // Hz, <= 0: no odometry
  double cmd_timeout = -1.0;    // s, < 0: none
};
const options::OptionTable<PlanarMoveOptions>& PlanarMoveTable();

// libgazebo_ros_control.so: the controllers come from the parameter server.
struct RosControlOptions {
  std::string robot_namespace;
  std::string robot_param = "robot_description";
  std::string robot_sim_type = "gazebo_ros_control/DefaultRobotHWSim";
  double control_period = 0.0;  // s, 0: the physics step
  bool legacy_mode_ns = false;
  std::string e_stop_topic;
};
const options::OptionTable<RosControlOptions>& RosControlTable();

// ros_controllers' diff_drive_controller/DiffDriveController, under <namespace>/<controller>/.
struct DiffDriveControllerOptions {
  std::string type;
  std::vector<std::string> left_wheel, right_wheel;
  double wheel_separation = 0.0;  // m, 0: from the URDF
  double wheel_radius = 0.0;      // m, 0: from the URDF
  double wheel_separation_multiplier = 1.0;
  double wheel_radius_multiplier = 1.0;
  double left_wheel_radius_multiplier = 1.0;
  double right_wheel_radius_multiplier = 1.0;
  std::vector<std::string> pose_covariance_diagonal, twist_covariance_diagonal;
  double publish_rate = 50.0;  // Hz
  bool open_loop = false;
  int velocity_rolling_window_size = 10;
  double cmd_vel_timeout = 0.5;  // s
  bool allow_multiple_cmd_vel_publishers = true;
  std::string base_frame_id = "base_link";
  std::string odom_frame_id = "odom";
  bool enable_odom_tf = true;
  bool publish_cmd = false;
  bool estimate_velocity_from_position = true;
  // Limits of linear/x and angular/z (SpeedLimiter); an unset min is -max.
  bool linear_has_velocity_limits = false, linear_has_acceleration_limits = false,
       linear_has_jerk_limits = false;
  double linear_max_velocity = 0.0, linear_min_velocity = NAN, linear_max_acceleration = 0.0,
         linear_min_acceleration = NAN, linear_max_jerk = 0.0, linear_min_jerk = NAN;
  bool angular_has_velocity_limits = false, angular_has_acceleration_limits = false,
       angular_has_jerk_limits = false;
  double angular_max_velocity = 0.0, angular_min_velocity = NAN, angular_max_acceleration = 0.0,
         angular_min_acceleration = NAN, angular_max_jerk = 0.0, angular_min_jerk = NAN;
};
const options::OptionTable<DiffDriveControllerOptions>& DiffDriveControllerTable();

// joint_state_controller/JointStateController.
struct JointStateControllerOptions {
  std::string type;
  double publish_rate = 0.0;  // Hz; required
  std::vector<std::string> extra_joints;
};
const options::OptionTable<JointStateControllerOptions>& JointStateControllerTable();

enum class DriveKind { kSkidSteer, kDiffDrive, kPlanarMove, kDiffDriveController };

struct DrivePluginSpec {
  DriveKind kind = DriveKind::kSkidSteer;
  std::string plugin_name;  // <plugin name="...">
  std::string filename;     // <plugin filename="...">
  std::string robot_namespace;  // as given or injected (spawn namespace)
  SkidSteerDriveOptions skid_steer;
  DiffDriveOptions diff_drive;
  PlanarMoveOptions planar_move;
  RosControlOptions ros_control;
  std::string controller_name;  // the diff_drive_controller's namespace
  DiffDriveControllerOptions controller;
  std::string joint_state_controller_name;  // empty: none configured
  JointStateControllerOptions joint_state_controller;
};

// ---------------------------------------------------------------------------------------------
// Sensors. Pose of the sensor: <pose> relative to the link of <gazebo reference="link">.

// <sensor type="ray"> / <sensor type="gpu_ray">.
struct RaySensorOptions {
  std::string pose = "0 0 0 0 0 0";
  double update_rate = 0.0;  // Hz, 0: every physics step
  bool always_on = false;
  bool visualize = false;
  std::string topic;
  int samples = 640;
  double resolution = 1.0;
  double min_angle = 0.0, max_angle = 0.0;    // rad
  int vertical_samples = 1;
  double vertical_resolution = 1.0;
  double vertical_min_angle = 0.0, vertical_max_angle = 0.0;
  double range_min = 0.0, range_max = 0.0;    // m
  double range_resolution = 0.0;              // m
  std::string noise_type;
  double noise_mean = 0.0, noise_stddev = 0.0;
};
const options::OptionTable<RaySensorOptions>& RaySensorTable();

// libgazebo_ros_laser.so / libgazebo_ros_gpu_laser.so on a ray sensor.
struct LaserPluginOptions {
  std::string robot_namespace;
  std::string topic_name = "/world";
  std::string frame_name = "/world";
  double gaussian_noise = 0.0;  // hokuyo-era tag, not read by Gazebo's plugin
  double update_rate = 0.0;     // idem
};
const options::OptionTable<LaserPluginOptions>& LaserPluginTable();

struct LaserSpec {
  std::string sensor_name;
  std::string link;                   // the URDF link it is attached to
  std::string frame_id;               // <frameName>, as given
  std::string topic;                  // <topicName>, as given
  std::string robot_namespace;
  Eigen::Isometry3d pose_in_root = Eigen::Isometry3d::Identity();  // ray origin (link ∘ <pose>)
  Eigen::Isometry3d link_in_root = Eigen::Isometry3d::Identity();  // the frame_id's frame
  int samples = 360;
  double min_angle = -M_PI, max_angle = M_PI;
  double min_range = 0.15, max_range = 12.0;
  double resolution = 0.01;  // range quantisation (m), 0: none
  double update_rate = 10.0;
  double noise_mean = 0.0, noise_stddev = 0.0;
};

// <sensor type="imu">.
struct ImuSensorOptions {
  std::string pose = "0 0 0 0 0 0";
  double update_rate = 0.0;
  bool always_on = false;
  bool visualize = false;
  std::string topic;
  // Gaussian noise of each axis of the rates (rad/s) and accelerations (m/s^2): mean, stddev and
  // the bias drawn once at start (its sign flipped with probability 1/2, as Gazebo does).
  double av_x_mean = 0, av_x_stddev = 0, av_x_bias_mean = 0, av_x_bias_stddev = 0;
  double av_y_mean = 0, av_y_stddev = 0, av_y_bias_mean = 0, av_y_bias_stddev = 0;
  double av_z_mean = 0, av_z_stddev = 0, av_z_bias_mean = 0, av_z_bias_stddev = 0;
  double la_x_mean = 0, la_x_stddev = 0, la_x_bias_mean = 0, la_x_bias_stddev = 0;
  double la_y_mean = 0, la_y_stddev = 0, la_y_bias_mean = 0, la_y_bias_stddev = 0;
  double la_z_mean = 0, la_z_stddev = 0, la_z_bias_mean = 0, la_z_bias_stddev = 0;
  // Each axis's noise type: gaussian, or empty for none.
  std::string av_x_type, av_y_type, av_z_type, la_x_type, la_y_type, la_z_type;
};

// The two IMU plugins: libgazebo_ros_imu_sensor.so (on an imu sensor) and libgazebo_ros_imu.so
// (a model plugin naming its link).
struct ImuPluginOptions {
  std::string robot_namespace;
  std::string topic_name;
  std::string service_name = "/default_imu";
  std::string frame_name;
  std::string body_name;
  double update_rate = 0.0;     // libgazebo_ros_imu.so <updateRate> (Hz, 0: every step)
  double update_rate_hz = 1.0;  // libgazebo_ros_imu_sensor.so <updateRateHZ>
  double gaussian_noise = 0.0;
  std::string xyz_offset = "0 0 0";
  std::string rpy_offset = "0 0 0";
  bool initial_orientation_as_reference = false;
};
const options::OptionTable<ImuSensorOptions>& ImuSensorTable();
const options::OptionTable<ImuPluginOptions>& ImuModelPluginTable();
const options::OptionTable<ImuPluginOptions>& ImuSensorPluginTable();

struct ImuSpec {
  std::string name;
  std::string link;
  std::string frame_id;
  std::string topic;
  std::string robot_namespace;
  Eigen::Isometry3d pose_in_root = Eigen::Isometry3d::Identity();  // the IMU frame
  double update_rate = 0.0;  // Hz, 0: every physics step
  bool gravity = true;       // the sensor plugin reports specific force (+g at rest)
  double gaussian_noise = 0.0;
  ImuSensorOptions noise;    // per-axis SDF noise (sensor plugin)
  Eigen::Quaterniond orientation_offset = Eigen::Quaterniond::Identity();
  bool initial_orientation_as_reference = false;
};

// <sensor type="depth"> / <sensor type="camera">.
struct CameraSensorOptions {
  std::string pose = "0 0 0 0 0 0";
  double update_rate = 0.0;
  bool always_on = false;
  bool visualize = false;
  std::string topic;
  std::string camera_name;
  double horizontal_fov = 1.047;  // rad
  int width = 320, height = 240;
  std::string format = "R8G8B8";
  double clip_near = 0.1, clip_far = 100.0;  // m
  std::string noise_type;
  double noise_mean = 0.0, noise_stddev = 0.0;
};
const options::OptionTable<CameraSensorOptions>& CameraSensorTable();

// libgazebo_ros_camera.so, libgazebo_ros_depth_camera.so, libgazebo_ros_openni_kinect.so.
struct CameraPluginOptions {
  std::string robot_namespace;
  std::string camera_name;
  std::string image_topic_name = "image_raw";
  std::string camera_info_topic_name = "camera_info";
  std::string depth_image_topic_name = "depth/image_raw";
  std::string depth_image_camera_info_topic_name = "depth/camera_info";
  std::string point_cloud_topic_name = "points";
  std::string frame_name;
  double update_rate = 0.0;  // Hz, 0: the sensor's
  double point_cloud_cutoff = 0.4;       // m
  double point_cloud_cutoff_max = -1.0;  // m, < 0: none (openni_kinect: 5)
  double focal_length = 0.0, cx = 0.0, cy = 0.0, cx_prime = 0.0;
  double hack_baseline = 0.0;
  double distortion_k1 = 0.0, distortion_k2 = 0.0, distortion_k3 = 0.0, distortion_t1 = 0.0,
         distortion_t2 = 0.0;
  bool border_crop = true;
};
const options::OptionTable<CameraPluginOptions>& CameraPluginTable();

struct CameraSpec {
  std::string name;
  std::string plugin;  // libgazebo_ros_camera.so, ..._depth_camera.so, ..._openni_kinect.so
  bool depth = false;
  std::string link;
  std::string robot_namespace;
  Eigen::Isometry3d pose_in_root = Eigen::Isometry3d::Identity();  // Gazebo camera frame (+x ahead)
  CameraSensorOptions sensor;
  CameraPluginOptions ros;
  double update_rate = 0.0;  // effective, Hz
};

// libgazebo_ros_p3d.so: a link's true pose and velocity.
struct GroundTruthOptions {
  std::string robot_namespace;
  std::string body_name;
  std::string topic_name;
  std::string frame_name = "world";
  std::string xyz_offset = "0 0 0";
  std::string rpy_offset = "0 0 0";
  double gaussian_noise = 0.0;
  double update_rate = 0.0;  // Hz, 0: every physics step
};
const options::OptionTable<GroundTruthOptions>& GroundTruthTable();

struct GroundTruthSpec {
  GroundTruthOptions options;
  std::string robot_namespace;
  Eigen::Isometry3d link_in_root = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
  // frame_name as a link of this robot (empty: the world).
  std::string reference_link;
  Eigen::Isometry3d reference_in_root = Eigen::Isometry3d::Identity();
};

// libgazebo_ros_joint_state_publisher.so.
struct JointStatePublisherOptions {
  std::string robot_namespace;
  std::string joint_name;  // comma-separated
  double update_rate = 100.0;
};
const options::OptionTable<JointStatePublisherOptions>& JointStatePublisherTable();

struct JointStatePublisherSpec {
  std::string robot_namespace;
  std::vector<std::string> joints;
  double update_rate = 100.0;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_GAZEBO_PLUGINS_H_
