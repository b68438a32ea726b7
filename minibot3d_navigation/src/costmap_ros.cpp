#include "costmap_ros.h"

#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include <geometry_msgs/PolygonStamped.h>
#include <tf2/utils.h>
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>

#include "minibot3d_ros/conversions.h"
#include "minibot3d_ros/params.h"
#include "transform_age.h"

namespace minibot3d_navigation {
namespace {

// costmap_2d's cost -> OccupancyGrid value table (Costmap2DPublisher).
int8_t Translate(uint8_t cost) {
  if (cost == nav::kFreeSpace) return 0;
  if (cost == nav::kNoInformation) return -1;
  if (cost == nav::kLethalObstacle) return 100;
  if (cost == nav::kInscribedInflatedObstacle) return 99;
  return static_cast<int8_t>(1 + (97 * (cost - 1)) / 251);
}

}  // namespace

CostmapRos::CostmapRos(const std::string& name, tf2_ros::Buffer* tf)
    : name_(name), tf_(tf), nh_("~" + name) {}

void CostmapRos::Configure(const minibot3d_ros::FrameNames& frames) {
  minibot3d_ros::ParamReport report =
      minibot3d_ros::LoadTable(nh_, nav::CostmapOptionTable(), &options_);
  nav::CostmapSensorOptions sensors;
  report.Also(minibot3d_ros::LoadTable(nh_, nav::CostmapSensorOptionTable(), &sensors));
  std::vector<std::string> problems = report.problems;
  try {
    nav::ValidateCostmapSensorOptions(sensors);
  } catch (const std::invalid_argument& e) {
    problems.push_back(nh_.getNamespace() + ": " + e.what());
  }
  // Each source's keys live in the sub-namespace of its name; plugins' namespaces are not read
  // (the layers follow static_map) and, like the sources', are no misspelt keys.
  for (const std::string& layer : sensors.plugins) report.Known(layer);
  for (const std::string& src : nav::ObservationSourceNames(sensors)) {
    report.Known(src);
    const ros::NodeHandle snh(nh_, src);
    auto s = std::make_unique<Source>();
    s->name = src;
    s->options = nav::DefaultObservationSource(src, options_);
    const minibot3d_ros::ParamReport source_report =
        minibot3d_ros::LoadTable(snh, nav::ObservationSourceOptionTable(), &s->options);
    source_report.WarnUnknown("move_base");
    problems.insert(problems.end(), source_report.problems.begin(), source_report.problems.end());
    s->options.sensor_frame = frames.Resolve(s->options.sensor_frame);
    if (s->options.data_type != "LaserScan" && s->options.data_type != "PointCloud2") {
      problems.push_back(nh_.getNamespace() + "/" + src + "/data_type: '" + s->options.data_type +
                         "' is not supported (LaserScan or PointCloud2)");
      continue;
    }
    if (s->options.subsample < 1) {
      problems.push_back(nh_.getNamespace() + "/" + src + "/subsample: must be >= 1");
    }
    if (!(s->options.min_obstacle_height <= s->options.max_obstacle_height)) {
      problems.push_back(nh_.getNamespace() + "/" + src + ": min_obstacle_height must be <= "
                         "max_obstacle_height");
    }
    if (!(s->options.obstacle_range >= 0.0) || !(s->options.raytrace_range >= 0.0)) {
      problems.push_back(nh_.getNamespace() + "/" + src + ": obstacle_range and raytrace_range "
                         "must be >= 0");
    }
    sources_.push_back(std::move(s));
  }
  report.WarnUnknown("move_base");
  options_.global_frame = frames.Resolve(options_.global_frame);
  options_.robot_base_frame = frames.Resolve(options_.robot_base_frame);
  try {
    nav::ValidateCostmapOptions(options_);
  } catch (const std::invalid_argument& e) {
    problems.push_back(nh_.getNamespace() + ": " + e.what());
  }
  if (!problems.empty()) {
    std::string msg;
    for (const auto& p : problems) msg += (msg.empty() ? "" : "\n  ") + p;
    throw std::invalid_argument(msg);
  }
  for (const std::string& w : nav::CostmapOptionWarnings(options_)) {
    ROS_WARN("move_base: %s: %s", nh_.getNamespace().c_str(), w.c_str());
  }
  if (sources_.empty()) {
    ROS_WARN("move_base: %s has no observation_sources: it will not see obstacles that are "
             "not in the map", nh_.getNamespace().c_str());
  }
  layered_ = std::make_unique<nav::LayeredCostmap>(nav::BuildLayeredCostmap(options_));
  footprint_ = layered_->footprint();
}

void CostmapRos::Start() {
  costmap_pub_ = nh_.advertise<nav_msgs::OccupancyGrid>("costmap", 1, true);
  footprint_pub_ = nh_.advertise<geometry_msgs::PolygonStamped>("footprint", 1);
  if (options_.static_map) {
    map_sub_ = gnh_.subscribe("map", 1, &CostmapRos::OnMap, this);
  }
  for (auto& s : sources_) {
    const std::string& frame = options_.global_frame;
    if (s->options.data_type == "PointCloud2") {
      s->cloud_sub = std::make_unique<message_filters::Subscriber<sensor_msgs::PointCloud2>>(
          gnh_, s->options.topic, 5);
      s->cloud_filter = std::make_unique<tf2_ros::MessageFilter<sensor_msgs::PointCloud2>>(
          *s->cloud_sub, *tf_, frame, 5, gnh_);
      Source* raw = s.get();
      s->cloud_filter->registerCallback(
          [this, raw](const sensor_msgs::PointCloud2::ConstPtr& c) { OnCloud(c, raw); });
      continue;
    }
    s->sub = std::make_unique<message_filters::Subscriber<sensor_msgs::LaserScan>>(
        gnh_, s->options.topic, 50);
    s->filter = std::make_unique<tf2_ros::MessageFilter<sensor_msgs::LaserScan>>(*s->sub, *tf_,
                                                                                 frame, 50, gnh_);
    Source* raw = s.get();
    s->filter->registerCallback(
        [this, raw](const sensor_msgs::LaserScan::ConstPtr& scan) { OnScan(scan, raw); });
    s->filter->registerFailureCallback(
        [this, raw](const sensor_msgs::LaserScan::ConstPtr& scan,
                    tf2_ros::filter_failure_reasons::FilterFailureReason) {
          ROS_WARN_THROTTLE(5.0, "move_base: %s: scan on %s in frame '%s' cannot be transformed "
                            "into '%s': check the tf tree (is the localizer running?)",
                            name_.c_str(), raw->options.topic.c_str(), scan->header.frame_id.c_str(),
                            options_.global_frame.c_str());
        });
  }
}

void CostmapRos::OnMap(const nav_msgs::OccupancyGrid::ConstPtr& map) {
  if (!map->header.frame_id.empty() && map->header.frame_id != options_.global_frame &&
      !options_.rolling_window) {
    ROS_WARN("move_base: %s: map frame '%s' differs from global_frame '%s'; using it as is",
             name_.c_str(), map->header.frame_id.c_str(), options_.global_frame.c_str());
  }
  try {
    layered_->SetStaticMap(minibot3d_ros::GridFromMsg(*map));
    have_map_ = true;
    next_update_ = ros::Time(0);
    ROS_INFO("move_base: %s: static map %ux%u at %.3f m", name_.c_str(), map->info.width,
             map->info.height, map->info.resolution);
  } catch (const std::invalid_argument& e) {
    ROS_ERROR("move_base: %s: map rejected: %s", name_.c_str(), e.what());
  }
}

void CostmapRos::OnScan(const sensor_msgs::LaserScan::ConstPtr& scan, Source* source) {
  const nav::ObservationSourceOptions& o = source->options;
  const std::string frame = o.sensor_frame.empty() ? scan->header.frame_id : o.sensor_frame;
  geometry_msgs::TransformStamped t;
  try {
    t = tf_->lookupTransform(options_.global_frame, frame, scan->header.stamp);
  } catch (const tf2::TransformException& e) {
    ROS_WARN_THROTTLE(5.0, "move_base: %s: no transform %s <- %s: %s", name_.c_str(),
                      options_.global_frame.c_str(), frame.c_str(), e.what());
    return;
  }
  nav::LaserScan s;
  s.ranges.assign(scan->ranges.begin(), scan->ranges.end());
  s.angles = nav::MakeBeamAngles(scan->angle_min, scan->angle_increment,
                                  static_cast<int>(scan->ranges.size()));
  s.range_min = scan->range_min;
  s.range_max = scan->range_max;
  tf2::Transform tt;
  tf2::fromMsg(t.transform, tt);
  const nav::Pose2 sensor = minibot3d_ros::PoseFromTf(tt);
  try {
    nav::Observation obs =
        nav::ObservationFromScan(s, sensor, o.marking ? o.obstacle_range : 0.0,
                                 o.clearing ? o.raytrace_range : 0.0, o.inf_is_valid);
    obs.stamp = scan->header.stamp.toSec();
    layered_->obstacle_layer()->AddObservation(obs);
    if (observation_callback_) observation_callback_(scan->header.stamp.toSec(), obs);
  } catch (const std::invalid_argument& e) {
    ROS_WARN_THROTTLE(5.0, "move_base: %s: scan from %s dropped: %s", name_.c_str(),
                      o.topic.c_str(), e.what());
  }
}

void CostmapRos::OnCloud(const sensor_msgs::PointCloud2::ConstPtr& cloud, Source* source) {
  const nav::ObservationSourceOptions& o = source->options;
  const std::string frame = o.sensor_frame.empty() ? cloud->header.frame_id : o.sensor_frame;
  geometry_msgs::TransformStamped t;
  try {
    t = tf_->lookupTransform(options_.global_frame, frame, cloud->header.stamp);
  } catch (const tf2::TransformException& e) {
    ROS_WARN_THROTTLE(5.0, "move_base: %s: no transform %s <- %s: %s", name_.c_str(),
                      options_.global_frame.c_str(), frame.c_str(), e.what());
    return;
  }
  tf2::Transform tt;
  tf2::fromMsg(t.transform, tt);
  const int step = std::max(1, o.subsample);
  int offset[3] = {-1, -1, -1};
  const char* names[3] = {"x", "y", "z"};
  for (const sensor_msgs::PointField& f : cloud->fields) {
    for (int a = 0; a < 3; ++a) {
      if (f.name == names[a] && f.datatype == sensor_msgs::PointField::FLOAT32 && f.count >= 1 &&
          f.offset + sizeof(float) <= cloud->point_step) {
        offset[a] = static_cast<int>(f.offset);
      }
    }
  }
  if (offset[0] < 0 || offset[1] < 0 || offset[2] < 0) {
    ROS_WARN_THROTTLE(5.0, "move_base: %s: cloud on %s dropped: it has no FLOAT32 x, y and z "
                      "fields", name_.c_str(), o.topic.c_str());
    return;
  }
  const uint64_t need = static_cast<uint64_t>(cloud->height) * cloud->row_step;
  if (cloud->data.size() < need ||
      static_cast<uint64_t>(cloud->width) * cloud->point_step > cloud->row_step ||
      cloud->is_bigendian) {
    ROS_WARN_THROTTLE(5.0, "move_base: %s: cloud on %s dropped: %ux%u points with point_step %u "
                      "and row_step %u do not fit its %zu bytes (or it is big-endian)",
                      name_.c_str(), o.topic.c_str(), cloud->width, cloud->height,
                      cloud->point_step, cloud->row_step, cloud->data.size());
    return;
  }
  std::vector<double>& xyz = source->xyz;
  xyz.clear();
  try {
    for (uint32_t r = 0; r < cloud->height; r += step) {
      const uint8_t* row = cloud->data.data() + static_cast<size_t>(r) * cloud->row_step;
      for (uint32_t c = 0; c < cloud->width; c += step) {
        const uint8_t* pt = row + static_cast<size_t>(c) * cloud->point_step;
        float v[3];
        for (int a = 0; a < 3; ++a) std::memcpy(&v[a], pt + offset[a], sizeof(float));
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) continue;
        const tf2::Vector3 p = tt * tf2::Vector3(v[0], v[1], v[2]);
        xyz.push_back(p.x());
        xyz.push_back(p.y());
        xyz.push_back(p.z());
      }
    }
    const tf2::Vector3 origin = tt.getOrigin();
    nav::Observation obs = nav::ObservationFromPoints(
        xyz, nav::Point2{origin.x(), origin.y()}, o.min_obstacle_height, o.max_obstacle_height,
        o.marking ? o.obstacle_range : 0.0, o.clearing ? o.raytrace_range : 0.0);
    obs.stamp = cloud->header.stamp.toSec();
    layered_->obstacle_layer()->AddObservation(obs);
    if (observation_callback_) observation_callback_(cloud->header.stamp.toSec(), obs);
  } catch (const std::exception& e) {
    ROS_WARN_THROTTLE(5.0, "move_base: %s: cloud from %s dropped: %s", name_.c_str(),
                      o.topic.c_str(), e.what());
  }
}

bool CostmapRos::RobotPose(nav::Pose2* pose, std::string* why, bool* clocks_disagree) const {
  if (clocks_disagree != nullptr) *clocks_disagree = false;
  const std::string& global = options_.global_frame;
  const std::string& base = options_.robot_base_frame;
  try {
    const auto t = tf_->lookupTransform(global, base, ros::Time(0));
    tf2::Transform tt;
    tf2::fromMsg(t.transform, tt);
    *pose = minibot3d_ros::PoseFromTf(tt);
    const TransformAge age = CheckTransformAge(ros::Time::now().toSec(), t.header.stamp.toSec(),
                                               global, base, options_.transform_tolerance);
    if (!age.ok) {
      *why = age.why;
      if (clocks_disagree != nullptr) *clocks_disagree = age.clocks_disagree;
    }
    return age.ok;
  } catch (const tf2::TransformException& e) {
    *why = "no transform " + global + " <- " + base + ": " + e.what();
    return false;
  }
}

void CostmapRos::Update(const ros::Time& now, const nav::Pose2& robot, bool force) {
  if (!ready()) return;
  if (force || now >= next_update_ || options_.update_frequency <= 0.0) {
    layered_->UpdateMap(robot);
    if (options_.update_frequency > 0.0) {
      next_update_ = now + ros::Duration(1.0 / options_.update_frequency);
    }
  }
  if (options_.publish_frequency > 0.0 && now >= next_publish_) {
    Publish(now);
    next_publish_ = now + ros::Duration(1.0 / options_.publish_frequency);
  }
}

void CostmapRos::Publish(const ros::Time& now) {
  const nav::Costmap2D& c = layered_->costmap();
  if (costmap_pub_.getNumSubscribers() > 0) {
    nav_msgs::OccupancyGrid g;
    g.header.stamp = now;
    g.header.frame_id = options_.global_frame;
    g.info.map_load_time = now;
    g.info.resolution = c.resolution();
    g.info.width = c.size_x();
    g.info.height = c.size_y();
    g.info.origin.position.x = c.origin_x();
    g.info.origin.position.y = c.origin_y();
    g.info.origin.orientation.w = 1.0;
    g.data.resize(c.cells().size());
    for (size_t i = 0; i < g.data.size(); ++i) g.data[i] = Translate(c.cells()[i]);
    costmap_pub_.publish(g);
  }
  if (footprint_pub_.getNumSubscribers() > 0) {
    geometry_msgs::PolygonStamped p;
    p.header.stamp = now;
    p.header.frame_id = options_.robot_base_frame;
    for (const auto& v : footprint_) {
      geometry_msgs::Point32 q;
      q.x = v.x;
      q.y = v.y;
      p.polygon.points.push_back(q);
    }
    footprint_pub_.publish(p);
  }
}

void CostmapRos::Reset() {
  layered_->ResetLayers();
  next_update_ = ros::Time(0);
}

void CostmapRos::ClearExceptAround(const nav::Pose2& robot, double reset_distance) {
  layered_->ClearExceptAround(robot, reset_distance);
}

}  // namespace minibot3d_navigation
