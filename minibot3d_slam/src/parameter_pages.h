// The SLAM package's pages of docs/parameters/, built from its option tables.
#ifndef MINIBOT3D_SLAM_SRC_PARAMETER_PAGES_H_
#define MINIBOT3D_SLAM_SRC_PARAMETER_PAGES_H_

#include <vector>

#include "minibot3d_common/parameter_docs.h"

namespace minibot3d_slam {

std::vector<minibot3d_common::ParameterPage> ParameterPages();

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_SRC_PARAMETER_PAGES_H_
