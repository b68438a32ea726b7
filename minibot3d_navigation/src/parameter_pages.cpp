#include "parameter_pages.h"

#include "minibot3d_navigation/amcl/amcl_options.h"

namespace minibot3d_navigation {

using minibot3d_common::ParameterPage;
using minibot3d_common::Section;

std::vector<ParameterPage> ParameterPages() {
  std::vector<ParameterPage> pages;
  pages.push_back(ParameterPage{
      "amcl.md", "amcl",
      "Private parameters of the `amcl` node (`~name`), with ROS amcl's names and defaults where "
      "ROS amcl has the parameter; `config/amcl.yaml` sets the ones the shipped stacks change. "
      "A key amcl does not know is reported once at start-up; a bad value stops the node with "
      "every offending parameter named.",
      {Section("Filter, models, confidence and global search",
               "The Monte Carlo localization filter (KLD-sampling, motion and laser models), "
               "what it must see before it claims a pose, and the map-wide search that seeds "
               "global localization.",
               amcl::AmclOptionTable()),
       Section("Node", "Frames, the map source and what the node publishes.",
               amcl::AmclNodeOptionTable())}});
  return pages;
}

}  // namespace minibot3d_navigation
