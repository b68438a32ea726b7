// Embree scenes for the world and its bodies; see ray_scene.h.
//
// The analytic shapes are solved in double precision in their own frame: the ray is taken into the
// shape frame (R^T (o − c), R^T d), where a capped cylinder is x² + y² = r², |z| ≤ h plus two discs,
// a sphere |p| = r, a plane n·p = 0. The smaller root of a quadratic is taken in the cancellation-
// free form q = −(b + sign(b)·√disc)/2, t = q/a or c/q.
#include "minibot3d_sim/ray_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <embree3/rtcore.h>

namespace minibot3d_sim {
namespace {

// Planes are infinite, but Embree needs finite bounds; nothing a sensor sees is 10 km away.
constexpr double kPlaneReach = 1.0e4;

thread_local std::string tls_embree_message;

void OnEmbreeError(void* /*user*/, RTCError /*code*/, const char* message) {
  tls_embree_message = message == nullptr ? "" : message;
}

const char* ErrorName(RTCError e) {
  switch (e) {
    case RTC_ERROR_NONE: return "RTC_ERROR_NONE";
    case RTC_ERROR_UNKNOWN: return "RTC_ERROR_UNKNOWN";
    case RTC_ERROR_INVALID_ARGUMENT: return "RTC_ERROR_INVALID_ARGUMENT";
    case RTC_ERROR_INVALID_OPERATION: return "RTC_ERROR_INVALID_OPERATION";
    case RTC_ERROR_OUT_OF_MEMORY: return "RTC_ERROR_OUT_OF_MEMORY";
    case RTC_ERROR_UNSUPPORTED_CPU: return "RTC_ERROR_UNSUPPORTED_CPU";
    case RTC_ERROR_CANCELLED: return "RTC_ERROR_CANCELLED";
  }
  return "RTC_ERROR_?";
}

// Embree reports errors through the device, per thread; turn the pending one into an exception.
void Check(RTCDevice device, const char* call) {
  const RTCError e = rtcGetDeviceError(device);
  if (e == RTC_ERROR_NONE) return;
  std::string message = std::string("Embree ") + call + " failed: " + ErrorName(e);
  if (!tls_embree_message.empty()) message += ": " + tls_embree_message;
  tls_embree_message.clear();
  throw RaySceneError(message);
}

// A shape frame for the analytic intersectors: world → shape is p' = rt·(p − c).
struct Frame {
  Eigen::Matrix3d r;   // shape → scene rotation
  Eigen::Matrix3d rt;  // its transpose
  Eigen::Vector3d c;

  explicit Frame(const Eigen::Isometry3d& pose)
      : r(pose.linear()), rt(pose.linear().transpose()), c(pose.translation()) {}
};

struct Cylinder {
  Frame frame;
  double radius, half_length;

  // Nearest crossing of the side or a cap with t in [t0, t1].
  bool Intersect(const Eigen::Vector3d& o_world, const Eigen::Vector3d& d_world, double t0,
                 double t1, double* t, Eigen::Vector3d* normal) const {
    const Eigen::Vector3d o = frame.rt * (o_world - frame.c);
    const Eigen::Vector3d d = frame.rt * d_world;
    double best = std::numeric_limits<double>::infinity();
    Eigen::Vector3d n_best = Eigen::Vector3d::Zero();
    const double a = d.x() * d.x() + d.y() * d.y();
    if (a > 0.0) {
      const double b = 2.0 * (o.x() * d.x() + o.y() * d.y());
      const double c = o.x() * o.x() + o.y() * o.y() - radius * radius;
      const double disc = b * b - 4.0 * a * c;
      if (disc >= 0.0) {
        const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
        double roots[2] = {q / a, q != 0.0 ? c / q : q / a};
        if (roots[0] > roots[1]) std::swap(roots[0], roots[1]);
        for (const double r : roots) {
          if (r < t0 || r > t1 || r >= best) continue;
          const double z = o.z() + r * d.z();
          if (std::abs(z) > half_length) continue;
          best = r;
          n_best = Eigen::Vector3d(o.x() + r * d.x(), o.y() + r * d.y(), 0.0);
          break;
        }
      }
    }
    if (d.z() != 0.0) {
      for (const double side : {-1.0, 1.0}) {
        const double r = (side * half_length - o.z()) / d.z();
        if (r < t0 || r > t1 || r >= best) continue;
        const double x = o.x() + r * d.x(), y = o.y() + r * d.y();
        if (x * x + y * y > radius * radius) continue;
        best = r;
        n_best = Eigen::Vector3d(0.0, 0.0, side);
      }
    }
    if (!std::isfinite(best)) return false;
    *t = best;
    *normal = frame.r * n_best;
    return true;
  }

  RTCBounds Bounds() const {
    // Extent of a cylinder along scene axis i: r·√(1 − a_i²) + h·|a_i|, a its unit axis.
    const Eigen::Vector3d axis = frame.r.col(2);
    RTCBounds b;
    float* lo[3] = {&b.lower_x, &b.lower_y, &b.lower_z};
    float* hi[3] = {&b.upper_x, &b.upper_y, &b.upper_z};
    for (int i = 0; i < 3; ++i) {
      const double e = radius * std::sqrt(std::max(0.0, 1.0 - axis[i] * axis[i])) +
                       half_length * std::abs(axis[i]);
      *lo[i] = static_cast<float>(frame.c[i] - e) - 1e-4f;
      *hi[i] = static_cast<float>(frame.c[i] + e) + 1e-4f;
    }
    return b;
  }
};

struct Sphere {
  Eigen::Vector3d center;
  double radius;

  bool Intersect(const Eigen::Vector3d& o_world, const Eigen::Vector3d& d, double t0, double t1,
                 double* t, Eigen::Vector3d* normal) const {
    const Eigen::Vector3d o = o_world - center;
    const double a = d.squaredNorm();
    const double b = 2.0 * o.dot(d);
    const double c = o.squaredNorm() - radius * radius;
    const double disc = b * b - 4.0 * a * c;
    if (!(a > 0.0) || disc < 0.0) return false;
    const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
    double roots[2] = {q / a, q != 0.0 ? c / q : q / a};
    if (roots[0] > roots[1]) std::swap(roots[0], roots[1]);
    for (const double r : roots) {
      if (r < t0 || r > t1) continue;
      *t = r;
      *normal = o + r * d;
      return true;
    }
    return false;
  }

  RTCBounds Bounds() const {
    const float r = static_cast<float>(radius) + 1e-4f;
    return RTCBounds{static_cast<float>(center.x()) - r, static_cast<float>(center.y()) - r,
                     static_cast<float>(center.z()) - r, 0.0f,
                     static_cast<float>(center.x()) + r, static_cast<float>(center.y()) + r,
                     static_cast<float>(center.z()) + r, 0.0f};
  }
};

struct Plane {
  Eigen::Vector3d point, normal;  // scene frame, unit normal

  bool Intersect(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t0, double t1,
                 double* t, Eigen::Vector3d* n) const {
    const double denom = normal.dot(d);
    if (denom == 0.0) return false;
    const double r = normal.dot(point - o) / denom;
    if (!(r >= t0 && r <= t1)) return false;
    *t = r;
    *n = normal;
    return true;
  }

  RTCBounds Bounds() const {
    // The part of the plane inside a cube of kPlaneReach around its point: thin along an axis the
    // normal is parallel to (the usual ground plane), the whole cube otherwise.
    RTCBounds b;
    float* lo[3] = {&b.lower_x, &b.lower_y, &b.lower_z};
    float* hi[3] = {&b.upper_x, &b.upper_y, &b.upper_z};
    for (int i = 0; i < 3; ++i) {
      const bool flat = std::abs(normal[i]) > 1.0 - 1e-12;
      const double e = flat ? 1e-3 : kPlaneReach;
      *lo[i] = static_cast<float>(point[i] - e);
      *hi[i] = static_cast<float>(point[i] + e);
    }
    return b;
  }
};

// Embree's user-geometry callbacks for a geometry whose primitives are a std::vector<Prim>. A
// packet arrives with a validity mask; each valid ray is solved on its own.
template <typename Prim>
void IntersectPrims(const RTCIntersectFunctionNArguments* args) {
  const Prim& prim = static_cast<const Prim*>(args->geometryUserPtr)[args->primID];
  const unsigned n = args->N;
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, n);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, n);
  for (unsigned i = 0; i < n; ++i) {
    if (args->valid[i] != -1) continue;
    const Eigen::Vector3d o(RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i),
                            RTCRayN_org_z(ray, n, i));
    const Eigen::Vector3d d(RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i),
                            RTCRayN_dir_z(ray, n, i));
    const float tnear = RTCRayN_tnear(ray, n, i);
    float& tfar = RTCRayN_tfar(ray, n, i);
    double t;
    Eigen::Vector3d normal;
    if (!prim.Intersect(o, d, tnear, tfar, &t, &normal)) continue;
    const float tf = static_cast<float>(t);
    if (tf < tnear || tf > tfar) continue;  // rounding to float may step over a limit
    tfar = tf;
    RTCHitN_Ng_x(hit, n, i) = static_cast<float>(normal.x());
    RTCHitN_Ng_y(hit, n, i) = static_cast<float>(normal.y());
    RTCHitN_Ng_z(hit, n, i) = static_cast<float>(normal.z());
    RTCHitN_u(hit, n, i) = 0.0f;
    RTCHitN_v(hit, n, i) = 0.0f;
    RTCHitN_primID(hit, n, i) = args->primID;
    RTCHitN_geomID(hit, n, i) = args->geomID;
    RTCHitN_instID(hit, n, i, 0) = args->context->instID[0];
  }
}

// The ground plane lies under every packet that looks down, so its callback runs for about half
// of a camera's packets: solved in single precision over the whole packet, where one division
// per ray loses nothing against the float t it reports.
template <>
void IntersectPrims<Plane>(const RTCIntersectFunctionNArguments* args) {
  const Plane& plane = static_cast<const Plane*>(args->geometryUserPtr)[args->primID];
  const float nx = static_cast<float>(plane.normal.x()), ny = static_cast<float>(plane.normal.y()),
              nz = static_cast<float>(plane.normal.z());
  const float c = static_cast<float>(plane.normal.dot(plane.point));
  const unsigned n = args->N;
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, n);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, n);
  const unsigned inst = args->context->instID[0];
  for (unsigned i = 0; i < n; ++i) {
    const float denom = nx * RTCRayN_dir_x(ray, n, i) + ny * RTCRayN_dir_y(ray, n, i) +
                        nz * RTCRayN_dir_z(ray, n, i);
    const float t = (c - (nx * RTCRayN_org_x(ray, n, i) + ny * RTCRayN_org_y(ray, n, i) +
                          nz * RTCRayN_org_z(ray, n, i))) /
                    denom;
    // A ray along the plane gives ±inf or NaN: not finite, no hit.
    if (args->valid[i] != -1 || !std::isfinite(t) || t < RTCRayN_tnear(ray, n, i) ||
        t > RTCRayN_tfar(ray, n, i)) {
      continue;
    }
    RTCRayN_tfar(ray, n, i) = t;
    RTCHitN_Ng_x(hit, n, i) = nx;
    RTCHitN_Ng_y(hit, n, i) = ny;
    RTCHitN_Ng_z(hit, n, i) = nz;
    RTCHitN_u(hit, n, i) = 0.0f;
    RTCHitN_v(hit, n, i) = 0.0f;
    RTCHitN_primID(hit, n, i) = args->primID;
    RTCHitN_geomID(hit, n, i) = args->geomID;
    RTCHitN_instID(hit, n, i, 0) = inst;
  }
}

template <typename Prim>
void OccludedPrims(const RTCOccludedFunctionNArguments* args) {
  const Prim& prim = static_cast<const Prim*>(args->geometryUserPtr)[args->primID];
  const unsigned n = args->N;
  for (unsigned i = 0; i < n; ++i) {
    if (args->valid[i] != -1) continue;
    const Eigen::Vector3d o(RTCRayN_org_x(args->ray, n, i), RTCRayN_org_y(args->ray, n, i),
                            RTCRayN_org_z(args->ray, n, i));
    const Eigen::Vector3d d(RTCRayN_dir_x(args->ray, n, i), RTCRayN_dir_y(args->ray, n, i),
                            RTCRayN_dir_z(args->ray, n, i));
    double t;
    Eigen::Vector3d normal;
    if (prim.Intersect(o, d, RTCRayN_tnear(args->ray, n, i), RTCRayN_tfar(args->ray, n, i), &t,
                       &normal)) {
      RTCRayN_tfar(args->ray, n, i) = -std::numeric_limits<float>::infinity();
    }
  }
}

template <typename Prim>
void BoundsPrims(const RTCBoundsFunctionArguments* args) {
  *args->bounds_o = static_cast<const Prim*>(args->geometryUserPtr)[args->primID].Bounds();
}

// The twelve triangles of a box, outward-wound.
void AppendBox(const Shape& s, std::vector<Eigen::Vector3f>* vertices,
               std::vector<std::array<std::uint32_t, 3>>* triangles) {
  const std::uint32_t base = static_cast<std::uint32_t>(vertices->size());
  const Eigen::Vector3d h = 0.5 * s.size;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(),
                                 (k & 4) ? h.z() : -h.z());
    vertices->push_back((s.pose * corner).cast<float>());
  }
  static const std::uint32_t kFaces[12][3] = {
      {0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},   // −z, +z
      {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},   // −y, +y
      {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};  // −x, +x
  for (const auto& f : kFaces) triangles->push_back({base + f[0], base + f[1], base + f[2]});
}

// Whether any ray of a packet, from its origin to its current tfar, can reach the box `b`: the
// segments' bounding box overlaps it. A second rtcIntersect16 costs about as much as
// a short traversal even when it finds nothing, so packets that stop short of every body skip it.
bool PacketReaches(const RTCRayHit16& rh, const RTCBounds& b) {
  // Lanes past the packet's rays repeat its last ray, so all 16 can take part.
  const float* org[3] = {rh.ray.org_x, rh.ray.org_y, rh.ray.org_z};
  const float* dir[3] = {rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z};
  const float lower[3] = {b.lower_x, b.lower_y, b.lower_z};
  const float upper[3] = {b.upper_x, b.upper_y, b.upper_z};
  for (int a = 0; a < 3; ++a) {
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (int i = 0; i < 16; ++i) {
      const float o = org[a][i], e = o + rh.ray.tfar[i] * dir[a][i];
      lo = std::min(lo, std::min(o, e));
      hi = std::max(hi, std::max(o, e));
    }
    // NaN (an infinite tfar times a zero direction) fails both tests: the packet is cast.
    if (hi < lower[a] || lo > upper[a]) return false;
  }
  return true;
}

}  // namespace

// One Embree scene over a list of shapes, with the tables that turn (geomID, primID) into hit ids.
struct RayScene::SubScene {
  RTCScene scene = nullptr;
  std::vector<std::vector<int>> hit_ids;  // [geomID][primID]
  std::vector<const int*> tables;         // hit_ids[g].data(), for the hot path
  std::vector<Cylinder> cylinders;
  std::vector<Sphere> spheres;
  std::vector<Plane> planes;

  SubScene() = default;
  SubScene(const SubScene&) = delete;
  SubScene& operator=(const SubScene&) = delete;
  ~SubScene() {
    if (scene != nullptr) rtcReleaseScene(scene);
  }

  void Build(RTCDevice device, const std::vector<Shape>& shapes, int first_hit_id) {
    std::vector<Eigen::Vector3f> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<int> triangle_ids, cylinder_ids, sphere_ids, plane_ids;
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      const Shape& s = shapes[i];
      const int id = first_hit_id + static_cast<int>(i);
      switch (s.type) {
        case ShapeType::kBox:
          AppendBox(s, &vertices, &triangles);
          triangle_ids.insert(triangle_ids.end(), 12, id);
          break;
        case ShapeType::kMesh: {
          if (!s.mesh) break;
          const std::uint32_t base = static_cast<std::uint32_t>(vertices.size());
          const Eigen::Isometry3f pose = s.pose.cast<float>();
          for (const Eigen::Vector3f& v : s.mesh->vertices) vertices.push_back(pose * v);
          for (const auto& t : s.mesh->triangles) {
            triangles.push_back({base + t[0], base + t[1], base + t[2]});
          }
          triangle_ids.insert(triangle_ids.end(), s.mesh->triangles.size(), id);
          break;
        }
        case ShapeType::kCylinder:
          cylinders.push_back(Cylinder{Frame(s.pose), s.size.x(), 0.5 * s.size.z()});
          cylinder_ids.push_back(id);
          break;
        case ShapeType::kSphere:
          spheres.push_back(Sphere{s.pose.translation(), s.size.x()});
          sphere_ids.push_back(id);
          break;
        case ShapeType::kPlane:
          planes.push_back(
              Plane{s.pose.translation(), (s.pose.linear() * s.normal).normalized()});
          plane_ids.push_back(id);
          break;
      }
    }

    scene = rtcNewScene(device);
    Check(device, "rtcNewScene");
    // Worlds are built once and cast millions of times: spend on the BVH. RTC_SCENE_FLAG_ROBUST
    // would cost a camera frame 14 %; without it, over 25 M pixels of the apartment the hit shape
    // changed at 4, all on the silhouette edge between two shapes, none inside a face.
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_NONE);
    Check(device, "rtcSetSceneFlags");

    if (!triangles.empty()) {
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      Check(device, "rtcNewGeometry(TRIANGLE)");
      auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
          g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices.size()));
      auto* ib = static_cast<std::uint32_t*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                  3 * sizeof(std::uint32_t), triangles.size()));
      Check(device, "rtcSetNewGeometryBuffer");
      for (std::size_t i = 0; i < vertices.size(); ++i) {
        vb[3 * i] = vertices[i].x();
        vb[3 * i + 1] = vertices[i].y();
        vb[3 * i + 2] = vertices[i].z();
      }
      for (std::size_t i = 0; i < triangles.size(); ++i) {
        for (int k = 0; k < 3; ++k) ib[3 * i + k] = triangles[i][k];
      }
      rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_HIGH);
      Attach(device, g, std::move(triangle_ids));
    }
    AttachUser(device, cylinders, std::move(cylinder_ids));
    AttachUser(device, spheres, std::move(sphere_ids));
    AttachUser(device, planes, std::move(plane_ids));

    rtcCommitScene(scene);
    Check(device, "rtcCommitScene");
    for (const auto& ids : hit_ids) tables.push_back(ids.data());
  }

  template <typename Prim>
  void AttachUser(RTCDevice device, const std::vector<Prim>& prims, std::vector<int> ids) {
    if (prims.empty()) return;
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    Check(device, "rtcNewGeometry(USER)");
    rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(prims.size()));
    // The vector is complete and never grows again, so the pointer stays valid.
    rtcSetGeometryUserData(g, const_cast<Prim*>(prims.data()));
    rtcSetGeometryBoundsFunction(g, &BoundsPrims<Prim>, nullptr);
    rtcSetGeometryIntersectFunction(g, &IntersectPrims<Prim>);
    rtcSetGeometryOccludedFunction(g, &OccludedPrims<Prim>);
    Check(device, "rtcSetGeometry*Function");
    Attach(device, g, std::move(ids));
  }

  void Attach(RTCDevice device, RTCGeometry g, std::vector<int> ids) {
    rtcCommitGeometry(g);
    Check(device, "rtcCommitGeometry");
    const unsigned geom_id = rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    Check(device, "rtcAttachGeometry");
    if (hit_ids.size() <= geom_id) hit_ids.resize(geom_id + 1);
    hit_ids[geom_id] = std::move(ids);
  }
};

struct RayScene::Body {
  std::string name;
  SubScene sub;
  int first_hit_id = 0;
  int num_shapes = 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // as set; applied by Commit()
  bool pose_pending = true;
  RTCGeometry instance = nullptr;  // owned by bodies_top_ once attached
};

RayScene::RayScene(const World& world, RTCDevice device) : device_(device) {
  if (device_ == nullptr) {
    device_ = rtcNewDevice(nullptr);
    if (device_ == nullptr) {
      Check(nullptr, "rtcNewDevice");  // throws with Embree's reason when it gave one
      throw RaySceneError("Embree rtcNewDevice failed");
    }
    own_device_ = true;
  }
  rtcSetDeviceErrorFunction(device_, &OnEmbreeError, nullptr);
  try {
    static_ = std::make_unique<SubScene>();
    static_->Build(device_, world.shapes, 0);
    static_tables_ = static_->tables.data();
  } catch (...) {
    static_.reset();
    if (own_device_) rtcReleaseDevice(device_);
    throw;
  }
  for (std::size_t i = 0; i < world.shapes.size(); ++i) {
    targets_.push_back(HitTarget{-1, static_cast<int>(i)});
    names_.push_back(world.shapes[i].name);
    colors_.push_back(world.shapes[i].color);
  }
}

RayScene::~RayScene() {
  // Top level first: its instances refer to the bodies' scenes.
  if (bodies_top_ != nullptr) rtcReleaseScene(bodies_top_);
  bodies_.clear();
  static_.reset();
  if (own_device_) rtcReleaseDevice(device_);
}

int RayScene::AddBody(std::vector<Shape> shapes_in_body_frame, std::string name) {
  if (shapes_in_body_frame.empty()) {
    throw std::invalid_argument("RayScene::AddBody: body '" + name + "' has no shapes");
  }
  auto body = std::make_unique<Body>();
  body->name = std::move(name);
  body->first_hit_id = num_hit_ids();
  body->num_shapes = static_cast<int>(shapes_in_body_frame.size());
  body->sub.Build(device_, shapes_in_body_frame, body->first_hit_id);
  const int index = num_bodies();
  for (int k = 0; k < body->num_shapes; ++k) {
    const Shape& s = shapes_in_body_frame[k];
    targets_.push_back(HitTarget{index, k});
    names_.push_back(body->name + "::" + s.name);
    colors_.push_back(s.color);
  }
  bodies_.push_back(std::move(body));
  return index;
}

void RayScene::CheckBody(int body, const char* what) const {
  if (body < 0 || body >= num_bodies()) {
    throw std::out_of_range(std::string("RayScene::") + what + ": no body " +
                            std::to_string(body) + " (have " + std::to_string(num_bodies()) +
                            ")");
  }
}

void RayScene::SetBodyPose(int body, const Eigen::Isometry3d& pose_in_world) {
  CheckBody(body, "SetBodyPose");
  bodies_[body]->pose = pose_in_world;
  bodies_[body]->pose_pending = true;
}

void RayScene::Commit() {
  if (bodies_.empty()) return;
  const auto set_transform = [this](RTCGeometry g, const Eigen::Isometry3d& pose) {
    // FLOAT3X4_COLUMN_MAJOR: the three columns of the rotation, then the translation.
    const Eigen::Matrix<float, 3, 4> m = pose.matrix().topRows<3>().cast<float>();
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m.data());
    rtcCommitGeometry(g);
    Check(device_, "rtcSetGeometryTransform");
  };
  if (bodies_top_ == nullptr) {
    bodies_top_ = rtcNewScene(device_);
    Check(device_, "rtcNewScene");
    // Rebuilt at every Commit, and only a handful of instances: build fast.
    rtcSetSceneBuildQuality(bodies_top_, RTC_BUILD_QUALITY_LOW);
    rtcSetSceneFlags(bodies_top_, RTC_SCENE_FLAG_DYNAMIC);
    Check(device_, "rtcSetSceneFlags");
  }
  for (int b = 0; b < num_bodies(); ++b) {
    Body& body = *bodies_[b];
    if (body.instance == nullptr) {
      body.instance = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
      Check(device_, "rtcNewGeometry(INSTANCE)");
      rtcSetGeometryInstancedScene(body.instance, body.sub.scene);
      set_transform(body.instance, body.pose);
      rtcAttachGeometryByID(bodies_top_, body.instance, static_cast<unsigned>(b));
      rtcReleaseGeometry(body.instance);  // bodies_top_ holds it from here on
      Check(device_, "rtcAttachGeometryByID");
      body_tables_.push_back(body.sub.tables.data());
      body_rotations_.push_back(body.pose.linear().cast<float>());
      body.pose_pending = false;
    } else if (body.pose_pending) {
      set_transform(body.instance, body.pose);
      body_rotations_[b] = body.pose.linear().cast<float>();
      body.pose_pending = false;
    }
  }
  rtcCommitScene(bodies_top_);
  Check(device_, "rtcCommitScene");
  rtcGetSceneBounds(bodies_top_, &bodies_bounds_);
  Check(device_, "rtcGetSceneBounds");
}

int RayScene::BodyHitId(int body, int shape) const {
  CheckBody(body, "BodyHitId");
  if (shape < 0 || shape >= bodies_[body]->num_shapes) {
    throw std::out_of_range("RayScene::BodyHitId: body '" + bodies_[body]->name +
                            "' has no shape " + std::to_string(shape));
  }
  return bodies_[body]->first_hit_id + shape;
}

HitTarget RayScene::Target(int hit_id) const {
  if (hit_id < 0 || hit_id >= num_hit_ids()) return HitTarget{};
  return targets_[hit_id];
}

const std::string& RayScene::HitName(int hit_id) const {
  static const std::string kNone = "(no hit)";
  if (hit_id < 0 || hit_id >= num_hit_ids()) return kNone;
  return names_[hit_id];
}

const Eigen::Vector3f& RayScene::HitColor(int hit_id) const {
  static const Eigen::Vector3f kNone = Eigen::Vector3f::Zero();
  if (hit_id < 0 || hit_id >= num_hit_ids()) return kNone;
  return colors_[hit_id];
}

const std::string& RayScene::body_name(int body) const {
  CheckBody(body, "body_name");
  return bodies_[body]->name;
}

template <bool kCommonOrigin>
void RayScene::Trace(const float* ox, const float* oy, const float* oz, const float* dx,
                     const float* dy, const float* dz, int n, float tnear, float tfar,
                     float* t_out, int* hit_id_out, float* normal_out) const {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  for (int i = 0; i < 16; ++i) {
    rh.ray.time[i] = 0.0f;
    rh.ray.mask[i] = 0xFFFFFFFFu;
    rh.ray.id[i] = static_cast<unsigned>(i);
    rh.ray.flags[i] = 0;
    if (kCommonOrigin) {
      rh.ray.org_x[i] = ox[0];
      rh.ray.org_y[i] = oy[0];
      rh.ray.org_z[i] = oz[0];
    }
  }
  for (int base = 0; base < n; base += 16) {
    const int m = std::min(16, n - base);
    if (m == 16) {
      std::copy_n(dx + base, 16, rh.ray.dir_x);
      std::copy_n(dy + base, 16, rh.ray.dir_y);
      std::copy_n(dz + base, 16, rh.ray.dir_z);
      if (!kCommonOrigin) {
        std::copy_n(ox + base, 16, rh.ray.org_x);
        std::copy_n(oy + base, 16, rh.ray.org_y);
        std::copy_n(oz + base, 16, rh.ray.org_z);
      }
    } else {
      // Unused lanes copy the last ray: Embree skips them, but they stay well-formed.
      for (int i = 0; i < 16; ++i) {
        const int k = base + std::min(i, m - 1);
        rh.ray.dir_x[i] = dx[k];
        rh.ray.dir_y[i] = dy[k];
        rh.ray.dir_z[i] = dz[k];
        if (!kCommonOrigin) {
          rh.ray.org_x[i] = ox[k];
          rh.ray.org_y[i] = oy[k];
          rh.ray.org_z[i] = oz[k];
        }
      }
    }
    for (int i = 0; i < 16; ++i) {
      valid[i] = i < m ? -1 : 0;
      rh.ray.tnear[i] = tnear;
      rh.ray.tfar[i] = tfar;
      rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    Intersect16(valid, &rh, &context);
    if (normal_out != nullptr) WorldNormals16(&rh);
    for (int i = 0; i < m; ++i) {
      const int k = base + i;
      const int id = HitId16(rh, i);
      hit_id_out[k] = id;
      t_out[k] = id == kNoHit ? kInf : rh.ray.tfar[i];
      if (normal_out != nullptr) {
        Eigen::Vector3f ng = Eigen::Vector3f::Zero();
        if (id != kNoHit) {
          ng = Eigen::Vector3f(rh.hit.Ng_x[i], rh.hit.Ng_y[i], rh.hit.Ng_z[i]);
          const float norm = ng.norm();
          if (norm > 0.0f) ng /= norm;
        }
        normal_out[3 * k] = ng.x();
        normal_out[3 * k + 1] = ng.y();
        normal_out[3 * k + 2] = ng.z();
      }
    }
  }
}

void RayScene::Intersect16(const int* valid, RTCRayHit16* rayhit,
                           RTCIntersectContext* context) const {
  rtcIntersect16(valid, static_->scene, context, rayhit);
  if (bodies_top_ != nullptr && PacketReaches(*rayhit, bodies_bounds_)) {
    rtcIntersect16(valid, bodies_top_, context, rayhit);
  }
}

void RayScene::Intersect(const float* ox, const float* oy, const float* oz, const float* dx,
                         const float* dy, const float* dz, int n, float tnear, float tfar,
                         float* t_out, int* hit_id_out, float* normal_out) const {
  Trace<false>(ox, oy, oz, dx, dy, dz, n, tnear, tfar, t_out, hit_id_out, normal_out);
}

void RayScene::IntersectFrom(const Eigen::Vector3f& origin, const float* dx, const float* dy,
                             const float* dz, int n, float tnear, float tfar, float* t_out,
                             int* hit_id_out, float* normal_out) const {
  Trace<true>(&origin.x(), &origin.y(), &origin.z(), dx, dy, dz, n, tnear, tfar, t_out,
              hit_id_out, normal_out);
}

}  // namespace minibot3d_sim
