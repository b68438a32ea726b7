// Option tables: how every minibot3d component reads, validates and documents its parameters.
//
// A component keeps its parameters in one options struct with defaults, and lists each field
// once in a table (name as users write it in their YAML, URDF tag or launch file; the member;
// one line of documentation with the unit). From that one list come parsing by name
// (Set/Has/Names, so a node loads a YAML namespace or a plugin's tags without a hand-written read
// per parameter and can report keys nobody reads), and the parameter reference in docs/parameters/
// (Markdown: name, type, default, meaning), which a test keeps equal to the table.
//
//   const OptionTable<DwaOptions>& DwaOptionTable() {
//     static const OptionTable<DwaOptions> t("TrajectoryPlannerROS", {
//         Field("max_vel_x", &DwaOptions::max_vel_x, "Largest forward speed (m/s)."), ...});
//     return t;
//   }
//
// Text parsing follows rosparam's YAML: numbers, integers, true/false; lists are comma-separated
// and may be bracketed. Validation of ranges and combinations stays with each component
// (Problems collects every offending value and throws them together).
#ifndef MINIBOT3D_COMMON_OPTIONS_H_
#define MINIBOT3D_COMMON_OPTIONS_H_

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
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

inline long long ParseInteger(const std::string& owner, const std::string& name,  // NOLINT
                              const std::string& text, long long lo, long long hi) {  // NOLINT
  const std::string t = Trim(text);
  if (t.empty()) ThrowBadText(owner, name, text, "an integer");
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(t.c_str(), &end, 10);  // NOLINT(runtime/int)
  if (end != t.c_str() + t.size() || errno == ERANGE || v < lo || v > hi) {
    ThrowBadText(owner, name, text, lo == 0 ? "a non-negative integer" : "an integer");
  }
  return v;
}

inline int ParseInt(const std::string& owner, const std::string& name, const std::string& text) {
  return static_cast<int>(ParseInteger(owner, name, text, std::numeric_limits<int>::min(),
                                       std::numeric_limits<int>::max()));
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

// Formats a number for messages and the docs: the shortest text that reads back as the same
// double ("0.1", "1e-06", "inf"), with every digit of the integer part ("10", not "1e+01").
inline std::string Num(double v) {
  const double magnitude = std::fabs(v);
  const int integer_digits =
      std::isfinite(v) && magnitude >= 1.0 ? static_cast<int>(std::log10(magnitude)) + 1 : 1;
  for (int precision = std::min(integer_digits, 17); precision <= 17; ++precision) {
    std::ostringstream os;
    os << std::setprecision(precision) << v;
    if (std::strtod(os.str().c_str(), nullptr) == v || !std::isfinite(v)) return os.str();
  }
  std::ostringstream os;
  os << std::setprecision(17) << v;
  return os.str();
}

template <typename T>
struct OptionField {
  const char* name = nullptr;
  const char* doc = nullptr;  // one line: what it sets, its unit, what special values mean
  int T::*int_field = nullptr;
  unsigned T::*unsigned_field = nullptr;
  double T::*double_field = nullptr;
  bool T::*bool_field = nullptr;
  std::string T::*string_field = nullptr;
  std::vector<std::string> T::*list_field = nullptr;
};

template <typename T>
OptionField<T> Field(const char* n, int T::*f, const char* doc) {
  OptionField<T> o; o.name = n; o.doc = doc; o.int_field = f; return o;
}
template <typename T>
OptionField<T> Field(const char* n, unsigned T::*f, const char* doc) {
  OptionField<T> o; o.name = n; o.doc = doc; o.unsigned_field = f; return o;
}
template <typename T>
OptionField<T> Field(const char* n, double T::*f, const char* doc) {
  OptionField<T> o; o.name = n; o.doc = doc; o.double_field = f; return o;
}
template <typename T>
OptionField<T> Field(const char* n, bool T::*f, const char* doc) {
  OptionField<T> o; o.name = n; o.doc = doc; o.bool_field = f; return o;
}
template <typename T>
OptionField<T> Field(const char* n, std::string T::*f, const char* doc) {
  OptionField<T> o; o.name = n; o.doc = doc; o.string_field = f; return o;
}
template <typename T>
OptionField<T> Field(const char* n, std::vector<std::string> T::*f, const char* doc) {
  OptionField<T> o; o.name = n; o.doc = doc; o.list_field = f; return o;
}

template <typename T>
class OptionTable {
 public:
  // `owner` names the component in messages and the docs ("TrajectoryPlannerROS", "amcl").
  OptionTable(std::string owner, std::initializer_list<OptionField<T>> fields)
      : owner_(std::move(owner)), fields_(fields) {
    for (size_t i = 0; i < fields_.size(); ++i) {
      if (fields_[i].name == nullptr || fields_[i].doc == nullptr || *fields_[i].doc == '\0') {
        throw std::logic_error(owner_ + " option table: field " + std::to_string(i) +
                               " has no name or no documentation");
      }
      for (size_t j = 0; j < i; ++j) {
        if (std::string(fields_[i].name) == fields_[j].name) {
          throw std::logic_error(owner_ + " option table lists '" + fields_[i].name + "' twice");
        }
      }
    }
  }

  const std::string& owner() const { return owner_; }
  const std::vector<OptionField<T>>& fields() const { return fields_; }

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
    } else if (f->unsigned_field) {
      options->*(f->unsigned_field) = static_cast<unsigned>(
          ParseInteger(owner_, name, text, 0, std::numeric_limits<unsigned>::max()));
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

  // The field's value in `options` as text Set() reads back.
  static std::string Text(const OptionField<T>& f, const T& options) {
    if (f.int_field) return std::to_string(options.*(f.int_field));
    if (f.unsigned_field) return std::to_string(options.*(f.unsigned_field));
    if (f.double_field) return Num(options.*(f.double_field));
    if (f.bool_field) return options.*(f.bool_field) ? "true" : "false";
    if (f.string_field) return options.*(f.string_field);
    std::string out;
    for (const auto& item : options.*(f.list_field)) out += (out.empty() ? "" : ", ") + item;
    return "[" + out + "]";
  }

  static const char* TypeName(const OptionField<T>& f) {
    if (f.int_field) return "int";
    if (f.unsigned_field) return "int (>= 0)";
    if (f.double_field) return "double";
    if (f.bool_field) return "bool";
    if (f.string_field) return "string";
    return "list";
  }

  // The reference table of the docs: one row per field, defaults read from `defaults`.
  std::string Markdown(const T& defaults = T()) const {
    std::ostringstream os;
    os << "| parameter | type | default | meaning |\n| --- | --- | --- | --- |\n";
    for (const auto& f : fields_) {
      std::string value = Text(f, defaults);
      if (value.empty()) value = "\"\"";
      if (f.double_field && std::isnan(defaults.*(f.double_field))) value = "unset";
      os << "| `" << f.name << "` | " << TypeName(f) << " | `" << value << "` | " << f.doc
         << " |\n";
    }
    return os.str();
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
  // "name=value must be <requirement>" unless ok.
  void Check(bool ok, const std::string& name, double value, const std::string& requirement) {
    Require(ok, name + "=" + Num(value) + " must be " + requirement);
  }
  // The usual checks of a number, each naming it and its value; NaN and ±inf fail all of them.
  void Positive(const std::string& name, double v) { Check(std::isfinite(v) && v > 0.0, name, v, "> 0"); }
  void NonNegative(const std::string& name, double v) {
    Check(std::isfinite(v) && v >= 0.0, name, v, ">= 0");
  }
  void InUnitInterval(const std::string& name, double v) {
    Check(std::isfinite(v) && v >= 0.0 && v <= 1.0, name, v, "in [0, 1]");
  }
  void Finite(const std::string& name, double v) { Check(std::isfinite(v), name, v, "finite"); }
  // A frame id, topic or file name that must be given.
  void NonEmpty(const std::string& name, const std::string& v) {
    Require(!v.empty(), name + " must not be empty");
  }
  bool empty() const { return list_.empty(); }
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
