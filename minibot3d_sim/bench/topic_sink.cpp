// topic_sink: subscribes to topics of any type and counts what arrives, so that a benchmark can
// make the simulator render its cameras (they render only for a listener) without a Python
// subscriber becoming the bottleneck.
//
//   rosrun minibot3d_sim topic_sink TOPIC...   (Ctrl-C prints messages and MB per topic)
#include <cstdio>
#include <string>
#include <vector>

#include <ros/ros.h>
#include <topic_tools/shape_shifter.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "topic_sink", ros::init_options::AnonymousName);
  if (argc < 2) {
    std::fprintf(stderr, "usage: topic_sink TOPIC...\n");
    return 2;
  }
  ros::NodeHandle nh;
  std::vector<std::string> topics(argv + 1, argv + argc);
  std::vector<long> messages(topics.size(), 0);
  std::vector<double> bytes(topics.size(), 0.0);
  std::vector<ros::Subscriber> subs;
  for (size_t i = 0; i < topics.size(); ++i) {
    subs.push_back(nh.subscribe<topic_tools::ShapeShifter>(
        topics[i], 2, [&, i](const topic_tools::ShapeShifter::ConstPtr& m) {
          ++messages[i];
          bytes[i] += m->size();
        }));
  }
  ros::spin();
  for (size_t i = 0; i < topics.size(); ++i) {
    std::printf("topic_sink: %s: %ld messages, %.1f MB\n", topics[i].c_str(), messages[i],
                bytes[i] / 1e6);
  }
  return 0;
}
