// docs/parameters/ says what the option tables say: a parameter the code reads and the docs do
// not list (or a changed default or meaning) fails here.
#include <string>

#include <gtest/gtest.h>

#include "minibot3d_common/parameter_docs.h"
#include "parameter_pages.h"

TEST(ParameterDocsTest, DocsMatchTheOptionTables) {
  const std::string dir = MINIBOT3D_DOCS_PARAMETERS_DIR;
  std::string arg0 = "parameter_docs_test", check = "--check";
  char* argv[] = {&arg0[0], &check[0], const_cast<char*>(dir.c_str())};
  EXPECT_EQ(minibot3d_common::ParameterDocsMain(3, argv, minibot3d_slam::ParameterPages()), 0)
      << "see the message above";
}
