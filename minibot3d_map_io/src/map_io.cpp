// Maps on disk in ROS map_server's format (see map_io.h). Loading follows map_server's
// image_loader: the mean of the colour channels is turned into an occupancy probability
// p = (255 - mean) / 255 (mean / 255 with negate) and classified by the YAML's thresholds.
// Saving follows map_saver: three grey levels, classified by the --occ/--free percentages.
#include "minibot3d_map_io/map_io.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "minibot3d_map_io/file_util.h"

namespace minibot3d_map_io {
namespace {

namespace fs = std::filesystem;

// The grey levels map_saver writes, and the YAML thresholds that read exactly those levels back:
// 205 is p = 50/255 = 0.19608, just above 0.196 and far below 0.65, so it stays unknown; 254 is
// p = 0.0039 (free) and 0 is p = 1 (occupied).
constexpr unsigned char kOccupiedPixel = 0;
constexpr unsigned char kFreePixel = 254;
constexpr unsigned char kUnknownPixel = 205;
constexpr double kSavedOccupiedThresh = 0.65;
constexpr double kSavedFreeThresh = 0.196;

enum class MapMode { kTrinary, kScale, kRaw };

[[noreturn]] void Fail(const std::string& yaml_path, const std::string& what) {
  throw MapIoError("map YAML '" + yaml_path + "': " + what);
}

std::string Show(const YAML::Node& node) {
  if (node.IsScalar()) return "'" + node.Scalar() + "'";
  std::ostringstream out;
  out << YAML::Dump(node);
  return "'" + out.str() + "'";
}

YAML::Node Require(const YAML::Node& root, const std::string& key, const std::string& yaml_path) {
  const YAML::Node node = root[key];
  if (!node || node.IsNull()) Fail(yaml_path, "missing key '" + key + "'");
  return node;
}

double ReadNumber(const YAML::Node& node, const std::string& key, const std::string& yaml_path) {
  double v = 0.0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, v) || !std::isfinite(v)) {
    Fail(yaml_path, "'" + key + "' must be a finite number, got " + Show(node));
  }
  return v;
}

bool ReadNegate(const YAML::Node& node, const std::string& yaml_path) {
  // map_server reads an int; true/false are accepted too because hand-written YAMLs use them.
  int as_int = 0;
  bool as_bool = false;
  if (node.IsScalar() && YAML::convert<int>::decode(node, as_int) && (as_int == 0 || as_int == 1)) {
    return as_int == 1;
  }
  if (node.IsScalar() && YAML::convert<bool>::decode(node, as_bool)) return as_bool;
  Fail(yaml_path, "'negate' must be 0 or 1, got " + Show(node));
}

MapMode ReadMode(const YAML::Node& root, const std::string& yaml_path) {
  const YAML::Node node = root["mode"];
  if (!node || node.IsNull()) return MapMode::kTrinary;
  if (node.IsScalar()) {
    if (node.Scalar() == "trinary") return MapMode::kTrinary;
    if (node.Scalar() == "scale") return MapMode::kScale;
    if (node.Scalar() == "raw") return MapMode::kRaw;
  }
  Fail(yaml_path, "'mode' must be trinary, scale or raw, got " + Show(node));
}

// Reads the image unchanged (grey, BGR or BGRA, 8 or 16 bit) as 8-bit with 1, 3 or 4 channels.
cv::Mat ReadImage(const std::string& image_path, const std::string& yaml_path) {
  std::error_code ec;
  if (!fs::exists(image_path, ec)) {
    Fail(yaml_path, "image '" + image_path + "' does not exist");
  }
  if (fs::is_directory(image_path, ec)) {
    Fail(yaml_path, "image '" + image_path + "' is a directory");
  }
  cv::Mat img;
  try {
    img = cv::imread(image_path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    Fail(yaml_path, "image '" + image_path + "' cannot be read: " + e.what());
  }
  if (img.empty()) {
    Fail(yaml_path, "image '" + image_path + "' cannot be read as an image (PGM, PNG, ...)");
  }
  if (img.depth() == CV_16U) {
    cv::Mat eight;
    img.convertTo(eight, CV_8U, 1.0 / 257.0);  // 65535 -> 255, as an 8-bit reader would see it
    img = eight;
  } else if (img.depth() != CV_8U) {
    Fail(yaml_path, "image '" + image_path + "' has an unsupported pixel depth (8 or 16 bit only)");
  }
  if (img.channels() != 1 && img.channels() != 3 && img.channels() != 4) {
    Fail(yaml_path, "image '" + image_path + "' has " + std::to_string(img.channels()) +
                        " channels (1, 3 or 4 expected)");
  }
  return img;
}

// One pixel to one cell value, as map_server's image_loader does it.
std::int8_t CellValue(double mean, int alpha, bool negate, MapMode mode, double occ_th,
                      double free_th) {
  if (negate) mean = 255.0 - mean;
  if (mode == MapMode::kRaw) {
    // map_server stores the (possibly negated) mean truncated to a byte: 0..255 as int8.
    return static_cast<std::int8_t>(static_cast<std::uint8_t>(mean));
  }
  const double p = (255.0 - mean) / 255.0;
  if (p > occ_th) return 100;
  if (p < free_th) return 0;
  // A fully transparent pixel is unknown whatever its colour.
  if (mode == MapMode::kTrinary || alpha == 0) return -1;
  return static_cast<std::int8_t>(99.0 * (p - free_th) / (occ_th - free_th));
}

// A YAML float: the shortest text that reads back as `v`, with a decimal point where it would
// otherwise read as an integer (0.0, -4.0), as YAML's float syntax and map_server's maps have it.
std::string YamlFloat(double v) {
  std::string text = FormatDouble(v);
  if (text.find_first_of(".eEn") == std::string::npos) text += ".0";  // 'n': nan, inf
  return text;
}

void CheckGrid(const OccupancyGrid& map, const std::string& what) {
  if (map.width <= 0 || map.height <= 0) {
    throw MapIoError("cannot save " + what + ": the map is empty (" + std::to_string(map.width) +
                     " x " + std::to_string(map.height) + " cells)");
  }
  const std::size_t cells = static_cast<std::size_t>(map.width) * map.height;
  if (map.data.size() != cells) {
    throw MapIoError("cannot save " + what + ": " + std::to_string(map.width) + " x " +
                     std::to_string(map.height) + " cells but " +
                     std::to_string(map.data.size()) + " values");
  }
  if (!(map.resolution > 0.0) || !std::isfinite(map.resolution)) {
    throw MapIoError("cannot save " + what + ": resolution must be positive, got " +
                     FormatDouble(map.resolution));
  }
  if (!std::isfinite(map.origin_x) || !std::isfinite(map.origin_y) ||
      !std::isfinite(map.origin_theta)) {
    throw MapIoError("cannot save " + what + ": the origin is not finite");
  }
}

}  // namespace

OccupancyGrid LoadMap(const std::string& yaml_path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path);
  } catch (const YAML::BadFile&) {
    throw MapIoError("map YAML '" + yaml_path + "' cannot be opened");
  } catch (const YAML::Exception& e) {
    // e.mark.line is 0-based; -1 when unknown.
    throw MapIoError("map YAML '" + yaml_path + "'" +
                     (e.mark.line >= 0 ? " line " + std::to_string(e.mark.line + 1) : "") +
                     " does not parse: " + e.msg);
  }
  if (!root.IsMap()) Fail(yaml_path, "expected a mapping of keys (image, resolution, ...)");

  try {
    const YAML::Node image_node = Require(root, "image", yaml_path);
    if (!image_node.IsScalar() || image_node.Scalar().empty()) {
      Fail(yaml_path, "'image' must be a file name, got " + Show(image_node));
    }
    const double resolution = ReadNumber(Require(root, "resolution", yaml_path), "resolution",
                                         yaml_path);
    if (resolution <= 0.0) {
      Fail(yaml_path, "'resolution' must be positive, got " + FormatDouble(resolution));
    }
    const YAML::Node origin = Require(root, "origin", yaml_path);
    if (!origin.IsSequence() || origin.size() != 3) {
      Fail(yaml_path, "'origin' must be [x, y, yaw], got " + Show(origin));
    }
    const bool negate = ReadNegate(Require(root, "negate", yaml_path), yaml_path);
    const double occ_th = ReadNumber(Require(root, "occupied_thresh", yaml_path),
                                     "occupied_thresh", yaml_path);
    const double free_th = ReadNumber(Require(root, "free_thresh", yaml_path), "free_thresh",
                                      yaml_path);
    if (occ_th < 0.0 || occ_th > 1.0) {
      Fail(yaml_path, "'occupied_thresh' must be within [0, 1], got " +
                          FormatDouble(occ_th));
    }
    if (free_th < 0.0 || free_th > 1.0) {
      Fail(yaml_path, "'free_thresh' must be within [0, 1], got " +
                          FormatDouble(free_th));
    }
    if (occ_th < free_th) {
      Fail(yaml_path, "'occupied_thresh' (" + FormatDouble(occ_th) +
                          ") is below 'free_thresh' (" + FormatDouble(free_th) + ")");
    }
    const MapMode mode = ReadMode(root, yaml_path);
    if (mode == MapMode::kScale && occ_th == free_th) {
      Fail(yaml_path, "mode scale needs 'free_thresh' below 'occupied_thresh'");
    }

    OccupancyGrid map;
    map.resolution = resolution;
    map.origin_x = ReadNumber(origin[0], "origin[0]", yaml_path);
    map.origin_y = ReadNumber(origin[1], "origin[1]", yaml_path);
    map.origin_theta = ReadNumber(origin[2], "origin[2]", yaml_path);

    fs::path image_path(image_node.Scalar());
    if (image_path.is_relative()) image_path = fs::path(yaml_path).parent_path() / image_path;
    const cv::Mat img = ReadImage(image_path.string(), yaml_path);

    map.width = img.cols;
    map.height = img.rows;
    map.data.assign(static_cast<std::size_t>(map.width) * map.height, -1);
    const int n = img.channels();
    const bool has_alpha = n == 4;
    // map_server averages alpha in with the colours in trinary mode (kept for compatibility),
    // and leaves it out in scale and raw mode.
    const int avg_channels = (mode == MapMode::kTrinary || !has_alpha) ? n : n - 1;
    for (int row = 0; row < img.rows; ++row) {
      const unsigned char* px = img.ptr<unsigned char>(row);
      // Image row 0 is the top of the map (largest y); grid row 0 is the bottom.
      std::int8_t* cells =
          map.data.data() + static_cast<std::size_t>(img.rows - 1 - row) * img.cols;
      for (int col = 0; col < img.cols; ++col, px += n) {
        int sum = 0;
        for (int k = 0; k < avg_channels; ++k) sum += px[k];
        const int alpha = has_alpha ? px[n - 1] : 255;
        cells[col] = CellValue(static_cast<double>(sum) / avg_channels, alpha, negate, mode,
                               occ_th, free_th);
      }
    }
    return map;
  } catch (const YAML::Exception& e) {
    // Type conversions on odd nodes (e.g. a mapping where a scalar belongs).
    throw MapIoError("map YAML '" + yaml_path + "': " + e.msg);
  }
}

void SaveMap(const OccupancyGrid& map, const std::string& base, const SaveOptions& options) {
  const std::string pgm_path = base + ".pgm";
  const std::string yaml_path = base + ".yaml";
  CheckGrid(map, "map '" + base + "'");
  const int occupied_percent = options.occupied_percent;
  const int free_percent = options.free_percent;
  // map_saver's limits for --occ / --free.
  if (occupied_percent < 1 || occupied_percent > 100 || free_percent < 0 || free_percent > 100 ||
      free_percent >= occupied_percent) {
    throw MapIoError("cannot save map '" + base + "': need 0 <= free (" +
                     std::to_string(free_percent) + ") < occupied (" +
                     std::to_string(occupied_percent) + ") <= 100");
  }
  if (options.pgm_comment.find_first_of("\n\r") != std::string::npos) {
    throw MapIoError("cannot save map '" + base + "': the PGM comment must be one line");
  }

  const std::string comment =
      options.pgm_comment.empty()
          ? "CREATOR: minibot3d_map_io " + FormatDouble(map.resolution) + " m/pix"
          : options.pgm_comment;
  std::string pgm = "P5\n# " + comment + "\n" + std::to_string(map.width) + " " +
                    std::to_string(map.height) + "\n255\n";
  const std::size_t header = pgm.size();
  pgm.resize(header + map.data.size());
  for (int row = 0; row < map.height; ++row) {
    const std::int8_t* cells = map.data.data() + static_cast<std::size_t>(map.height - 1 - row) *
                                                     map.width;
    char* out = &pgm[header + static_cast<std::size_t>(row) * map.width];
    for (int col = 0; col < map.width; ++col) {
      const int v = cells[col];
      unsigned char px = kUnknownPixel;
      if (v >= 0 && v <= free_percent) {
        px = kFreePixel;
      } else if (v >= occupied_percent && v <= 100) {
        px = kOccupiedPixel;
      }
      out[col] = static_cast<char>(px);
    }
  }

  // The image name is written relative (its basename) so the pair can be moved together. The
  // emitter quotes it if it needs quoting (spaces, '#', ':').
  YAML::Emitter image_name;
  image_name << fs::path(pgm_path).filename().string();
  std::ostringstream yaml;
  yaml << "image: " << image_name.c_str() << "\n"
       << "resolution: " << YamlFloat(map.resolution) << "\n"
       << "origin: [" << YamlFloat(map.origin_x) << ", " << YamlFloat(map.origin_y) << ", "
       << YamlFloat(map.origin_theta) << "]\n"
       << "negate: 0\n"
       << "occupied_thresh: " << YamlFloat(kSavedOccupiedThresh) << "\n"
       << "free_thresh: " << YamlFloat(kSavedFreeThresh) << "\n";
  if (options.explain_grey_levels) {
    yaml << "# Cells were written as " << int{kOccupiedPixel} << " (occupied, >= "
         << occupied_percent << "), " << int{kFreePixel} << " (free, 0.." << free_percent
         << ") or " << int{kUnknownPixel}
         << " (unknown); the thresholds above read exactly those grey levels back (as "
            "map_saver).\n";
  }

  // Image first: a YAML on disk always points at a complete image.
  std::string error = WriteFileAtomically(pgm_path, pgm);
  if (!error.empty()) throw MapIoError("cannot write map image '" + pgm_path + "': " + error);
  error = WriteFileAtomically(yaml_path, yaml.str());
  if (!error.empty()) throw MapIoError("cannot write map YAML '" + yaml_path + "': " + error);
}

}  // namespace minibot3d_map_io
