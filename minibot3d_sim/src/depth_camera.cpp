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

void Validate(const CameraSpec& s) {
  const auto fail = [](const std::string& what) {
    throw std::invalid_argument("CameraSpec: " + what);
  };
  if (s.width < 1 || s.width > CameraSpec::kMaxSize) {
    fail("width must be in 1.." + Str(CameraSpec::kMaxSize) + ", got " + Str(s.width));
  }
  if (s.height < 1 || s.height > CameraSpec::kMaxSize) {
    fail("height must be in 1.." + Str(CameraSpec::kMaxSize) + ", got " + Str(s.height));
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

// One band's rays and hits, in tile order.
struct DepthCamera::Scratch {
  std::vector<float> dx, dy, dz, inv_len, t, normal;
  std::vector<int> id;

  explicit Scratch(int rays)
      : dx(rays), dy(rays), dz(rays), inv_len(rays), t(rays),
        normal(3 * static_cast<std::size_t>(rays)), id(rays) {}
};

DepthCamera::DepthCamera(const CameraSpec& spec) : spec_(spec), rng_(spec.seed) {
  Validate(spec_);
  const int w = spec_.width, h = spec_.height;
  focal_ = w / (2.0 * std::tan(0.5 * spec_.horizontal_fov));
  col_offset_.resize(w);
  row_offset_.resize(h);
  for (int u = 0; u < w; ++u) col_offset_[u] = static_cast<float>(-(u - 0.5 * (w - 1)) / focal_);
  for (int v = 0; v < h; ++v) row_offset_[v] = static_cast<float>(-(v - 0.5 * (h - 1)) / focal_);
  tiles_x_ = (w + kTile - 1) / kTile;
  bands_ = (h + kTile - 1) / kTile;
  threads_ = spec_.threads > 0 ? spec_.threads
                               : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  threads_ = std::min(threads_, bands_);
  pool_ = std::make_unique<WorkerPool>(threads_);
  for (int i = 0; i < threads_; ++i) scratch_.push_back(std::make_unique<Scratch>(tiles_x_ * kPacket));
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
  pool_->Run([&](int thread) {
    Scratch* scratch = scratch_[thread].get();
    for (int band = next_band.fetch_add(1); band < bands_; band = next_band.fetch_add(1)) {
      RenderBand(scene, camera_pose_in_world, band, scratch, out);
    }
  });

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

void DepthCamera::RenderBand(const RayScene& scene, const Eigen::Isometry3d& pose, int band,
                             Scratch* s, DepthFrame* out) const {
  const int w = spec_.width, h = spec_.height;
  const int v0 = band * kTile;
  const Eigen::Matrix3f r = pose.linear().cast<float>();
  const Eigen::Vector3f origin = pose.translation().cast<float>();
  const Eigen::Vector3f fwd = r.col(0), left = r.col(1), up = r.col(2);

  // Camera-frame direction (1, col_offset, row_offset), in the world; edge tiles repeat the last
  // column or row so every packet is full and always holds the same rays.
  int k = 0;
  for (int tx = 0; tx < tiles_x_; ++tx) {
    for (int dv = 0; dv < kTile; ++dv) {
      const float b = row_offset_[std::min(v0 + dv, h - 1)];
      for (int du = 0; du < kTile; ++du, ++k) {
        const float a = col_offset_[std::min(tx * kTile + du, w - 1)];
        s->dx[k] = fwd.x() + a * left.x() + b * up.x();
        s->dy[k] = fwd.y() + a * left.y() + b * up.y();
        s->dz[k] = fwd.z() + a * left.z() + b * up.z();
        s->inv_len[k] = 1.0f / std::sqrt(1.0f + a * a + b * b);
      }
    }
  }
  scene.IntersectFrom(origin, s->dx.data(), s->dy.data(), s->dz.data(), k, 0.0f,
                      static_cast<float>(spec_.far_clip), s->t.data(), s->id.data(),
                      s->normal.data());

  switch (spec_.format) {
    case PixelFormat::kR8G8B8:
      Shade<PixelFormat::kR8G8B8>(v0, *s, out);
      break;
    case PixelFormat::kB8G8R8:
      Shade<PixelFormat::kB8G8R8>(v0, *s, out);
      break;
    case PixelFormat::kL8:
      Shade<PixelFormat::kL8>(v0, *s, out);
      break;
  }
}

template <PixelFormat kFormat>
void DepthCamera::Shade(int v0, const Scratch& s, DepthFrame* out) const {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  constexpr int kChannels = kFormat == PixelFormat::kL8 ? 1 : 3;
  const int w = spec_.width, h = spec_.height;
  const float near = static_cast<float>(spec_.near_clip);
  // Entries are clamped and scaled to 0..255 and the shading factor is at most 1, so the bytes
  // need no clamping (a branch per channel otherwise).
  const Eigen::Vector3f* colors = colors_.data();
  const Eigen::Vector3f& background = background_;
  const int rows = std::min(kTile, h - v0);
  for (int tx = 0; tx < tiles_x_; ++tx) {
    const int u0 = tx * kTile;
    const int cols = std::min(kTile, w - u0);
    for (int dv = 0; dv < rows; ++dv) {
      const std::size_t row = static_cast<std::size_t>(v0 + dv) * w + u0;
      float* depth = &out->depth[row];
      int* hit_id = &out->hit_id[row];
      std::uint8_t* px = &out->rgb[row * kChannels];
      const int k0 = tx * kPacket + dv * kTile;
      for (int du = 0; du < cols; ++du, px += kChannels) {
        const int k = k0 + du;
        const int id = s.id[k];
        const float t = s.t[k];
        depth[du] = t < near ? kInf : t;
        hit_id[du] = id;
        Eigen::Vector3f color;
        if (id == RayScene::kNoHit) {
          color = background;
        } else {
          const float* n = &s.normal[3 * k];
          const float cos_view =
              std::abs(n[0] * s.dx[k] + n[1] * s.dy[k] + n[2] * s.dz[k]) * s.inv_len[k];
          color = colors[id] * (kAmbient + (1.0f - kAmbient) * std::min(cos_view, 1.0f));
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
