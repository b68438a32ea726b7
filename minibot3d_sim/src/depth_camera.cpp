// Depth camera rendering by ray casting; see depth_camera.h.
#include "minibot3d_sim/depth_camera.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

#include <embree3/rtcore.h>

namespace minibot3d_sim {
namespace {

// A tile of kTile × kTile pixels is one Embree packet of 16 rays.
constexpr int kTile = 4;
constexpr int kPacket = kTile * kTile;
// Share of the colour a surface keeps when seen edge-on (see the header).
constexpr float kAmbient = 0.3f;

template <typename T>
std::string Str(T v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void Validate(const DepthCameraSpec& s) {
  const auto fail = [](const std::string& what) {
    throw std::invalid_argument("DepthCameraSpec: " + what);
  };
  if (s.width < 1 || s.width > DepthCameraSpec::kMaxSize) {
    fail("width must be in 1.." + Str(DepthCameraSpec::kMaxSize) + ", got " + Str(s.width));
  }
  if (s.height < 1 || s.height > DepthCameraSpec::kMaxSize) {
    fail("height must be in 1.." + Str(DepthCameraSpec::kMaxSize) + ", got " + Str(s.height));
  }
  if (!(s.horizontal_fov > 0.0 && s.horizontal_fov < M_PI)) {
    fail("horizontal_fov must be in (0, pi) rad, got " + Str(s.horizontal_fov));
  }
  if (!(s.near_clip > 0.0) || !std::isfinite(s.near_clip)) {
    fail("near_clip must be > 0, got " + Str(s.near_clip));
  }
  if (!(s.far_clip > s.near_clip) || !std::isfinite(s.far_clip)) {
    fail("far_clip must be finite and > near_clip (" + Str(s.near_clip) + "), got " +
         Str(s.far_clip));
  }
  if (!(s.noise_stddev >= 0.0) || !std::isfinite(s.noise_stddev)) {
    fail("noise_stddev must be >= 0, got " + Str(s.noise_stddev));
  }
  if (!std::isfinite(s.noise_mean)) fail("noise_mean must be finite, got " + Str(s.noise_mean));
  if (s.threads < 0) fail("threads must be >= 0 (0: one per core), got " + Str(s.threads));
  for (int i = 0; i < 3; ++i) {
    if (!(s.background[i] >= 0.0f && s.background[i] <= 1.0f)) {
      fail("background must be RGB in [0, 1], got " + Str(s.background.transpose()));
    }
  }
}

// An RGB colour in [0, 1] as the image stores it: 0..255 per channel in the format's order, or the
// Rec. 601 luma for L8 (in x).
Eigen::Vector3f ImageColor(const Eigen::Vector3f& rgb, PixelFormat format) {
  const Eigen::Vector3f c = rgb.cwiseMax(0.0f).cwiseMin(1.0f) * 255.0f;
  switch (format) {
    case PixelFormat::kR8G8B8:
      return c;
    case PixelFormat::kB8G8R8:
      return Eigen::Vector3f(c.z(), c.y(), c.x());
    case PixelFormat::kL8:
      return Eigen::Vector3f::Constant(0.299f * c.x() + 0.587f * c.y() + 0.114f * c.z());
  }
  return c;
}

}  // namespace

// Threads that live as long as the camera, so a frame costs a wake-up rather than a thread start.
class DepthCamera::WorkerPool {
 public:
  explicit WorkerPool(int threads) {
    for (int i = 1; i < threads; ++i) workers_.emplace_back([this, i] { Loop(i); });
  }

  ~WorkerPool() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
  }

  // Runs job(thread index) on the caller (index 0) and every worker; returns when all are done,
  // rethrowing the first exception any of them raised.
  void Run(const std::function<void(int)>& job) {
    if (workers_.empty()) {
      job(0);
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      job_ = &job;
      error_ = nullptr;
      pending_ = static_cast<int>(workers_.size());
      ++generation_;
    }
    wake_.notify_all();
    std::exception_ptr mine;
    try {
      job(0);
    } catch (...) {
      mine = std::current_exception();
    }
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return pending_ == 0; });
    job_ = nullptr;
    if (mine) std::rethrow_exception(mine);
    if (error_) std::rethrow_exception(error_);
  }

 private:
  void Loop(int index) {
    std::uint64_t seen = 0;
    for (;;) {
      const std::function<void(int)>* job;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
        if (stop_) return;
        seen = generation_;
        job = job_;
      }
      std::exception_ptr error;
      try {
        (*job)(index);
      } catch (...) {
        error = std::current_exception();
      }
      std::lock_guard<std::mutex> lock(mutex_);
      if (error && !error_) error_ = error;
      if (--pending_ == 0) done_.notify_one();
    }
  }

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void(int)>* job_ = nullptr;
  std::exception_ptr error_;
  std::uint64_t generation_ = 0;
  int pending_ = 0;
  bool stop_ = false;
};

DepthCamera::DepthCamera(const DepthCameraSpec& spec) : spec_(spec), rng_(spec.seed) {
  Validate(spec_);
  const int w = spec_.width, h = spec_.height;
  focal_ = w / (2.0 * std::tan(0.5 * spec_.horizontal_fov));
  tiles_x_ = (w + kTile - 1) / kTile;
  bands_ = (h + kTile - 1) / kTile;
  // Padded to whole tiles by repeating the last column and row: every packet is full and always
  // holds the same rays.
  col_offset_.resize(tiles_x_ * kTile);
  row_offset_.resize(bands_ * kTile);
  for (int u = 0; u < tiles_x_ * kTile; ++u) {
    col_offset_[u] = static_cast<float>(-(std::min(u, w - 1) - 0.5 * (w - 1)) / focal_);
  }
  for (int v = 0; v < bands_ * kTile; ++v) {
    row_offset_[v] = static_cast<float>(-(std::min(v, h - 1) - 0.5 * (h - 1)) / focal_);
  }
  threads_ = spec_.threads > 0 ? spec_.threads
                               : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  threads_ = std::min(threads_, bands_);
  pool_ = std::make_unique<WorkerPool>(threads_);
}

DepthCamera::~DepthCamera() = default;

CameraIntrinsics DepthCamera::Intrinsics() const {
  return CameraIntrinsics{focal_, focal_, (spec_.width + 1) / 2.0, (spec_.height + 1) / 2.0};
}

void DepthCamera::Render(const RayScene& scene, const Eigen::Isometry3d& camera_pose_in_world,
                         DepthFrame* out) {
  const int w = spec_.width, h = spec_.height;
  const std::size_t pixels = static_cast<std::size_t>(w) * h;
  out->width = w;
  out->height = h;
  out->channels = spec_.format == PixelFormat::kL8 ? 1 : 3;
  out->depth.resize(pixels);
  out->rgb.resize(pixels * out->channels);
  out->hit_id.resize(pixels);

  const std::vector<Eigen::Vector3f>& colors = scene.hit_colors();
  colors_.resize(colors.size());
  for (std::size_t i = 0; i < colors.size(); ++i) colors_[i] = ImageColor(colors[i], spec_.format);
  background_ = ImageColor(spec_.background, spec_.format);

  std::atomic<int> next_band{0};
  const auto render = [&](auto band_renderer) {
    pool_->Run([&](int /*thread*/) {
      for (int band = next_band.fetch_add(1); band < bands_; band = next_band.fetch_add(1)) {
        (this->*band_renderer)(scene, camera_pose_in_world, band, out);
      }
    });
  };
  switch (spec_.format) {
    case PixelFormat::kR8G8B8:
      render(&DepthCamera::RenderBand<PixelFormat::kR8G8B8>);
      break;
    case PixelFormat::kB8G8R8:
      render(&DepthCamera::RenderBand<PixelFormat::kB8G8R8>);
      break;
    case PixelFormat::kL8:
      render(&DepthCamera::RenderBand<PixelFormat::kL8>);
      break;
  }

  if (spec_.noise_stddev > 0.0 || spec_.noise_mean != 0.0) {
    std::normal_distribution<double> noise(spec_.noise_mean,
                                           spec_.noise_stddev > 0.0 ? spec_.noise_stddev : 1.0);
    const float near = static_cast<float>(spec_.near_clip), far = static_cast<float>(spec_.far_clip);
    for (float& d : out->depth) {
      if (!std::isfinite(d)) continue;
      const double n = spec_.noise_stddev > 0.0 ? noise(rng_) : spec_.noise_mean;
      d = static_cast<float>(d + n);
      if (d < near || d > far) d = std::numeric_limits<float>::infinity();
    }
  }
}

template <PixelFormat kFormat>
void DepthCamera::RenderBand(const RayScene& scene, const Eigen::Isometry3d& pose, int band,
                             DepthFrame* out) const {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  constexpr int kChannels = kFormat == PixelFormat::kL8 ? 1 : 3;
  const int w = spec_.width, h = spec_.height;
  const int v0 = band * kTile;
  const int rows = std::min(kTile, h - v0);
  const float near = static_cast<float>(spec_.near_clip);
  const float far = static_cast<float>(spec_.far_clip);
  const Eigen::Matrix3f r = pose.linear().cast<float>();
  const Eigen::Vector3f origin = pose.translation().cast<float>();
  const Eigen::Vector3f fwd = r.col(0), left = r.col(1), up = r.col(2);
  // Entries are clamped and scaled to 0..255 and the shading factor is at most 1, so the bytes
  // need no clamping (a branch per channel otherwise).
  const Eigen::Vector3f* colors = colors_.data();
  const float* b = &row_offset_[v0];

  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[kPacket];
  for (int i = 0; i < kPacket; ++i) {
    valid[i] = -1;
    rh.ray.org_x[i] = origin.x();
    rh.ray.org_y[i] = origin.y();
    rh.ray.org_z[i] = origin.z();
    rh.ray.tnear[i] = 0.0f;
    rh.ray.time[i] = 0.0f;
    rh.ray.mask[i] = 0xFFFFFFFFu;
    rh.ray.id[i] = static_cast<unsigned>(i);
    rh.ray.flags[i] = 0;
  }
  for (int tx = 0; tx < tiles_x_; ++tx) {
    const int u0 = tx * kTile;
    const float* a = &col_offset_[u0];
    // Lane i is pixel (u0 + i % 4, v0 + i / 4): camera-frame direction (1, a, b) in the world.
    for (int i = 0; i < kPacket; ++i) {
      const float ai = a[i % kTile], bi = b[i / kTile];
      rh.ray.dir_x[i] = fwd.x() + ai * left.x() + bi * up.x();
      rh.ray.dir_y[i] = fwd.y() + ai * left.y() + bi * up.y();
      rh.ray.dir_z[i] = fwd.z() + ai * left.z() + bi * up.z();
      rh.ray.tfar[i] = far;
      rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    scene.Intersect16(valid, &rh, &context);
    scene.WorldNormals16(&rh);
    // The headlight term of all 16 lanes at once (lanes without a hit compute garbage, unused).
    alignas(64) float shade[kPacket];
    for (int i = 0; i < kPacket; ++i) {
      const float nx = rh.hit.Ng_x[i], ny = rh.hit.Ng_y[i], nz = rh.hit.Ng_z[i];
      const float dx = rh.ray.dir_x[i], dy = rh.ray.dir_y[i], dz = rh.ray.dir_z[i];
      const float cos_view = std::abs(nx * dx + ny * dy + nz * dz) /
                             std::sqrt((nx * nx + ny * ny + nz * nz) * (dx * dx + dy * dy + dz * dz));
      shade[i] = kAmbient + (1.0f - kAmbient) * std::min(cos_view, 1.0f);
    }

    const int cols = std::min(kTile, w - u0);
    for (int dv = 0; dv < rows; ++dv) {
      const std::size_t row = static_cast<std::size_t>(v0 + dv) * w + u0;
      float* depth = &out->depth[row];
      int* hit_id = &out->hit_id[row];
      std::uint8_t* px = &out->rgb[row * kChannels];
      for (int du = 0; du < cols; ++du, px += kChannels) {
        const int i = dv * kTile + du;
        const int id = scene.HitId16(rh, i);
        hit_id[du] = id;
        Eigen::Vector3f color;
        if (id == RayScene::kNoHit) {
          depth[du] = kInf;
          color = background_;
        } else {
          const float t = rh.ray.tfar[i];
          depth[du] = t < near ? kInf : t;
          color = colors[id] * shade[i];
        }
        px[0] = static_cast<std::uint8_t>(static_cast<int>(color.x() + 0.5f));
        if (kChannels == 3) {
          px[1] = static_cast<std::uint8_t>(static_cast<int>(color.y() + 0.5f));
          px[2] = static_cast<std::uint8_t>(static_cast<int>(color.z() + 0.5f));
        }
      }
    }
  }
}

void PointsFromDepth(const DepthFrame& frame, double focal_length, double cutoff,
                     double cutoff_max, std::vector<float>* points) {
  const int w = frame.width, h = frame.height;
  points->resize(static_cast<std::size_t>(w) * h * 3);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const double cu = 0.5 * (w - 1), cv = 0.5 * (h - 1);
  float* out = points->data();
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u, out += 3) {
      const double d = frame.depth[static_cast<std::size_t>(v) * w + u];
      if (std::isfinite(d) && d > cutoff && (cutoff_max < 0.0 || d < cutoff_max)) {
        out[0] = static_cast<float>(d * (u - cu) / focal_length);
        out[1] = static_cast<float>(d * (v - cv) / focal_length);
        out[2] = static_cast<float>(d);
      } else {
        out[0] = out[1] = out[2] = nan;
      }
    }
  }
}

}  // namespace minibot3d_sim
