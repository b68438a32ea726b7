// A depth + colour camera modelled on Gazebo's <sensor type="depth"> and the gazebo_ros depth camera
// plugins, ray cast with Embree (ray_scene.h) instead of rasterised.
//
// Frames. The pose handed to Render() is Gazebo's camera frame: it looks along its +x, y left,
// z up. Images come out in the optical convention of ROS images (REP 103 "_optical" frames): x
// right, y down, z forward; row 0 is the top of the image, column 0 its left.
//
// Pixel rays. Square pixels with focal length f = W / (2·tan(hfov/2)) (pixels), rendered through
// pixel centres as Gazebo's OpenGL camera does: the image spans exactly hfov from the left edge of
// column 0 to the right edge of column W − 1, so pixel (u, v) (column, row, from 0) looks along
//     optical frame:  d = ((u − (W − 1)/2) / f,  (v − (H − 1)/2) / f,  1)
//     camera frame:   d = (1,  −(u − (W − 1)/2) / f,  −(v − (H − 1)/2) / f)
// and the ray is o + t·d in the world, with o the camera position and d rotated by the camera's
// orientation. The component of d along the optical axis is 1, so the t at which the ray meets a
// surface is that point's z-depth: depth images hold z-depth (distance along the optical axis, as
// OpenGL's depth buffer and Gazebo's depth camera give it), not ray length.
//
// Intrinsics. CameraInfo, as gazebo_ros_camera_utils fills it, reports fx = fy = f and
// cx = (W + 1)/2, cy = (H + 1)/2: half a pixel off the (W − 1)/2, (H − 1)/2 the rays go through.
// That difference is Gazebo's; it is kept so that consumers see the numbers they see with Gazebo.
//
// Clipping. Hits farther than the far clip are not hits (+inf, background colour); hits nearer
// than the near clip read +inf in the depth image, like a real sensor's minimum range. The colour
// image still shows such a near surface (it blocks the view; nothing behind it is visible).
//
// Colour. Flat shading from the hit shape's colour c with a headlight: the light comes from the
// camera, so a surface lit face-on is brightest and faces at different angles to the view differ:
//     rgb = c · (kAmbient + (1 − kAmbient)·|n·v|),   n unit normal, v unit view ray,
// with kAmbient = 0.3 so grazing faces are dimmed, not black. No shadows, no specular. Pixels with
// no hit are the background colour (Gazebo's default scene background, 0.7 grey).
//
// Noise. Optional Gaussian noise N(mean, stddev²) on the depth of every pixel with a return, drawn
// after the whole image is cast, in pixel order, from a generator seeded once: a frame depends only
// on the seed and the frames before it, never on the thread count. A noisy depth that leaves
// [near, far] becomes +inf.
//
// Speed. The rays of a 4×4 tile of pixels form one Embree packet of 16, built in place and shaded
// straight from Embree's hit record; the image is cut into bands of tile rows that worker threads
// take in turn. Directions are made per frame from two per-camera tables (one value per column,
// one per row), so nothing is allocated per ray or per frame.
#ifndef MINIBOT3D_SIM_DEPTH_CAMERA_H_
#define MINIBOT3D_SIM_DEPTH_CAMERA_H_

#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "minibot3d_sim/ray_scene.h"

namespace minibot3d_sim {

// Gazebo's <image><format> for the colour image.
enum class PixelFormat { kR8G8B8, kB8G8R8, kL8 };

struct DepthCameraSpec {
  static constexpr int kMaxSize = 32768;

  int width = 320;                // <image><width>, 1 .. kMaxSize
  int height = 240;               // <image><height>, 1 .. kMaxSize
  double horizontal_fov = 1.047;  // <horizontal_fov> (rad), in (0, π)
  double near_clip = 0.05;        // <clip><near> (m), > 0
  double far_clip = 10.0;         // <clip><far> (m), > near
  PixelFormat format = PixelFormat::kR8G8B8;  // colour image only
  double noise_mean = 0.0;        // depth noise (m)
  double noise_stddev = 0.0;      // depth noise (m), ≥ 0; 0 and a zero mean: no noise
  unsigned seed = 0;              // for the noise
  int threads = 0;                // rendering threads; 0: std::thread::hardware_concurrency()
  Eigen::Vector3f background = Eigen::Vector3f(0.7f, 0.7f, 0.7f);  // RGB in [0, 1]
};

// CameraInfo's K as gazebo_ros_camera_utils fills it (see the header comment).
struct CameraIntrinsics {
  double fx, fy, cx, cy;
};

struct DepthFrame {
  int width = 0, height = 0;
  int channels = 0;           // 3 (R8G8B8, B8G8R8) or 1 (L8)
  std::vector<float> depth;   // W×H z-depth (m), row-major, row 0 at the top; +inf: no return
  std::vector<std::uint8_t> rgb;  // W×H×channels
  // W×H RayScene hit ids: the shape seen, also where the near clip cut its depth; kNoHit for none.
  std::vector<int> hit_id;
};

class DepthCamera {
 public:
  // Throws std::invalid_argument naming the offending field and value.
  explicit DepthCamera(const DepthCameraSpec& spec);
  ~DepthCamera();
  DepthCamera(const DepthCamera&) = delete;
  DepthCamera& operator=(const DepthCamera&) = delete;

  // Renders one frame with the Gazebo camera frame at `camera_pose_in_world`. `out` is resized as
  // needed (no allocation once it has the right size). One frame at a time per camera.
  void Render(const RayScene& scene, const Eigen::Isometry3d& camera_pose_in_world,
              DepthFrame* out);

  CameraIntrinsics Intrinsics() const;
  // f in pixels, for both axes.
  double focal_length() const { return focal_; }
  const DepthCameraSpec& spec() const { return spec_; }
  int threads() const { return threads_; }
  void Reseed(unsigned seed) { rng_.seed(seed); }

 private:
  class WorkerPool;

  // Casts and shades the 4 rows of pixels [4·band, 4·band + 4).
  template <PixelFormat kFormat>
  void RenderBand(const RayScene& scene, const Eigen::Isometry3d& pose, int band,
                  DepthFrame* out) const;

  const DepthCameraSpec spec_;
  double focal_ = 0.0;
  int threads_ = 1;
  int tiles_x_ = 0, bands_ = 0;
  // −(u − (W−1)/2)/f and −(v − (H−1)/2)/f, padded to whole tiles with the last column and row.
  std::vector<float> col_offset_, row_offset_;
  std::unique_ptr<WorkerPool> pool_;
  // The scene's colours and the background as the image stores them (per frame: bodies may come).
  std::vector<Eigen::Vector3f> colors_;
  Eigen::Vector3f background_;
  std::mt19937 rng_;
};

// The organised cloud of gazebo_ros_depth_camera (optical frame, one point per pixel, row-major):
// x = d·(u − (W−1)/2)/f, y = d·(v − (H−1)/2)/f, z = d for depth d; NaN for all three where there is
// no return or d is not within (cutoff, cutoff_max) (the plugin's pointCloudCutoff and
// pointCloudCutoffMax; cutoff_max < 0: no upper cutoff, as the plugin reads it). `points` holds
// W×H×3 floats.
void PointsFromDepth(const DepthFrame& frame, double focal_length, double cutoff,
                     double cutoff_max, std::vector<float>* points);

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_DEPTH_CAMERA_H_
