// map_io: maps on disk with map_server's (loading) and map_saver's (saving) semantics. The
// Python twin (test/test_map_io.py) checks the same cases and the same golden bytes.
#include "minibot3d_map_io/map_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <string>
#include <vector>

namespace minibot3d_map_io {
namespace {

namespace fs = std::filesystem;

class MapIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "map_io_test.XXXXXX").string();
    ASSERT_NE(::mkdtemp(&tmpl[0]), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  void WriteText(const std::string& name, const std::string& text) const {
    fs::create_directories(fs::path(Path(name)).parent_path());
    std::ofstream(Path(name), std::ios::binary) << text;
  }

  // A P5 PGM, rows top to bottom.
  void WritePgm(const std::string& name, int width, int height,
                const std::vector<unsigned char>& pixels) const {
    ASSERT_EQ(pixels.size(), static_cast<std::size_t>(width * height));
    WriteText(name, "P5\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n" +
                        std::string(pixels.begin(), pixels.end()));
  }

  // A YAML with every required key; `extra` is appended, `drop` names a key to leave out.
  std::string Yaml(const std::string& image, const std::string& extra = "",
                   const std::string& drop = "", const std::string& occ = "0.65",
                   const std::string& free = "0.196", const std::string& negate = "0") const {
    std::string out;
    auto add = [&](const std::string& key, const std::string& value) {
      if (key != drop) out += key + ": " + value + "\n";
    };
    add("image", image);
    add("resolution", "0.1");
    add("origin", "[-1.5, 2.25, 0.3]");
    add("negate", negate);
    add("occupied_thresh", occ);
    add("free_thresh", free);
    return out + extra;
  }

  std::set<std::string> Files() const {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.insert(e.path().filename().string());
    return names;
  }

  fs::path dir_;
};

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Expects a MapIoError whose message contains every one of `needles`.
void ExpectError(const std::function<void()>& f, const std::vector<std::string>& needles) {
  try {
    f();
    ADD_FAILURE() << "no MapIoError thrown; expected one mentioning " << needles.front();
  } catch (const MapIoError& e) {
    for (const auto& n : needles) {
      EXPECT_NE(std::string(e.what()).find(n), std::string::npos)
          << "message '" << e.what() << "' does not mention '" << n << "'";
    }
  }
}

OccupancyGrid SmallMap() {
  OccupancyGrid m;
  m.resolution = 0.05;
  m.origin_x = -1.5;
  m.origin_y = 2.25;
  m.origin_theta = 0.3;
  m.width = 4;
  m.height = 3;
  // Row 0 is the bottom (lowest y). Asymmetric so any flip or transpose shows.
  m.data = {100, -1, 0, 0,
            0, 100, -1, 0,
            -1, 0, 0, 100};
  return m;
}

SaveOptions Percent(int occupied, int free) {
  SaveOptions options;
  options.occupied_percent = occupied;
  options.free_percent = free;
  return options;
}

// SmallMap() saved with the default options, byte for byte (test_map_io.py holds the same).
const char kGoldenPgmHeader[] = "P5\n# CREATOR: minibot3d_map_io 0.05 m/pix\n4 3\n255\n";
const char kGoldenYaml[] =
    "image: m.pgm\n"
    "resolution: 0.05\n"
    "origin: [-1.5, 2.25, 0.3]\n"
    "negate: 0\n"
    "occupied_thresh: 0.65\n"
    "free_thresh: 0.196\n"
    "# Cells were written as 0 (occupied, >= 65), 254 (free, 0..25) or 205 (unknown); the "
    "thresholds above read exactly those grey levels back (as map_saver).\n";

TEST_F(MapIoTest, SavedFilesAreTheGoldenBytes) {
  SaveMap(SmallMap(), Path("m"));
  const std::vector<unsigned char> pixels = {205, 254, 254, 0,   254, 0,
                                             205, 254, 0,   205, 254, 254};
  EXPECT_EQ(ReadFile(Path("m.pgm")),
            kGoldenPgmHeader + std::string(pixels.begin(), pixels.end()));
  EXPECT_EQ(ReadFile(Path("m.yaml")), kGoldenYaml);
}

TEST_F(MapIoTest, SaveOptionsSetTheCommentsAndFloatsKeepAPoint) {
  OccupancyGrid m = SmallMap();
  m.origin_x = -4.0;
  m.origin_theta = 0.0;
  SaveOptions options;
  options.pgm_comment = "minibot3d_sim ground-truth map";
  options.explain_grey_levels = false;
  SaveMap(m, Path("g"), options);
  EXPECT_EQ(ReadFile(Path("g.pgm")).substr(0, 40), "P5\n# minibot3d_sim ground-truth map\n4 3\n");
  EXPECT_EQ(ReadFile(Path("g.yaml")),
            "image: g.pgm\nresolution: 0.05\norigin: [-4.0, 2.25, 0.0]\nnegate: 0\n"
            "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  EXPECT_EQ(LoadMap(Path("g.yaml")).origin_x, -4.0);
  options.pgm_comment = "two\nlines";
  ExpectError([&] { SaveMap(m, Path("h"), options); }, {Path("h"), "one line"});
}

TEST_F(MapIoTest, RoundTripKeepsCellsAndGeometry) {
  const OccupancyGrid in = SmallMap();
  SaveMap(in, Path("m"));
  const OccupancyGrid out = LoadMap(Path("m.yaml"));
  EXPECT_EQ(out.width, in.width);
  EXPECT_EQ(out.height, in.height);
  EXPECT_EQ(out.data, in.data);
  EXPECT_DOUBLE_EQ(out.resolution, in.resolution);
  EXPECT_DOUBLE_EQ(out.origin_x, in.origin_x);
  EXPECT_DOUBLE_EQ(out.origin_y, in.origin_y);
  EXPECT_DOUBLE_EQ(out.origin_theta, in.origin_theta);
  EXPECT_EQ(Files(), (std::set<std::string>{"m.pgm", "m.yaml"})) << "temporary files left";
  // Any double reads back bit for bit.
  OccupancyGrid odd = in;
  odd.origin_x = -73 * 0.05;  // -3.6500000000000004
  odd.origin_y = 1.0 / 3.0;
  odd.origin_theta = -1e-17;
  odd.resolution = 0.1 + 0.2;
  SaveMap(odd, Path("o"));
  const OccupancyGrid back = LoadMap(Path("o.yaml"));
  EXPECT_EQ(back.origin_x, odd.origin_x);
  EXPECT_EQ(back.origin_y, odd.origin_y);
  EXPECT_EQ(back.origin_theta, odd.origin_theta);
  EXPECT_EQ(back.resolution, odd.resolution);
}

TEST_F(MapIoTest, SavedImageIsMapSaversPgmWithTopRowFirst) {
  SaveMap(SmallMap(), Path("m"));
  const std::string pgm = ReadFile(Path("m.pgm"));
  ASSERT_EQ(pgm.compare(0, 3, "P5\n"), 0);
  ASSERT_GE(pgm.size(), 12u);
  const std::string pixels = pgm.substr(pgm.size() - 12);
  // Image row 0 is the map's top row (grid row 2): -1 0 0 100 -> 205 254 254 0.
  const std::vector<unsigned char> expected = {205, 254, 254, 0,   254, 0,
                                               205, 254, 0,   205, 254, 254};
  EXPECT_EQ(std::vector<unsigned char>(pixels.begin(), pixels.end()), expected);
  const cv::Mat img = cv::imread(Path("m.pgm"), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(img.empty()) << "OpenCV cannot read the saved PGM";
  EXPECT_EQ(img.cols, 4);
  EXPECT_EQ(img.rows, 3);
}

TEST_F(MapIoTest, SavedYamlHasMapServerKeys) {
  SaveMap(SmallMap(), Path("m"));
  const std::string yaml = ReadFile(Path("m.yaml"));
  EXPECT_NE(yaml.find("image: m.pgm\n"), std::string::npos) << yaml;  // basename, not a path
  EXPECT_NE(yaml.find("resolution: 0.05\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("origin: [-1.5, 2.25, 0.3]\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("negate: 0\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("occupied_thresh: 0.65\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("free_thresh: 0.196\n"), std::string::npos) << yaml;
}

TEST_F(MapIoTest, SaveClassifiesByPercentThresholds) {
  OccupancyGrid m;
  m.width = 8;
  m.height = 1;
  m.data = {0, 25, 26, 64, 65, 100, -1, -100};
  SaveMap(m, Path("d"));  // --occ 65 --free 25
  EXPECT_EQ(LoadMap(Path("d.yaml")).data,
            (std::vector<std::int8_t>{0, 0, -1, -1, 100, 100, -1, -1}));
  m.data = {10, 11, 49, 50, 0, 100, -1, 30};
  SaveMap(m, Path("c"), Percent(50, 10));
  EXPECT_EQ(LoadMap(Path("c.yaml")).data,
            (std::vector<std::int8_t>{0, -1, -1, 100, 0, 100, -1, -1}));
}

TEST_F(MapIoTest, SaveOverwritesAndLeavesNoTemporaries) {
  OccupancyGrid m = SmallMap();
  SaveMap(m, Path("m"));
  m.data.assign(m.data.size(), 100);
  SaveMap(m, Path("m"));
  EXPECT_EQ(LoadMap(Path("m.yaml")).data, m.data);
  EXPECT_EQ(Files(), (std::set<std::string>{"m.pgm", "m.yaml"}));
}

TEST_F(MapIoTest, SaveFailureNamesTheFileAndCleansUp) {
  // A directory where the image should go: the rename fails.
  fs::create_directory(Path("blocked.pgm"));
  ExpectError([&] { SaveMap(SmallMap(), Path("blocked")); }, {Path("blocked.pgm")});
  EXPECT_EQ(Files(), (std::set<std::string>{"blocked.pgm"})) << "temporary files left";
  ExpectError([&] { SaveMap(SmallMap(), Path("no/such/dir/m")); }, {Path("no/such/dir/m.pgm")});
}

TEST_F(MapIoTest, SaveRefusesInconsistentMaps) {
  OccupancyGrid m = SmallMap();
  m.data.pop_back();
  ExpectError([&] { SaveMap(m, Path("m")); }, {Path("m"), "11 values"});
  m = SmallMap();
  m.resolution = 0.0;
  ExpectError([&] { SaveMap(m, Path("m")); }, {"resolution"});
  ExpectError([&] { SaveMap(SmallMap(), Path("m"), Percent(25, 65)); }, {"free (65)", "occupied (25)"});
  EXPECT_TRUE(Files().empty());
}

// Pixels of a 3 x 2 test image, rows top to bottom, and what trinary mode makes of them with
// occupied_thresh 0.65 / free_thresh 0.196 (p = (255 - v) / 255).
const std::vector<unsigned char> kPixels = {0, 254, 205,     // p 1.0 occ, 0.004 free, 0.196 unk
                                            210, 80, 100};   // p 0.176 free, 0.686 occ, 0.608 unk
// The same, as grid cells (row 0 = the image's bottom row).
const std::vector<std::int8_t> kTrinaryCells = {0, 100, -1, 100, 0, -1};

TEST_F(MapIoTest, TrinaryThresholdsAndRowOrder) {
  WritePgm("t.pgm", 3, 2, kPixels);
  WriteText("t.yaml", Yaml("t.pgm"));
  const OccupancyGrid m = LoadMap(Path("t.yaml"));
  ASSERT_EQ(m.width, 3);
  ASSERT_EQ(m.height, 2);
  EXPECT_EQ(m.data, kTrinaryCells);
  EXPECT_DOUBLE_EQ(m.resolution, 0.1);
  EXPECT_DOUBLE_EQ(m.origin_x, -1.5);
  EXPECT_DOUBLE_EQ(m.origin_y, 2.25);
  EXPECT_DOUBLE_EQ(m.origin_theta, 0.3);
}

TEST_F(MapIoTest, ExplicitTrinaryModeAndBoolNegate) {
  WritePgm("t.pgm", 3, 2, kPixels);
  WriteText("t.yaml", Yaml("t.pgm", "mode: trinary\n", "", "0.65", "0.196", "false"));
  EXPECT_EQ(LoadMap(Path("t.yaml")).data, kTrinaryCells);
}

TEST_F(MapIoTest, NegateSwapsBlackAndWhite) {
  WritePgm("t.pgm", 3, 2, kPixels);
  // negate: p = v / 255: 0 -> 0 free, 254 -> 0.996 occ, 205 -> 0.804 occ,
  // 210 -> 0.824 occ, 80 -> 0.314 unknown, 100 -> 0.392 unknown.
  WriteText("t.yaml", Yaml("t.pgm", "", "", "0.65", "0.196", "1"));
  EXPECT_EQ(LoadMap(Path("t.yaml")).data, (std::vector<std::int8_t>{100, -1, -1, 0, 100, 100}));
}

TEST_F(MapIoTest, ScaleModeIsLinearBetweenThresholds) {
  // p: 1.0, 0.0, 127/255 = 0.498, 153/255 = 0.6, 51/255 = 0.2 (not below free), 0.8 (not above occ)
  WritePgm("s.pgm", 6, 1, {0, 255, 128, 102, 204, 51});
  WriteText("s.yaml", Yaml("s.pgm", "mode: scale\n", "", "0.8", "0.2"));
  // 99 * (p - free) / (occ - free), truncated: 49.18 -> 49; p = 0.6 -> 66 (65 after rounding);
  // p = 0.2 -> 0; p = 0.8 -> 99 (98 after rounding, or 100 if p rounds above occupied_thresh).
  const OccupancyGrid m = LoadMap(Path("s.yaml"));
  auto scaled = [](int v) {
    const double p = (255.0 - v) / 255.0;
    return static_cast<int>(99.0 * (p - 0.2) / (0.8 - 0.2));
  };
  EXPECT_EQ(m.data[0], 100);
  EXPECT_EQ(m.data[1], 0);
  EXPECT_EQ(m.data[2], 49);
  EXPECT_EQ(m.data[3], scaled(102));
  EXPECT_EQ(m.data[4], 0);  // p = 0.2 exactly: not below free_thresh, scaled to 0
  EXPECT_GE(m.data[5], 98);
}

TEST_F(MapIoTest, RawModeKeepsPixelValues) {
  WritePgm("r.pgm", 4, 1, {0, 50, 100, 200});
  WriteText("r.yaml", Yaml("r.pgm", "mode: raw\n"));
  // 200 does not fit an int8 cell: stored as its byte, -56, as map_server does.
  EXPECT_EQ(LoadMap(Path("r.yaml")).data, (std::vector<std::int8_t>{0, 50, 100, -56}));
  WriteText("rn.yaml", Yaml("r.pgm", "mode: raw\n", "", "0.65", "0.196", "1"));
  EXPECT_EQ(LoadMap(Path("rn.yaml")).data, (std::vector<std::int8_t>{-1, -51, -101, 55}));
}

TEST_F(MapIoTest, SixteenBitImagesReadAsEightBit) {
  cv::Mat wide(2, 3, CV_16UC1);
  for (int k = 0; k < 6; ++k) wide.at<std::uint16_t>(k / 3, k % 3) = kPixels[k] * 257;
  ASSERT_TRUE(cv::imwrite(Path("w.pgm"), wide));
  WriteText("w.yaml", Yaml("w.pgm"));
  EXPECT_EQ(LoadMap(Path("w.yaml")).data, kTrinaryCells);
}

TEST_F(MapIoTest, ColourImagesAverageChannels) {
  cv::Mat bgr(1, 3, CV_8UC3);
  bgr.at<cv::Vec3b>(0, 0) = {0, 0, 255};      // mean 85: p 0.667 occupied
  bgr.at<cv::Vec3b>(0, 1) = {254, 254, 254};  // free
  bgr.at<cv::Vec3b>(0, 2) = {255, 150, 210};  // mean 205: unknown
  ASSERT_TRUE(cv::imwrite(Path("c.png"), bgr));
  WriteText("c.yaml", Yaml("c.png"));
  EXPECT_EQ(LoadMap(Path("c.yaml")).data, (std::vector<std::int8_t>{100, 0, -1}));
}

TEST_F(MapIoTest, AlphaChannelAsMapServer) {
  cv::Mat bgra(1, 3, CV_8UC4);
  bgra.at<cv::Vec4b>(0, 0) = {128, 128, 128, 255};  // opaque mid grey
  bgra.at<cv::Vec4b>(0, 1) = {128, 128, 128, 0};    // transparent mid grey
  bgra.at<cv::Vec4b>(0, 2) = {254, 254, 254, 0};    // transparent white
  ASSERT_TRUE(cv::imwrite(Path("a.png"), bgra));
  // Scale: alpha is not averaged; a transparent in-between pixel is unknown, an opaque one scaled.
  WriteText("a.yaml", Yaml("a.png", "mode: scale\n", "", "0.8", "0.2"));
  const OccupancyGrid s = LoadMap(Path("a.yaml"));
  EXPECT_EQ(s.data[0], 49);  // p = 127 / 255: 99 * 0.298 / 0.6
  EXPECT_EQ(s.data[1], -1);
  EXPECT_EQ(s.data[2], 0);  // clearly free whatever its alpha
  // Trinary: map_server averages alpha in with the colours: (254 * 3 + 0) / 4 = 190.5 -> p 0.25.
  WriteText("b.yaml", Yaml("a.png"));
  EXPECT_EQ(LoadMap(Path("b.yaml")).data[2], -1);
}

TEST_F(MapIoTest, RelativeImagePathIsRelativeToTheYaml) {
  WritePgm("maps/img/t.pgm", 3, 2, kPixels);
  WriteText("maps/t.yaml", Yaml("img/t.pgm"));
  const std::string cwd = fs::current_path().string();
  fs::current_path(fs::temp_directory_path());  // not the YAML's folder
  OccupancyGrid m;
  EXPECT_NO_THROW(m = LoadMap(Path("maps/t.yaml")));
  fs::current_path(cwd);
  EXPECT_EQ(m.data, kTrinaryCells);
  // An absolute image path is taken as it is.
  WriteText("abs.yaml", Yaml(Path("maps/img/t.pgm")));
  EXPECT_EQ(LoadMap(Path("abs.yaml")).data, m.data);
}

TEST_F(MapIoTest, MissingKeysAreNamed) {
  WritePgm("t.pgm", 3, 2, kPixels);
  for (const std::string key :
       {"image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh"}) {
    WriteText("k.yaml", Yaml("t.pgm", "", key));
    ExpectError([&] { LoadMap(Path("k.yaml")); }, {Path("k.yaml"), "missing key '" + key + "'"});
  }
}

TEST_F(MapIoTest, BadValuesAreNamed) {
  WritePgm("t.pgm", 3, 2, kPixels);
  const std::string yaml = Path("b.yaml");
  auto expect = [&](const std::string& text, const std::vector<std::string>& needles) {
    WriteText("b.yaml", text);
    std::vector<std::string> all = needles;
    all.push_back(yaml);
    ExpectError([&] { LoadMap(yaml); }, all);
  };
  std::string y = Yaml("t.pgm");
  expect(std::string(y).replace(y.find("0.1\n"), 3, "-0.05"), {"'resolution'", "positive"});
  expect(std::string(y).replace(y.find("0.1\n"), 3, "abc"), {"'resolution'", "'abc'"});
  expect(Yaml("t.pgm", "", "", "0.1", "0.3"), {"'occupied_thresh'", "'free_thresh'"});
  expect(Yaml("t.pgm", "", "", "1.5", "0.3"), {"'occupied_thresh'", "[0, 1]"});
  expect(Yaml("t.pgm", "", "", "0.65", "0.196", "2"), {"'negate'"});
  expect(Yaml("t.pgm", "mode: fancy\n"), {"'mode'", "fancy"});
  expect(std::string(y).replace(y.find("[-1.5, 2.25, 0.3]"), 17, "[1, 2]"), {"'origin'"});
  expect(std::string(y).replace(y.find("[-1.5, 2.25, 0.3]"), 17, "[1, 2, x]"), {"origin[2]"});
  expect("image: [t.pgm\n", {"line", "does not parse"});
  expect("just a string\n", {"mapping"});
}

TEST_F(MapIoTest, MissingOrUnreadableImageIsNamed) {
  WriteText("m.yaml", Yaml("nothere.pgm"));
  ExpectError([&] { LoadMap(Path("m.yaml")); },
              {Path("m.yaml"), Path("nothere.pgm"), "does not exist"});
  WriteText("junk.pgm", "this is not an image");
  WriteText("j.yaml", Yaml("junk.pgm"));
  ExpectError([&] { LoadMap(Path("j.yaml")); },
              {Path("j.yaml"), Path("junk.pgm"), "cannot be read"});
  ExpectError([&] { LoadMap(Path("absent.yaml")); }, {Path("absent.yaml"), "cannot be opened"});
}

TEST_F(MapIoTest, LoadsTheShippedWorldMaps) {
  // The repository's ground-truth maps, if this test runs from the source tree.
#ifdef MINIBOT3D_MAP_IO_SOURCE_DIR
  const fs::path maps = fs::path(MINIBOT3D_MAP_IO_SOURCE_DIR) / ".." / "maps";
#else
  const fs::path maps = fs::path(__FILE__).parent_path() / ".." / ".." / "maps";
#endif
  if (!fs::exists(maps / "arena.yaml")) GTEST_SKIP() << "no " << maps;
  const OccupancyGrid m = LoadMap((maps / "arena.yaml").string());
  EXPECT_GT(m.width, 0);
  EXPECT_EQ(m.data.size(), static_cast<std::size_t>(m.width) * m.height);
  bool has_occupied = false, has_free = false;
  for (auto v : m.data) {
    has_occupied |= v == 100;
    has_free |= v == 0;
  }
  EXPECT_TRUE(has_occupied && has_free);
}

}  // namespace
}  // namespace minibot3d_map_io
