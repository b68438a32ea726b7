#include "minibot3d_sim/gazebo_plugins.h"

namespace minibot3d_sim {

using options::Field;
using options::OptionTable;

const OptionTable<SkidSteerDriveOptions>& SkidSteerDriveTable() {
  using O = SkidSteerDriveOptions;
  static const OptionTable<O> t(
      "libgazebo_ros_skid_steer_drive.so",
      {Field("robotNamespace", &O::robot_namespace,
             "Namespace of the plugin's topics (missing: the spawn namespace, usually /)."),
       Field("leftFrontJoint", &O::left_front_joint, "Left front wheel joint."),
       Field("rightFrontJoint", &O::right_front_joint, "Right front wheel joint."),
       Field("leftRearJoint", &O::left_rear_joint, "Left rear wheel joint."),
       Field("rightRearJoint", &O::right_rear_joint, "Right rear wheel joint."),
       Field("wheelSeparation", &O::wheel_separation,
             "Distance between the left and right wheels (m), used for the wheel speeds and the "
             "odometry."),
       Field("wheelDiameter", &O::wheel_diameter, "Wheel diameter (m)."),
       Field("torque", &O::torque, "Largest torque of each wheel's motor (N m)."),
       Field("commandTopic", &O::command_topic, "geometry_msgs/Twist command (linear.x, angular.z)."),
       Field("odometryTopic", &O::odometry_topic, "nav_msgs/Odometry output."),
       Field("odometryFrame", &O::odometry_frame, "Frame of the odometry (header.frame_id)."),
       Field("robotBaseFrame", &O::robot_base_frame,
             "Frame the odometry tracks (child_frame_id); a link of the URDF."),
       Field("updateRate", &O::update_rate,
             "Rate of the wheel commands and the odometry (Hz); 0: every physics step."),
       Field("broadcastTF", &O::broadcast_tf, "Publish odometryFrame -> robotBaseFrame on /tf."),
       Field("covariance_x", &O::covariance_x, "Odometry pose and twist variance of x."),
       Field("covariance_y", &O::covariance_y, "Odometry pose and twist variance of y."),
       Field("covariance_yaw", &O::covariance_yaw, "Odometry pose and twist variance of yaw.")});
  return t;
}

const OptionTable<DiffDriveOptions>& DiffDriveTable() {
  using O = DiffDriveOptions;
  static const OptionTable<O> t(
      "libgazebo_ros_diff_drive.so",
      {Field("robotNamespace", &O::robot_namespace,
             "Namespace of the plugin's topics (missing: the spawn namespace, usually /)."),
       Field("leftJoint", &O::left_joint, "Left wheel joint."),
       Field("rightJoint", &O::right_joint, "Right wheel joint."),
       Field("wheelSeparation", &O::wheel_separation, "Distance between the wheels (m)."),
       Field("wheelDiameter", &O::wheel_diameter, "Wheel diameter (m)."),
       Field("wheelAcceleration", &O::wheel_acceleration,
             "Largest change of a wheel's rim speed (m/s^2) while the commanded speed is not "
             "reached, as the plugin ramps it; 0: none."),
       Field("wheelTorque", &O::wheel_torque, "Largest torque of each wheel's motor (N m)."),
       Field("commandTopic", &O::command_topic, "geometry_msgs/Twist command (linear.x, angular.z)."),
       Field("odometryTopic", &O::odometry_topic, "nav_msgs/Odometry output."),
       Field("odometryFrame", &O::odometry_frame, "Frame of the odometry."),
       Field("robotBaseFrame", &O::robot_base_frame, "Frame the odometry tracks; a link of the URDF."),
       Field("odometrySource", &O::odometry_source,
             "world: the true pose and velocity; encoder: integrated from the wheel joints' "
             "speeds every physics step (drifts when the wheels slip)."),
       Field("publishTf", &O::publish_tf,
             "Publish odometry at all (false: neither the topic nor the transform)."),
       Field("publishOdomTF", &O::publish_odom_tf, "Publish odometryFrame -> robotBaseFrame on /tf."),
       Field("publishWheelTF", &O::publish_wheel_tf,
             "Publish each wheel's transform from its joint's parent link on /tf."),
       Field("publishWheelJointState", &O::publish_wheel_joint_state,
             "Publish the wheel joints' positions on joint_states."),
       Field("updateRate", &O::update_rate,
             "Rate of the wheel commands and the odometry (Hz); 0: every physics step."),
       Field("rosDebugLevel", &O::ros_debug_level, "Accepted; logging levels are rosconsole's."),
       Field("legacyMode", &O::legacy_mode,
             "Accepted and ignored, as in ROS Noetic's plugin (true warns: swap leftJoint and "
             "rightJoint if the robot turns the wrong way).")});
  return t;
}

const OptionTable<PlanarMoveOptions>& PlanarMoveTable() {
  using O = PlanarMoveOptions;
  static const OptionTable<O> t(
      "libgazebo_ros_planar_move.so",
      {Field("robotNamespace", &O::robot_namespace,
             "Namespace of the plugin's topics (missing: the spawn namespace, usually /)."),
       Field("commandTopic", &O::command_topic,
             "geometry_msgs/Twist command: linear.x, linear.y (m/s) and angular.z (rad/s) in the "
             "body frame."),
       Field("odometryTopic", &O::odometry_topic, "nav_msgs/Odometry output (the true pose)."),
       Field("odometryFrame", &O::odometry_frame, "Frame of the odometry."),
       Field("robotBaseFrame", &O::robot_base_frame, "Frame the odometry tracks; a link of the URDF."),
       Field("odometryRate", &O::odometry_rate,
             "Rate of the odometry and its transform (Hz); <= 0: neither is published."),
       Field("cmdTimeout", &O::cmd_timeout,
             "A command older than this (s) stops the robot; < 0: commands never expire.")});
  return t;
}

const OptionTable<RosControlOptions>& RosControlTable() {
  using O = RosControlOptions;
  static const OptionTable<O> t(
      "libgazebo_ros_control.so",
      {Field("robotNamespace", &O::robot_namespace,
             "Namespace of the controllers' parameters and topics (missing: the spawn namespace)."),
       Field("robotParam", &O::robot_param, "Parameter holding the URDF (accepted)."),
       Field("robotSimType", &O::robot_sim_type,
             "Hardware interface; only gazebo_ros_control/DefaultRobotHWSim (velocity-controlled "
             "joints) is simulated."),
       Field("controlPeriod", &O::control_period,
             "Period of the controllers' update (s); 0: every physics step."),
       Field("legacyModeNS", &O::legacy_mode_ns, "Accepted and ignored (PID gains are not used)."),
       Field("eStopTopic", &O::e_stop_topic, "Accepted and ignored.")});
  return t;
}

const OptionTable<DiffDriveControllerOptions>& DiffDriveControllerTable() {
  using O = DiffDriveControllerOptions;
  static const OptionTable<O> t(
      "diff_drive_controller/DiffDriveController",
      {Field("type", &O::type, "diff_drive_controller/DiffDriveController."),
       Field("left_wheel", &O::left_wheel, "Left wheel joint(s): a name or a list; required."),
       Field("right_wheel", &O::right_wheel, "Right wheel joint(s), as many as left; required."),
       Field("wheel_separation", &O::wheel_separation,
             "Distance between the wheels (m); 0/unset: between the first left and right wheel "
             "joints' origins in the URDF."),
       Field("wheel_radius", &O::wheel_radius,
             "Wheel radius (m); 0/unset: the first left wheel link's cylinder or sphere collision."),
       Field("wheel_separation_multiplier", &O::wheel_separation_multiplier,
             "Effective separation = wheel_separation x this (skid-steer bases calibrate it)."),
       Field("wheel_radius_multiplier", &O::wheel_radius_multiplier,
             "Effective radius = wheel_radius x this; when set it overrides both per-side ones."),
       Field("left_wheel_radius_multiplier", &O::left_wheel_radius_multiplier,
             "Left wheels' radius multiplier."),
       Field("right_wheel_radius_multiplier", &O::right_wheel_radius_multiplier,
             "Right wheels' radius multiplier."),
       Field("pose_covariance_diagonal", &O::pose_covariance_diagonal,
             "Six numbers: the odometry pose covariance's diagonal; required."),
       Field("twist_covariance_diagonal", &O::twist_covariance_diagonal,
             "Six numbers: the odometry twist covariance's diagonal; required."),
       Field("publish_rate", &O::publish_rate, "Rate of the odometry and its transform (Hz)."),
       Field("open_loop", &O::open_loop,
             "Integrate the limited command instead of the wheel joints' positions."),
       Field("velocity_rolling_window_size", &O::velocity_rolling_window_size,
             "Velocity estimates averaged for the odometry's twist."),
       Field("cmd_vel_timeout", &O::cmd_vel_timeout,
             "A command older than this (s) is taken as zero (the limits then ramp the robot "
             "down)."),
       Field("allow_multiple_cmd_vel_publishers", &O::allow_multiple_cmd_vel_publishers,
             "false: brake while more than one node publishes commands."),
       Field("base_frame_id", &O::base_frame_id, "Frame the odometry tracks."),
       Field("odom_frame_id", &O::odom_frame_id, "Frame of the odometry."),
       Field("enable_odom_tf", &O::enable_odom_tf, "Publish odom_frame_id -> base_frame_id on /tf."),
       Field("publish_cmd", &O::publish_cmd,
             "Publish the limited command as geometry_msgs/TwistStamped on cmd_vel_out."),
       Field("estimate_velocity_from_position", &O::estimate_velocity_from_position,
             "Accepted (the twist is always estimated from the wheel positions)."),
       Field("linear/x/has_velocity_limits", &O::linear_has_velocity_limits,
             "Clamp the forward speed."),
       Field("linear/x/has_acceleration_limits", &O::linear_has_acceleration_limits,
             "Limit the forward acceleration."),
       Field("linear/x/has_jerk_limits", &O::linear_has_jerk_limits, "Limit the forward jerk."),
       Field("linear/x/max_velocity", &O::linear_max_velocity, "Largest forward speed (m/s)."),
       Field("linear/x/min_velocity", &O::linear_min_velocity,
             "Smallest forward speed (m/s); unset: -max_velocity."),
       Field("linear/x/max_acceleration", &O::linear_max_acceleration,
             "Largest forward acceleration (m/s^2)."),
       Field("linear/x/min_acceleration", &O::linear_min_acceleration,
             "Smallest forward acceleration (m/s^2); unset: -max_acceleration."),
       Field("linear/x/max_jerk", &O::linear_max_jerk, "Largest forward jerk (m/s^3)."),
       Field("linear/x/min_jerk", &O::linear_min_jerk,
             "Smallest forward jerk (m/s^3); unset: -max_jerk."),
       Field("angular/z/has_velocity_limits", &O::angular_has_velocity_limits,
             "Clamp the yaw rate."),
       Field("angular/z/has_acceleration_limits", &O::angular_has_acceleration_limits,
             "Limit the yaw acceleration."),
       Field("angular/z/has_jerk_limits", &O::angular_has_jerk_limits, "Limit the yaw jerk."),
       Field("angular/z/max_velocity", &O::angular_max_velocity, "Largest yaw rate (rad/s)."),
       Field("angular/z/min_velocity", &O::angular_min_velocity,
             "Smallest yaw rate (rad/s); unset: -max_velocity."),
       Field("angular/z/max_acceleration", &O::angular_max_acceleration,
             "Largest yaw acceleration (rad/s^2)."),
       Field("angular/z/min_acceleration", &O::angular_min_acceleration,
             "Smallest yaw acceleration (rad/s^2); unset: -max_acceleration."),
       Field("angular/z/max_jerk", &O::angular_max_jerk, "Largest yaw jerk (rad/s^3)."),
       Field("angular/z/min_jerk", &O::angular_min_jerk,
             "Smallest yaw jerk (rad/s^3); unset: -max_jerk.")});
  return t;
}

const OptionTable<JointStateControllerOptions>& JointStateControllerTable() {
  using O = JointStateControllerOptions;
  static const OptionTable<O> t(
      "joint_state_controller/JointStateController",
      {Field("type", &O::type, "joint_state_controller/JointStateController."),
       Field("publish_rate", &O::publish_rate,
             "Rate of joint_states (Hz); required, <= 0 publishes nothing."),
       Field("extra_joints", &O::extra_joints, "Accepted; names of joints published at 0.")});
  return t;
}

const OptionTable<RaySensorOptions>& RaySensorTable() {
  using O = RaySensorOptions;
  static const OptionTable<O> t(
      "<sensor type=\"ray\"> / <sensor type=\"gpu_ray\">",
      {Field("pose", &O::pose, "x y z roll pitch yaw of the sensor in its link (m, rad)."),
       Field("update_rate", &O::update_rate, "Scans per second of sim time; 0: every physics step."),
       Field("always_on", &O::always_on, "Accepted (scans are always taken)."),
       Field("visualize", &O::visualize, "Accepted (no GUI)."),
       Field("topic", &O::topic, "Accepted (Gazebo transport topic; the ROS plugin's topicName counts)."),
       Field("ray/scan/horizontal/samples", &O::samples, "Beams per scan."),
       Field("ray/scan/horizontal/resolution", &O::resolution,
             "Ranges per beam; only 1 is simulated (other values are an error)."),
       Field("ray/scan/horizontal/min_angle", &O::min_angle, "Bearing of the first beam (rad)."),
       Field("ray/scan/horizontal/max_angle", &O::max_angle, "Bearing of the last beam (rad)."),
       Field("ray/scan/vertical/samples", &O::vertical_samples,
             "Rows of beams; only 1 is simulated (planar lasers)."),
       Field("ray/scan/vertical/resolution", &O::vertical_resolution, "Accepted with one row."),
       Field("ray/scan/vertical/min_angle", &O::vertical_min_angle, "Accepted with one row."),
       Field("ray/scan/vertical/max_angle", &O::vertical_max_angle, "Accepted with one row."),
       Field("ray/range/min", &O::range_min,
             "Shortest range (m); closer returns read -inf (REP 117)."),
       Field("ray/range/max", &O::range_max,
             "Longest range (m); beams with no return within it read +inf."),
       Field("ray/range/resolution", &O::range_resolution,
             "Ranges are rounded to multiples of it (m); 0: not rounded."),
       Field("ray/noise/type", &O::noise_type, "gaussian (the only kind), or empty for none."),
       Field("ray/noise/mean", &O::noise_mean, "Mean of the noise added to every return (m)."),
       Field("ray/noise/stddev", &O::noise_stddev,
             "Standard deviation of the noise (m); seeded by the simulator's ~seed.")});
  return t;
}

const OptionTable<LaserPluginOptions>& LaserPluginTable() {
  using O = LaserPluginOptions;
  static const OptionTable<O> t(
      "libgazebo_ros_laser.so / libgazebo_ros_gpu_laser.so",
      {Field("robotNamespace", &O::robot_namespace,
             "Namespace of topicName (missing: the spawn namespace, usually /)."),
       Field("topicName", &O::topic_name, "sensor_msgs/LaserScan output."),
       Field("frameName", &O::frame_name, "header.frame_id of the scans (a leading / is dropped)."),
       Field("gaussianNoise", &O::gaussian_noise,
             "Accepted and ignored, as by Gazebo (the sensor's <noise> counts)."),
       Field("updateRate", &O::update_rate,
             "Accepted and ignored, as by Gazebo (the sensor's <update_rate> counts).")});
  return t;
}

const OptionTable<ImuSensorOptions>& ImuSensorTable() {
  using O = ImuSensorOptions;
  static const OptionTable<O> t(
      "<sensor type=\"imu\">",
      {Field("pose", &O::pose, "x y z roll pitch yaw of the IMU in its link (m, rad)."),
       Field("update_rate", &O::update_rate, "Samples per second; 0: every physics step."),
       Field("always_on", &O::always_on, "Accepted."),
       Field("visualize", &O::visualize, "Accepted."),
       Field("topic", &O::topic, "Accepted (Gazebo transport topic)."),
       Field("imu/angular_velocity/x/noise/type", &O::av_x_type, "gaussian, or empty for none."),
       Field("imu/angular_velocity/y/noise/type", &O::av_y_type, "gaussian, or empty for none."),
       Field("imu/angular_velocity/z/noise/type", &O::av_z_type, "gaussian, or empty for none."),
       Field("imu/linear_acceleration/x/noise/type", &O::la_x_type, "gaussian, or empty for none."),
       Field("imu/linear_acceleration/y/noise/type", &O::la_y_type, "gaussian, or empty for none."),
       Field("imu/linear_acceleration/z/noise/type", &O::la_z_type, "gaussian, or empty for none."),
       Field("imu/angular_velocity/x/noise/mean", &O::av_x_mean, "Rate noise mean, x (rad/s)."),
       Field("imu/angular_velocity/x/noise/stddev", &O::av_x_stddev, "Rate noise stddev, x (rad/s)."),
       Field("imu/angular_velocity/x/noise/bias_mean", &O::av_x_bias_mean, "Rate bias mean, x (rad/s)."),
       Field("imu/angular_velocity/x/noise/bias_stddev", &O::av_x_bias_stddev,
             "Rate bias stddev, x (rad/s); the bias is drawn once."),
       Field("imu/angular_velocity/y/noise/mean", &O::av_y_mean, "Rate noise mean, y (rad/s)."),
       Field("imu/angular_velocity/y/noise/stddev", &O::av_y_stddev, "Rate noise stddev, y (rad/s)."),
       Field("imu/angular_velocity/y/noise/bias_mean", &O::av_y_bias_mean, "Rate bias mean, y (rad/s)."),
       Field("imu/angular_velocity/y/noise/bias_stddev", &O::av_y_bias_stddev, "Rate bias stddev, y (rad/s)."),
       Field("imu/angular_velocity/z/noise/mean", &O::av_z_mean, "Rate noise mean, z (rad/s)."),
       Field("imu/angular_velocity/z/noise/stddev", &O::av_z_stddev, "Rate noise stddev, z (rad/s)."),
       Field("imu/angular_velocity/z/noise/bias_mean", &O::av_z_bias_mean, "Rate bias mean, z (rad/s)."),
       Field("imu/angular_velocity/z/noise/bias_stddev", &O::av_z_bias_stddev, "Rate bias stddev, z (rad/s)."),
       Field("imu/linear_acceleration/x/noise/mean", &O::la_x_mean, "Acceleration noise mean, x (m/s^2)."),
       Field("imu/linear_acceleration/x/noise/stddev", &O::la_x_stddev,
             "Acceleration noise stddev, x (m/s^2)."),
       Field("imu/linear_acceleration/x/noise/bias_mean", &O::la_x_bias_mean,
             "Acceleration bias mean, x (m/s^2)."),
       Field("imu/linear_acceleration/x/noise/bias_stddev", &O::la_x_bias_stddev,
             "Acceleration bias stddev, x (m/s^2)."),
       Field("imu/linear_acceleration/y/noise/mean", &O::la_y_mean, "Acceleration noise mean, y (m/s^2)."),
       Field("imu/linear_acceleration/y/noise/stddev", &O::la_y_stddev,
             "Acceleration noise stddev, y (m/s^2)."),
       Field("imu/linear_acceleration/y/noise/bias_mean", &O::la_y_bias_mean,
             "Acceleration bias mean, y (m/s^2)."),
       Field("imu/linear_acceleration/y/noise/bias_stddev", &O::la_y_bias_stddev,
             "Acceleration bias stddev, y (m/s^2)."),
       Field("imu/linear_acceleration/z/noise/mean", &O::la_z_mean, "Acceleration noise mean, z (m/s^2)."),
       Field("imu/linear_acceleration/z/noise/stddev", &O::la_z_stddev,
             "Acceleration noise stddev, z (m/s^2)."),
       Field("imu/linear_acceleration/z/noise/bias_mean", &O::la_z_bias_mean,
             "Acceleration bias mean, z (m/s^2)."),
       Field("imu/linear_acceleration/z/noise/bias_stddev", &O::la_z_bias_stddev,
             "Acceleration bias stddev, z (m/s^2).")});
  return t;
}

const OptionTable<ImuPluginOptions>& ImuSensorPluginTable() {
  using O = ImuPluginOptions;
  static const OptionTable<O> t(
      "libgazebo_ros_imu_sensor.so",
      {Field("robotNamespace", &O::robot_namespace,
             "Namespace of topicName (missing: the spawn namespace, usually /)."),
       Field("topicName", &O::topic_name, "sensor_msgs/Imu output (empty: imu_data)."),
       Field("frameName", &O::frame_name, "header.frame_id; required."),
       Field("bodyName", &O::body_name, "Accepted and ignored (the sensor's link counts)."),
       Field("updateRateHZ", &O::update_rate_hz,
             "Rate of the messages (Hz), on top of the sensor's update_rate."),
       Field("gaussianNoise", &O::gaussian_noise,
             "Standard deviation of noise added to the rates, accelerations and orientation "
             "quaternion's components."),
       Field("xyzOffset", &O::xyz_offset, "Accepted (position is not reported)."),
       Field("rpyOffset", &O::rpy_offset, "Rotation (rad) applied to the reported orientation."),
       Field("initialOrientationAsReference", &O::initial_orientation_as_reference,
             "Report the orientation relative to the sensor's first one instead of the world "
             "(REP 145).")});
  return t;
}

const OptionTable<ImuPluginOptions>& ImuModelPluginTable() {
  using O = ImuPluginOptions;
  static const OptionTable<O> t(
      "libgazebo_ros_imu.so",
      {Field("robotNamespace", &O::robot_namespace,
             "Namespace of topicName (missing: the spawn namespace, usually /)."),
       Field("bodyName", &O::body_name, "The link the IMU is on; required."),
       Field("topicName", &O::topic_name, "sensor_msgs/Imu output (empty: /default_imu)."),
       Field("serviceName", &O::service_name, "Calibration service (accepted, not served)."),
       Field("frameName", &O::frame_name, "header.frame_id (empty: bodyName)."),
       Field("updateRate", &O::update_rate, "Rate of the messages (Hz); 0: every physics step."),
       Field("gaussianNoise", &O::gaussian_noise,
             "Standard deviation of noise added to the rates and accelerations."),
       Field("xyzOffset", &O::xyz_offset, "Accepted (position is not reported)."),
       Field("rpyOffset", &O::rpy_offset, "Rotation (rad) applied to the reported orientation."),
       Field("updateRateHZ", &O::update_rate_hz, "Accepted (the sensor plugin's tag).")});
  return t;
}

const OptionTable<CameraSensorOptions>& CameraSensorTable() {
  using O = CameraSensorOptions;
  static const OptionTable<O> t(
      "<sensor type=\"depth\"> / <sensor type=\"camera\">",
      {Field("pose", &O::pose,
             "x y z roll pitch yaw of the camera in its link (m, rad); it looks along its +x."),
       Field("update_rate", &O::update_rate, "Frames per second of sim time; 0: every physics step."),
       Field("always_on", &O::always_on, "Accepted (frames are always taken)."),
       Field("visualize", &O::visualize, "Accepted (no GUI)."),
       Field("topic", &O::topic, "Accepted (Gazebo transport topic)."),
       Field("camera/name", &O::camera_name, "Accepted."),
       Field("camera/horizontal_fov", &O::horizontal_fov, "Horizontal field of view (rad), in (0, pi)."),
       Field("camera/image/width", &O::width, "Image width (pixels), 1 .. 32768."),
       Field("camera/image/height", &O::height, "Image height (pixels), 1 .. 32768."),
       Field("camera/image/format", &O::format,
             "R8G8B8, B8G8R8 or L8 (the colour image's encoding rgb8, bgr8 or mono8)."),
       Field("camera/clip/near", &O::clip_near, "Nearest distance seen (m)."),
       Field("camera/clip/far", &O::clip_far, "Farthest distance seen (m)."),
       Field("camera/noise/type", &O::noise_type, "gaussian, or empty for none."),
       Field("camera/noise/mean", &O::noise_mean, "Mean of the noise added to every depth (m)."),
       Field("camera/noise/stddev", &O::noise_stddev, "Standard deviation of the depth noise (m).")});
  return t;
}

const OptionTable<CameraPluginOptions>& CameraPluginTable() {
  using O = CameraPluginOptions;
  static const OptionTable<O> t(
      "libgazebo_ros_camera.so / libgazebo_ros_depth_camera.so / libgazebo_ros_openni_kinect.so",
      {Field("robotNamespace", &O::robot_namespace,
             "Namespace of the topics (missing: the spawn namespace, usually /)."),
       Field("cameraName", &O::camera_name, "Namespace of the topics below robotNamespace."),
       Field("imageTopicName", &O::image_topic_name, "The colour image (flat-shaded)."),
       Field("cameraInfoTopicName", &O::camera_info_topic_name, "The colour image's CameraInfo."),
       Field("depthImageTopicName", &O::depth_image_topic_name,
             "The depth image: 32FC1, metres along the optical axis, NaN for no return."),
       Field("depthImageCameraInfoTopicName", &O::depth_image_camera_info_topic_name,
             "The depth image's CameraInfo."),
       Field("pointCloudTopicName", &O::point_cloud_topic_name,
             "sensor_msgs/PointCloud2, organised, x y z and rgb, in frameName."),
       Field("frameName", &O::frame_name,
             "header.frame_id: an optical frame (z ahead, x right, y down), as Gazebo's plugins "
             "expect."),
       Field("updateRate", &O::update_rate,
             "Frames per second (Hz) on top of the sensor's update_rate; 0: the sensor's."),
       Field("pointCloudCutoff", &O::point_cloud_cutoff,
             "Depths below this (m) are NaN in the depth image and cloud."),
       Field("pointCloudCutoffMax", &O::point_cloud_cutoff_max,
             "Depths above this (m) are NaN; < 0: no limit (libgazebo_ros_openni_kinect.so's "
             "default is 5)."),
       Field("focalLength", &O::focal_length, "CameraInfo's focal length; 0: W / (2 tan(hfov/2))."),
       Field("Cx", &O::cx, "CameraInfo's principal point x; 0: (W + 1) / 2."),
       Field("Cy", &O::cy, "CameraInfo's principal point y; 0: (H + 1) / 2."),
       Field("CxPrime", &O::cx_prime, "Accepted, as by Gazebo."),
       Field("hackBaseline", &O::hack_baseline, "CameraInfo P[3] = -f x this (stereo)."),
       Field("distortionK1", &O::distortion_k1, "CameraInfo's D[0] (images are not distorted)."),
       Field("distortionK2", &O::distortion_k2, "CameraInfo's D[1]."),
       Field("distortionK3", &O::distortion_k3, "CameraInfo's D[4]."),
       Field("distortionT1", &O::distortion_t1, "CameraInfo's D[2]."),
       Field("distortionT2", &O::distortion_t2, "CameraInfo's D[3]."),
       Field("borderCrop", &O::border_crop, "Accepted.")});
  return t;
}

const OptionTable<GroundTruthOptions>& GroundTruthTable() {
  using O = GroundTruthOptions;
  static const OptionTable<O> t(
      "libgazebo_ros_p3d.so",
      {Field("robotNamespace", &O::robot_namespace,
             "Namespace of topicName (missing: the spawn namespace, usually /)."),
       Field("bodyName", &O::body_name, "The link tracked; required."),
       Field("topicName", &O::topic_name, "nav_msgs/Odometry output; required."),
       Field("frameName", &O::frame_name,
             "world (or map): the pose in the world; else a link of this robot the pose is "
             "given relative to."),
       Field("xyzOffset", &O::xyz_offset, "Added to the position (m)."),
       Field("rpyOffset", &O::rpy_offset, "Rotation (rad) applied before the link's orientation."),
       Field("gaussianNoise", &O::gaussian_noise,
             "Standard deviation of noise added to the twist (as Gazebo: not to the pose)."),
       Field("updateRate", &O::update_rate, "Rate (Hz); 0: every physics step.")});
  return t;
}

const OptionTable<JointStatePublisherOptions>& JointStatePublisherTable() {
  using O = JointStatePublisherOptions;
  static const OptionTable<O> t(
      "libgazebo_ros_joint_state_publisher.so",
      {Field("robotNamespace", &O::robot_namespace,
             "Namespace of joint_states (missing: the spawn namespace, usually /)."),
       Field("jointName", &O::joint_name, "Comma-separated joints to publish."),
       Field("updateRate", &O::update_rate, "Rate of joint_states (Hz).")});
  return t;
}

}  // namespace minibot3d_sim
