// print_parameter_docs [--check] DIR: writes (or checks) the SLAM package's pages of
// docs/parameters/ from its option tables (tools/update_parameter_docs.sh runs it).
#include "minibot3d_common/parameter_docs.h"
#include "parameter_pages.h"

int main(int argc, char** argv) {
  return minibot3d_common::ParameterDocsMain(argc, argv, minibot3d_slam::ParameterPages());
}
