// Parameters through option tables without a master: values of every type, every bad value
// reported with its full name, keys no table reads.
#include "minibot3d_ros/params.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace minibot3d_ros {
namespace {

namespace options = minibot3d_common::options;

struct Demo {
  int count = 3;
  double speed = 0.5;
  bool on = false;
  std::string frame = "odom";
  std::vector<std::string> names;
};

const options::OptionTable<Demo>& Table() {
  static const options::OptionTable<Demo> t(
      "demo", {options::Field("count", &Demo::count, "How many."),
               options::Field("speed", &Demo::speed, "How fast (m/s)."),
               options::Field("on", &Demo::on, "Whether on."),
               options::Field("frame", &Demo::frame, "Which frame."),
               options::Field("names", &Demo::names, "Which names.")});
  return t;
}

XmlRpc::XmlRpcValue List(std::initializer_list<const char*> items) {
  XmlRpc::XmlRpcValue v;
  v.setSize(static_cast<int>(items.size()));
  int i = 0;
  for (const char* s : items) v[i++] = std::string(s);
  return v;
}

TEST(ParamsTest, EveryTypeIsParsed) {
  Demo d;
  const ParamReport r = ApplyTable(
      "/node", {{"count", XmlRpc::XmlRpcValue(7)}, {"speed", XmlRpc::XmlRpcValue(2)},
                {"on", XmlRpc::XmlRpcValue(true)}, {"frame", XmlRpc::XmlRpcValue("map")},
                {"names", List({"a", "b"})}},
      Table(), &d);
  EXPECT_TRUE(r.problems.empty());
  EXPECT_TRUE(r.Unknown().empty());
  EXPECT_EQ(d.count, 7);
  EXPECT_DOUBLE_EQ(d.speed, 2.0);  // an int where a double is expected is fine
  EXPECT_TRUE(d.on);
  EXPECT_EQ(d.frame, "map");
  EXPECT_EQ(d.names, (std::vector<std::string>{"a", "b"}));
}

TEST(ParamsTest, EveryBadValueIsNamedAndUnknownKeysAreReported) {
  Demo d;
  ParamReport r = ApplyTable(
      "/node", {{"count", XmlRpc::XmlRpcValue(1.5)}, {"on", XmlRpc::XmlRpcValue("maybe")},
                {"sped", XmlRpc::XmlRpcValue(1.0)}, {"speed", XmlRpc::XmlRpcValue(1.0)}},
      Table(), &d);
  ASSERT_EQ(r.problems.size(), 2u);
  EXPECT_NE(r.problems[0].find("/node/count"), std::string::npos) << r.problems[0];
  EXPECT_NE(r.problems[1].find("/node/on"), std::string::npos) << r.problems[1];
  EXPECT_EQ(r.Unknown(), std::vector<std::string>{"sped"});
  try {
    r.ThrowIfBad();
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("count"), std::string::npos);
    EXPECT_NE(what.find("on"), std::string::npos);
  }
  // A second table over the same namespace, or the node itself, may read the key.
  r.Known("sped");
  EXPECT_TRUE(r.Unknown().empty());
}

TEST(ParamsTest, TwoTablesShareANamespace) {
  Demo a, b;
  const NamedValues values{{"count", XmlRpc::XmlRpcValue(4)}, {"other", XmlRpc::XmlRpcValue(1)}};
  ParamReport r = ApplyTable("/node", values, Table(), &a);
  EXPECT_EQ(r.Unknown(), std::vector<std::string>{"other"});
  static const options::OptionTable<Demo> other(
      "other", {options::Field("other", &Demo::count, "Another count.")});
  r.Also(ApplyTable("/node", values, other, &b));
  EXPECT_TRUE(r.Unknown().empty());
  EXPECT_EQ(a.count, 4);
  EXPECT_EQ(b.count, 1);
}

TEST(ParamsTest, ListsOfStructsContributeTheirNames) {
  XmlRpc::XmlRpcValue v;
  v.setSize(2);
  v[0]["name"] = std::string("clear");
  v[0]["type"] = std::string("x");
  v[1]["name"] = std::string("rotate");
  std::string text;
  ASSERT_TRUE(XmlToText(v, &text));
  EXPECT_EQ(text, "[clear, rotate]");
  XmlRpc::XmlRpcValue s;
  s["a"] = 1;
  EXPECT_FALSE(XmlToText(s, &text));
}

}  // namespace
}  // namespace minibot3d_ros
