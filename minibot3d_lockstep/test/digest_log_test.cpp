#include "minibot3d_lockstep/digest_log.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace minibot3d_lockstep {
namespace {

std::string Slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

std::string TempDir() {
  char tmpl[] = "/tmp/digest_log_test_XXXXXX";
  const char* dir = mkdtemp(tmpl);
  if (!dir) throw std::runtime_error("mkdtemp failed");
  return dir;
}

const std::uint8_t* Bytes(const char* s) { return reinterpret_cast<const std::uint8_t*>(s); }

TEST(DigestLogTest, CrcCoversTheLengthPrefixAndChainsLikeZlibOverTheWire) {
  // zlib.crc32(b'\x03\x00\x00\x00abc') in Python: what the Python participant computes for the
  // same message.
  EXPECT_EQ(ChainCrc(0, Bytes("abc"), 3), 0x66e15d33u);
  // Chained: the CRC of both messages as they travel, length prefixes included.
  // zlib.crc32(b'\x03\x00\x00\x00abc\x01\x00\x00\x00d')
  EXPECT_EQ(ChainCrc(ChainCrc(0, Bytes("abc"), 3), Bytes("d"), 1), 0xf5fc1873u);
  // The split between messages counts ("ab" + "cd" is not "abc" + "d").
  EXPECT_NE(ChainCrc(ChainCrc(0, Bytes("ab"), 2), Bytes("cd"), 2),
            ChainCrc(ChainCrc(0, Bytes("abc"), 3), Bytes("d"), 1));
}

TEST(DigestLogTest, NamesAndStamps) {
  EXPECT_EQ(DigestFileName("/move_base"), "move_base.digest");
  EXPECT_EQ(DigestFileName("/robot1/move_base"), "robot1.move_base.digest");
  EXPECT_EQ(FormatStamp(0), "0.000000000");
  EXPECT_EQ(FormatStamp(2168350000000LL), "2168.350000000");
  EXPECT_EQ(FormatStamp(1000000001LL), "1.000000001");
}

TEST(DigestLogTest, WritesOnlyWhatChangedAndAppendsOneSectionPerProcess) {
  const std::string dir = TempDir();
  {
    DigestLog log(dir, "/explore", "run-1", 42, 1.5);
    log.Received("/map", "/slam", Bytes("abc"), 3);
    log.Tick(7, 5000000);
    log.Acknowledged({{"/move_base/goal", "/move_base", 1}, {"/rosout", "/rosout", 2}}, 55000000);
    // Nothing new: a tick line only; the sent counts did not change: no O lines.
    log.Tick(9, 55000000);
    log.Acknowledged({{"/move_base/goal", "/move_base", 1}, {"/rosout", "/rosout", 3}}, 0);
    log.Received("/map", "/slam", Bytes("d"), 1);
    log.Tick(12, 60000000);
    log.Acknowledged({{"/move_base/goal", "/move_base", 1}, {"/rosout", "/rosout", 3}}, 0);
  }
  {
    DigestLog sim(dir, "/sim", "run-1", 43, 1.6);
    sim.ReceivedBy(7, 5000000);  // nothing received: nothing written
    sim.Received("/cmd_vel", "/move_base", Bytes("v"), 1);
    sim.ReceivedBy(9, 55000000);
  }
  {
    DigestLog again(dir, "/explore", "run-2", 44, 9.0);
  }
  EXPECT_EQ(Slurp(dir + "/explore.digest"),
            "N /explore run=run-1 pid=42 wall=1.500000\n"
            "T 7 0.005000000\n"
            "I /map /slam 1 66e15d33\n"
            "O /move_base/goal /move_base 1\n"
            "O /rosout /rosout 2\n"
            "A 0.055000000\n"
            "T 9 0.055000000\n"
            "O /rosout /rosout 3\n"
            "A 0.000000000\n"
            "T 12 0.060000000\n"
            "I /map /slam 2 f5fc1873\n"
            "A 0.000000000\n"
            "N /explore run=run-2 pid=44 wall=9.000000\n");
  const std::string sim = Slurp(dir + "/sim.digest");
  // zlib.crc32(b'\x01\x00\x00\x00v')
  EXPECT_EQ(sim.substr(sim.find('\n') + 1), "T 9 0.055000000\nI /cmd_vel /move_base 1 42240aa4\n");
  std::filesystem::remove_all(dir);
}

TEST(DigestLogTest, WritesWholeMessagesOfTheTopicsAskedForAfterTheCounts) {
  EXPECT_EQ(SplitTopicList(" /a,b  c,,"), (std::vector<std::string>{"/a", "b", "c"}));
  const std::string dir = TempDir();
  {
    DigestLog log(dir, "/move_base", "run-1", 42, 1.5);
    log.WriteMessagesOf({"/move_base/goal"});
    EXPECT_TRUE(log.WritesMessagesOf("/move_base/goal"));
    EXPECT_FALSE(log.WritesMessagesOf("/map"));
    log.Received("/move_base/goal", "/explore", Bytes("\x01\xab"), 2, "m/Goal");
    log.Received("/map", "/slam", Bytes("abc"), 3, "nav_msgs/OccupancyGrid");
    log.Received("/move_base/goal", "/explore", Bytes(""), 0, "");
    log.Tick(7, 5000000);
    log.Acknowledged({}, 0);
  }
  const std::string text = Slurp(dir + "/move_base.digest");
  const std::string body = text.substr(text.find('\n') + 1);
  char crc[16];
  std::snprintf(crc, sizeof(crc), "%08x",
                static_cast<unsigned>(ChainCrc(ChainCrc(0, Bytes("\x01\xab"), 2), Bytes(""), 0)));
  EXPECT_EQ(body.substr(0, body.find("A ")),
            "T 7 0.005000000\n"
            "I /map /slam 1 66e15d33\n"
            "I /move_base/goal /explore 2 " + std::string(crc) + "\n"
            "M /move_base/goal /explore 1 m/Goal 01ab\n"
            "M /move_base/goal /explore 2 ? -\n");
  std::filesystem::remove_all(dir);
}

TEST(DigestLogTest, AnUnwritableDirectoryIsNamedInTheError) {
  try {
    DigestLog log("/proc/no_such_dir", "/node", "", 1, 0.0);
    FAIL() << "opened a digest in /proc";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/no_such_dir/node.digest"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find(kDigestEnv), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace minibot3d_lockstep
