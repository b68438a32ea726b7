// 3-D ray casting against the world with Intel Embree 3 (Wald, Woop, Benthin, Johnson, Ernst:
// "Embree: A Kernel Framework for Efficient CPU Ray Tracing", ACM TOG 33(4), 2014).
//
// The static world becomes one Embree scene: boxes and meshes as triangles, cylinders (capped),
// spheres and planes as user geometry whose callbacks intersect the ray analytically, so a round
// pillar reads round at every pixel instead of showing the facets of a tessellation. Embree builds
// the BVH and traverses it; the callbacks only run for the rays that reach a primitive's box.
//
// Movable bodies (another robot, a walking person) get a scene each, placed by Embree instances in
// a small top-level scene of their own. Moving a body changes only its instance transform and
// rebuilds that top level (one box per body), never the static BVH. A packet is cast against the
// static scene, then against the bodies' scene only if the packet's segments, cut at the static
// hits, can reach the bodies' bounds. With one person in the apartment that costs a camera frame
// about 8 %; instancing the static scene under the same top level instead cost every ray the
// instance traversal, about 20 %.
//
// Rays go to Embree in packets of 16 (rtcIntersect16): rays that start together and point almost
// the same way (a 4×4 tile of camera pixels) visit mostly the same BVH nodes, so one traversal
// serves sixteen. Callers that want that speed hand in rays in coherent groups of 16.
//
// Ray parameters are in units of the direction's length: with a direction whose component along
// the camera's optical axis is 1, the hit distance t is the hit's z-depth (see depth_camera.h).
#ifndef MINIBOT3D_SIM_RAY_SCENE_H_
#define MINIBOT3D_SIM_RAY_SCENE_H_

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <embree3/rtcore.h>

#include "minibot3d_sim/world.h"

namespace minibot3d_sim {

// An Embree call failed; the message names the call, Embree's error code and its text.
class RaySceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What a hit id stands for.
struct HitTarget {
  int body = -1;   // −1: the static world; otherwise the index AddBody returned
  int shape = -1;  // index into World::shapes, or into that body's shapes
};

class RayScene {
 public:
  static constexpr int kNoHit = -1;

  // Builds the static scene from `world`. `device` may be shared by several scenes and must then
  // outlive them (the scene sets the device's error function); null makes one of the scene's own.
  // Throws RaySceneError.
  explicit RayScene(const World& world, RTCDevice device = nullptr);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // A rigid set of shapes (poses in the body frame), invisible until the next Commit(); its pose is
  // the identity until SetBodyPose. Returns the body's index (0, 1, ...). Throws
  // std::invalid_argument for an empty body.
  int AddBody(std::vector<Shape> shapes_in_body_frame, std::string name);
  // Takes effect at the next Commit(): rays cast before it still see the old pose.
  void SetBodyPose(int body, const Eigen::Isometry3d& pose_in_world);
  // Makes added bodies and new poses visible. AddBody, SetBodyPose and Commit must not run
  // concurrently with a cast or with each other.
  void Commit();

  // Casts n rays, ray i from (ox[i], oy[i], oz[i]) along (dx[i], dy[i], dz[i]) (any non-zero
  // length) in the world frame, and reports the nearest hit with tnear ≤ t ≤ tfar: t_out[i] (in
  // units of the direction's length; +inf for none), hit_id_out[i] (kNoHit for none) and, when
  // normal_out is not null, the unit geometric normal in the world frame at normal_out[3i..3i+2]
  // (either side of the surface; zero for none). Rays are traced 16 at a time in the order given.
  // Safe to call from several threads at once.
  void Intersect(const float* ox, const float* oy, const float* oz, const float* dx,
                 const float* dy, const float* dz, int n, float tnear, float tfar, float* t_out,
                 int* hit_id_out, float* normal_out = nullptr) const;
  // The same for rays that share one origin (a camera, a lidar).
  void IntersectFrom(const Eigen::Vector3f& origin, const float* dx, const float* dy,
                     const float* dz, int n, float tnear, float tfar, float* t_out,
                     int* hit_id_out, float* normal_out = nullptr) const;

  // Low level, for sensors that lay out Embree packets themselves and read the hits straight from
  // them (DepthCamera), saving the copies in and out of the arrays above. Casts the lanes with
  // valid[i] = −1: the caller fills org, dir, tnear, tfar, time = 0, mask = ~0u, flags = 0 and
  // sets hit.geomID[i] and hit.instID[0][i] to RTC_INVALID_GEOMETRY_ID; afterwards ray.tfar[i] is
  // the nearest hit's t where HitId16 is not kNoHit.
  void Intersect16(const int* valid, RTCRayHit16* rayhit, RTCIntersectContext* context) const;
  int HitId16(const RTCRayHit16& rayhit, int lane) const {
    const unsigned geom = rayhit.hit.geomID[lane];
    if (geom == RTC_INVALID_GEOMETRY_ID) return kNoHit;
    const unsigned inst = rayhit.hit.instID[0][lane];
    const int* const* tables = inst == RTC_INVALID_GEOMETRY_ID ? static_tables_ : body_tables_[inst];
    return tables[geom][rayhit.hit.primID[lane]];
  }
  // Turns the geometric normals of the hits on bodies, which Embree leaves in the body's frame, into
  // the world frame: afterwards hit.Ng of every hit lane is a world-frame normal, not normalised.
  void WorldNormals16(RTCRayHit16* rayhit) const {
    for (int i = 0; i < 16; ++i) {
      const unsigned inst = rayhit->hit.instID[0][i];
      if (inst == RTC_INVALID_GEOMETRY_ID || rayhit->hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) {
        continue;
      }
      const Eigen::Vector3f n = body_rotations_[inst] * Eigen::Vector3f(
          rayhit->hit.Ng_x[i], rayhit->hit.Ng_y[i], rayhit->hit.Ng_z[i]);
      rayhit->hit.Ng_x[i] = n.x();
      rayhit->hit.Ng_y[i] = n.y();
      rayhit->hit.Ng_z[i] = n.z();
    }
  }

  // Hit ids are dense: static shape i has id i; the shapes of each body follow, body by body.
  int num_hit_ids() const { return static_cast<int>(targets_.size()); }
  int num_bodies() const { return static_cast<int>(bodies_.size()); }
  int BodyHitId(int body, int shape) const;
  HitTarget Target(int hit_id) const;
  // "model::link::collision" for the static world, "body_name::shape_name" for a body.
  const std::string& HitName(int hit_id) const;
  const Eigen::Vector3f& HitColor(int hit_id) const;
  // Every hit id's colour, indexed by hit id (for per-pixel shading without a call per pixel).
  const std::vector<Eigen::Vector3f>& hit_colors() const { return colors_; }
  const std::string& body_name(int body) const;

 private:
  struct SubScene;
  struct Body;

  template <bool kCommonOrigin>
  void Trace(const float* ox, const float* oy, const float* oz, const float* dx, const float* dy,
             const float* dz, int n, float tnear, float tfar, float* t_out, int* hit_id_out,
             float* normal_out) const;
  void CheckBody(int body, const char* what) const;

  RTCDevice device_ = nullptr;
  bool own_device_ = false;
  std::unique_ptr<SubScene> static_;
  std::vector<std::unique_ptr<Body>> bodies_;
  // Instances of the committed bodies (instance id b: body b); null until a body is committed.
  RTCScene bodies_top_ = nullptr;
  RTCBounds bodies_bounds_{};
  // [geomID][primID] → hit id, for the static scene and per body instance; and the rotation that
  // takes Embree's object-space normals of a body to the world frame, as of the last Commit().
  const int* const* static_tables_ = nullptr;
  std::vector<const int* const*> body_tables_;
  std::vector<Eigen::Matrix3f> body_rotations_;
  std::vector<HitTarget> targets_;
  std::vector<std::string> names_;
  std::vector<Eigen::Vector3f> colors_;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_RAY_SCENE_H_
