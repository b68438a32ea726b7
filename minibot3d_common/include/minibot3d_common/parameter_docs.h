// The parameter reference of the docs (docs/parameters/*.md), generated from the option tables
// that parse and validate the parameters, so that the two cannot drift apart.
//
// Each package lists its pages (one per component: a title, a short introduction and one section
// per table), a small program writes them (tools/update_parameter_docs.sh), and a test of the
// package fails when a committed page differs from what the tables say.
#ifndef MINIBOT3D_COMMON_PARAMETER_DOCS_H_
#define MINIBOT3D_COMMON_PARAMETER_DOCS_H_

#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "minibot3d_common/options.h"

namespace minibot3d_common {

struct ParameterSection {
  std::string heading;   // e.g. "Filter", "Node: frames and topics"
  std::string intro;     // where the keys live (namespace, URDF tag), one or two sentences
  std::string markdown;  // OptionTable::Markdown()
};

struct ParameterPage {
  std::string file;   // e.g. "amcl.md" in docs/parameters/
  std::string title;  // e.g. "amcl"
  std::string intro;  // one paragraph
  std::vector<ParameterSection> sections;
};

template <typename T>
ParameterSection Section(const std::string& heading, const std::string& intro,
                         const options::OptionTable<T>& table, const T& defaults = T()) {
  return ParameterSection{heading, intro, table.Markdown(defaults)};
}

inline std::string Render(const ParameterPage& page) {
  std::ostringstream os;
  os << "<!-- Generated from the option tables by tools/update_parameter_docs.sh; do not edit. "
        "-->\n";
  os << "# " << page.title << " parameters\n\n" << page.intro << "\n";
  for (const auto& s : page.sections) {
    os << "\n## " << s.heading << "\n\n";
    if (!s.intro.empty()) os << s.intro << "\n\n";
    os << s.markdown;
  }
  return os.str();
}

// `print_parameter_docs DIR` writes every page into DIR; `--check DIR` compares instead and
// names the first page and line that differ. Returns the process's exit code.
inline int ParameterDocsMain(int argc, char** argv, const std::vector<ParameterPage>& pages) {
  const bool check = argc == 3 && std::string(argv[1]) == "--check";
  if (!(argc == 2 || check)) {
    std::fprintf(stderr, "usage: %s [--check] DOCS_PARAMETERS_DIR\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[argc - 1];
  int status = 0;
  for (const auto& page : pages) {
    const std::string path = dir + "/" + page.file;
    const std::string text = Render(page);
    if (check) {
      std::ifstream in(path);
      std::stringstream have;
      have << in.rdbuf();
      if (!in || have.str() != text) {
        std::istringstream a(have.str()), b(text);
        std::string la, lb;
        int line = 0;
        while (true) {
          ++line;
          const bool ga = static_cast<bool>(std::getline(a, la));
          const bool gb = static_cast<bool>(std::getline(b, lb));
          if (!ga && !gb) break;
          if (!ga || !gb || la != lb) break;
        }
        std::fprintf(stderr,
                     "%s is out of date with the option tables at line %d:\n  file:   %s\n"
                     "  tables: %s\nRun tools/update_parameter_docs.sh.\n",
                     path.c_str(), line, la.c_str(), lb.c_str());
        status = 1;
      }
    } else {
      const std::string tmp = path + ".tmp";
      std::ofstream out(tmp);
      out << text;
      out.close();
      if (!out || std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::fprintf(stderr, "cannot write %s\n", path.c_str());
        return 1;
      }
    }
  }
  return status;
}

}  // namespace minibot3d_common

#endif  // MINIBOT3D_COMMON_PARAMETER_DOCS_H_
