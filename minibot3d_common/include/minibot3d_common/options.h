// A table of named option fields, shared by every options struct of the
// navigation core (AMCL, costmap, planners, DWA, move_base, explore).  Each options file
// lists its fields once — name and member pointer — and gets Set/IsName/Names
// from here, so a new parameter is one line and the three can't drift apart.
//
//   const OptionTable<DwaOptions>& Table() {
//     static const OptionTable<DwaOptions> t("TrajectoryPlannerROS", {
//         Field("max_vel_x", &DwaOptions::max_vel_x), ...});
//     return t;
//   }
//   void SetDwaOption(n, text, o) { Table().Set(n, text, o); }
//
// Text parsing follows rosparam's YAML: numbers, integers, true/false.
// Lists (std::vector<std::string>) are comma-separated.
#ifndef MINIBOT3D_COMMON_OPTIONS_H_
#define MINIBOT3D_COMMON_OPTIONS_H_

#include <cerrno>
#include <cstdlib>
#include <initializer_list>
#include <limits>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace minibot3d_common {
namespace options {

inline std::string Trim(const std::string& s) {
  const char* ws = " \t\r\n";
  const size_t b = s.find_first_not_of(ws);
  if (b == std::string::npos) return "";
  const size_t e = s.find_last_not_of(ws);
  return s.substr(b, e - b + 1);
}

[[noreturn]] inline void ThrowBadText(const std::string& owner, const std::string& name,
                                      const std::string& text, const char* type) {
  throw std::invalid_argument(owner + " parameter " + name + ": cannot parse '" + text +
                              "' as " + type);
}

inline double ParseDouble(const std::string& owner, const std::string& name,
                          const std::string& text) {
  const std::string t = Trim(text);
  if (t.empty()) ThrowBadText(owner, name, text, "a number");
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || errno == ERANGE) ThrowBadText(owner, name, text, "a number");
  return v;
}

inline int ParseInt(const std::string& owner, const std::string& name, const std::string& text) {
  const std::string t = Trim(text);
  if (t.empty()) ThrowBadText(owner, name, text, "an integer");
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(t.c_str(), &end, 10);  // NOLINT(runtime/int)
  if (end != t.c_str() + t.size() || errno == ERANGE || v > std::numeric_limits<int>::max() ||
      v < std::numeric_limits<int>::min()) {
    ThrowBadText(owner, name, text, "an integer");
  }
  return static_cast<int>(v);
}

inline bool ParseBool(const std::string& owner, const std::string& name, const std::string& text) {
  const std::string t = Trim(text);
  if (t == "true" || t == "True" || t == "TRUE" || t == "1") return true;
  if (t == "false" || t == "False" || t == "FALSE" || t == "0") return false;
  ThrowBadText(owner, name, text, "a boolean");
}

inline std::vector<std::string> ParseList(const std::string& text) {
  std::vector<std::string> out;
  std::string t = Trim(text);
  if (!t.empty() && t.front() == '[' && t.back() == ']') t = t.substr(1, t.size() - 2);
  std::stringstream ss(t);
  std::string item;
  while (std::getline(ss, item, ',')) {
    item = Trim(item);
    if (item.size() >= 2 && (item.front() == '\'' || item.front() == '"')) {
      item = item.substr(1, item.size() - 2);
    }
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

// Formats a number for error messages ("max_vel_x=-1").
inline std::string Num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

template <typename T>
struct OptionField {
  const char* name = nullptr;
  int T::*int_field = nullptr;
  double T::*double_field = nullptr;
  bool T::*bool_field = nullptr;
  std::string T::*string_field = nullptr;
  std::vector<std::string> T::*list_field = nullptr;
};

template <typename T>
OptionField<T> Field(const char* n, int T::*f) {
  OptionField<T> o; o.name = n; o.int_field = f; return o;
}
template <typename T>
OptionField<T> Field(const char* n, double T::*f) {
  OptionField<T> o; o.name = n; o.double_field = f; return o;
}
template <typename T>
OptionField<T> Field(const char* n, bool T::*f) {
  OptionField<T> o; o.name = n; o.bool_field = f; return o;
}
template <typename T>
OptionField<T> Field(const char* n, std::string T::*f) {
  OptionField<T> o; o.name = n; o.string_field = f; return o;
}
template <typename T>
OptionField<T> Field(const char* n, std::vector<std::string> T::*f) {
  OptionField<T> o; o.name = n; o.list_field = f; return o;
}

template <typename T>
class OptionTable {
 public:
  // `owner` names the component in messages ("TrajectoryPlannerROS").
  OptionTable(std::string owner, std::initializer_list<OptionField<T>> fields)
      : owner_(std::move(owner)), fields_(fields) {}

  const std::string& owner() const { return owner_; }

  bool Has(const std::string& name) const { return Find(name) != nullptr; }

  std::vector<std::string> Names() const {
    std::vector<std::string> out;
    for (const auto& f : fields_) out.push_back(f.name);
    return out;
  }

  // Throws std::invalid_argument for an unknown name or unparsable text.
  void Set(const std::string& name, const std::string& text, T* options) const {
    const OptionField<T>* f = Find(name);
    if (f == nullptr) throw std::invalid_argument("unknown " + owner_ + " parameter '" + name + "'");
    if (f->int_field) {
      options->*(f->int_field) = ParseInt(owner_, name, text);
    } else if (f->double_field) {
      options->*(f->double_field) = ParseDouble(owner_, name, text);
    } else if (f->bool_field) {
      options->*(f->bool_field) = ParseBool(owner_, name, text);
    } else if (f->string_field) {
      options->*(f->string_field) = Trim(text);
    } else {
      options->*(f->list_field) = ParseList(text);
    }
  }

 private:
  const OptionField<T>* Find(const std::string& name) const {
    for (const auto& f : fields_) {
      if (name == f.name) return &f;
    }
    return nullptr;
  }

  std::string owner_;
  std::vector<OptionField<T>> fields_;
};

// Collects "name=value must be ..." problems and throws them all at once.
class Problems {
 public:
  explicit Problems(std::string owner) : owner_(std::move(owner)) {}
  void Add(const std::string& problem) { list_.push_back(problem); }
  void Require(bool ok, const std::string& problem) { if (!ok) Add(problem); }
  // The usual checks of a number, each naming it and its value; NaN and ±inf fail all of them.
  void Positive(const std::string& name, double v) {
    Require(std::isfinite(v) && v > 0.0, name + "=" + Num(v) + " must be > 0");
  }
  void NonNegative(const std::string& name, double v) {
    Require(std::isfinite(v) && v >= 0.0, name + "=" + Num(v) + " must be >= 0");
  }
  void InUnitInterval(const std::string& name, double v) {
    Require(std::isfinite(v) && v >= 0.0 && v <= 1.0, name + "=" + Num(v) + " must be in [0, 1]");
  }
  void Finite(const std::string& name, double v) {
    Require(std::isfinite(v), name + "=" + Num(v) + " must be finite");
  }
  void ThrowIfAny() const {
    if (list_.empty()) return;
    std::string msg = "invalid " + owner_ + " parameters: ";
    for (size_t i = 0; i < list_.size(); ++i) msg += (i ? "; " : "") + list_[i];
    throw std::invalid_argument(msg);
  }

 private:
  std::string owner_;
  std::vector<std::string> list_;
};

}  // namespace options
}  // namespace minibot3d_common

#endif  // MINIBOT3D_COMMON_OPTIONS_H_
