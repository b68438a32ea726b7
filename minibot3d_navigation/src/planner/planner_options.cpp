#include "minibot3d_navigation/planner/planner_options.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace minibot3d_navigation {
namespace nav {
namespace {

// One row of the option table; exactly one member pointer is non-null, so
// Set/IsName/Names stay in sync with a single edit per new option.
struct OptionField {
  const char* name;
  int GlobalPlannerOptions::*int_field;
  double GlobalPlannerOptions::*double_field;
  bool GlobalPlannerOptions::*bool_field;
  std::string GlobalPlannerOptions::*string_field;
};

using O = GlobalPlannerOptions;
constexpr OptionField Int(const char* n, int O::*f) {
  return {n, f, nullptr, nullptr, nullptr};
}
constexpr OptionField Dbl(const char* n, double O::*f) {
  return {n, nullptr, f, nullptr, nullptr};
}
constexpr OptionField Bool(const char* n, bool O::*f) {
  return {n, nullptr, nullptr, f, nullptr};
}
constexpr OptionField Str(const char* n, std::string O::*f) {
  return {n, nullptr, nullptr, nullptr, f};
}

const OptionField kFields[] = {
    Str("base_global_planner", &O::base_global_planner),
    Dbl("default_tolerance", &O::default_tolerance),
    Bool("allow_unknown", &O::allow_unknown),
    Int("neutral_cost", &O::neutral_cost),
    Dbl("cost_factor", &O::cost_factor),
    Int("lethal_cost", &O::lethal_cost),
    Bool("smooth_path", &O::smooth_path),
    Int("orientation_mode", &O::orientation_mode),
    Str("ompl_planner", &O::ompl_planner),
    Dbl("ompl_planning_time", &O::ompl_planning_time),
    Bool("ompl_simplify", &O::ompl_simplify),
    Dbl("ompl_interpolation_resolution", &O::ompl_interpolation_resolution),
    Int("ompl_seed", &O::ompl_seed),
};

const char* const kAStarNames[] = {"astar", "navfn/NavfnROS",
                                   "global_planner/GlobalPlanner"};
const char* const kOmplPlannerNames[] = {"rrtstar", "prmstar", "rrtconnect"};

const OptionField* FindField(const std::string& name) {
  for (const OptionField& f : kFields) {
    if (name == f.name) return &f;
  }
  return nullptr;
}

std::string Trim(const std::string& s) {
  const char* ws = " \t\r\n";
  const size_t b = s.find_first_not_of(ws);
  if (b == std::string::npos) return "";
  const size_t e = s.find_last_not_of(ws);
  return s.substr(b, e - b + 1);
}

[[noreturn]] void ThrowBadText(const std::string& name, const std::string& text,
                               const char* type) {
  throw std::invalid_argument("global planner option " + name +
                              ": cannot parse '" + text + "' as " + type);
}

double ParseDouble(const std::string& name, const std::string& text) {
  const std::string t = Trim(text);
  if (t.empty()) ThrowBadText(name, text, "a number");
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || errno == ERANGE) {
    ThrowBadText(name, text, "a number");
  }
  return v;
}

int ParseInt(const std::string& name, const std::string& text) {
  const std::string t = Trim(text);
  if (t.empty()) ThrowBadText(name, text, "an integer");
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(t.c_str(), &end, 10);  // NOLINT(runtime/int)
  if (end != t.c_str() + t.size() || errno == ERANGE ||
      v > std::numeric_limits<int>::max() ||
      v < std::numeric_limits<int>::min()) {
    ThrowBadText(name, text, "an integer");
  }
  return static_cast<int>(v);
}

bool ParseBool(const std::string& name, const std::string& text) {
  const std::string t = Trim(text);
  if (t == "true" || t == "True" || t == "TRUE" || t == "1") return true;
  if (t == "false" || t == "False" || t == "FALSE" || t == "0") return false;
  ThrowBadText(name, text, "a boolean");
}

std::string Num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

template <size_t N>
std::string JoinNames(const char* const (&names)[N]) {
  std::string s;
  for (size_t i = 0; i < N; ++i) s += (i ? ", " : "") + std::string(names[i]);
  return s;
}

}  // namespace

void SetGlobalPlannerOption(const std::string& name, const std::string& text,
                            GlobalPlannerOptions* options) {
  const OptionField* f = FindField(name);
  if (f == nullptr) {
    throw std::invalid_argument("unknown global planner option '" + name + "'");
  }
  if (f->int_field != nullptr) {
    options->*(f->int_field) = ParseInt(name, text);
  } else if (f->double_field != nullptr) {
    options->*(f->double_field) = ParseDouble(name, text);
  } else if (f->bool_field != nullptr) {
    options->*(f->bool_field) = ParseBool(name, text);
  } else {
    options->*(f->string_field) = Trim(text);
  }
}

bool IsGlobalPlannerOptionName(const std::string& name) {
  return FindField(name) != nullptr;
}

std::vector<std::string> GlobalPlannerOptionNames() {
  std::vector<std::string> names;
  for (const OptionField& f : kFields) names.emplace_back(f.name);
  return names;
}

std::vector<std::string> GlobalPlannerNames() {
  std::vector<std::string> names(std::begin(kAStarNames), std::end(kAStarNames));
  names.emplace_back("ompl");
  return names;
}

bool IsAStarPlannerName(const std::string& name) {
  for (const char* n : kAStarNames) {
    if (name == n) return true;
  }
  return false;
}

std::vector<std::string> OmplPlannerNames() {
  return {std::begin(kOmplPlannerNames), std::end(kOmplPlannerNames)};
}

void ValidateGlobalPlannerOptions(const GlobalPlannerOptions& o) {
  std::vector<std::string> errors;
  auto require = [&errors](bool ok, const std::string& what) {
    if (!ok) errors.push_back(what);
  };
  // Comparisons with NaN are false, so these also reject NaN.
  require(IsAStarPlannerName(o.base_global_planner) ||
              o.base_global_planner == "ompl",
          "base_global_planner='" + o.base_global_planner + "' is not one of " +
              JoinNames(kAStarNames) + ", ompl");
  require(std::isfinite(o.default_tolerance) && o.default_tolerance >= 0.0,
          "default_tolerance=" + Num(o.default_tolerance) + " must be >= 0");
  require(o.neutral_cost >= 1 && o.neutral_cost <= 1000000,
          "neutral_cost=" + std::to_string(o.neutral_cost) +
              " must be in [1, 1000000]");
  require(std::isfinite(o.cost_factor) && o.cost_factor >= 0.0 &&
              o.cost_factor <= 1e6,
          "cost_factor=" + Num(o.cost_factor) + " must be in [0, 1e6]");
  require(o.lethal_cost >= 1 && o.lethal_cost <= 254,
          "lethal_cost=" + std::to_string(o.lethal_cost) +
              " must be in [1, 254] (255 is unknown, see allow_unknown)");
  require(o.orientation_mode >= 0 && o.orientation_mode <= 2,
          "orientation_mode=" + std::to_string(o.orientation_mode) +
              " must be 0 (None), 1 (Forward) or 2 (Interpolate)");
  require(std::find(std::begin(kOmplPlannerNames), std::end(kOmplPlannerNames),
                    o.ompl_planner) != std::end(kOmplPlannerNames),
          "ompl_planner='" + o.ompl_planner + "' is not one of " +
              JoinNames(kOmplPlannerNames));
  require(std::isfinite(o.ompl_planning_time) && o.ompl_planning_time > 0.0,
          "ompl_planning_time=" + Num(o.ompl_planning_time) + " must be > 0");
  require(std::isfinite(o.ompl_interpolation_resolution) &&
              o.ompl_interpolation_resolution > 0.0,
          "ompl_interpolation_resolution=" +
              Num(o.ompl_interpolation_resolution) + " must be > 0");
  require(o.ompl_seed >= 0, "ompl_seed=" + std::to_string(o.ompl_seed) +
                                " must be >= 0 (0 = random)");
  if (!errors.empty()) {
    std::string msg = "invalid global planner options: ";
    for (size_t i = 0; i < errors.size(); ++i) {
      if (i > 0) msg += "; ";
      msg += errors[i];
    }
    throw std::invalid_argument(msg);
  }
}

std::string DescribeCost(uint8_t cost) {
  std::string s = std::to_string(cost);
  if (cost == kLethalObstacle) s += " (lethal)";
  if (cost == kInscribedInflatedObstacle) s += " (inscribed)";
  if (cost == kNoInformation) s += " (unknown)";
  return s;
}

std::string FormatXY(double x, double y) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "(%.3f, %.3f)", x, y);
  return buf;
}

PlanEndpoints ResolveEndpoints(const Costmap2D& costmap, const Pose2D& start,
                               const Pose2D& goal,
                               const GlobalPlannerOptions& options) {
  using Code = PlanningError::Code;
  if (!amcl::IsFinite(start) || !amcl::IsFinite(goal)) {
    throw PlanningError(Code::kInvalidInput,
                        "start " + FormatXY(start.x, start.y) + " yaw " +
                            Num(start.yaw) + " or goal " +
                            FormatXY(goal.x, goal.y) + " yaw " + Num(goal.yaw) +
                            " is not finite");
  }
  auto cell_text = [](int mx, int my) {
    return "cell (" + std::to_string(mx) + ", " + std::to_string(my) + ")";
  };
  const std::string extent =
      " outside the costmap [" + Num(costmap.origin_x()) + ", " +
      Num(costmap.origin_x() + costmap.size_x_m()) + "] x [" +
      Num(costmap.origin_y()) + ", " +
      Num(costmap.origin_y() + costmap.size_y_m()) + "]";
  PlanEndpoints ep;
  if (!costmap.WorldToMap(start.x, start.y, &ep.start_mx, &ep.start_my)) {
    throw PlanningError(Code::kStartOffMap,
                        "start " + FormatXY(start.x, start.y) + " is" + extent +
                            "; has the robot been localized?");
  }
  const uint8_t start_cost = costmap.cost(ep.start_mx, ep.start_my);
  // A start in the inflated band (cost >= lethal_cost but not an obstacle)
  // is allowed: the robot is there, and A* steps out of the band first.
  if (start_cost == kLethalObstacle) {
    throw PlanningError(
        Code::kStartOccupied,
        "start " + FormatXY(start.x, start.y) + " is in " +
            cell_text(ep.start_mx, ep.start_my) + " of cost " +
            DescribeCost(start_cost) + " (an obstacle): is the robot localized?");
  }
  int gx = 0, gy = 0;
  if (!costmap.WorldToMap(goal.x, goal.y, &gx, &gy)) {
    throw PlanningError(Code::kGoalOffMap,
                        "goal " + FormatXY(goal.x, goal.y) + " is" + extent);
  }
  const uint8_t goal_cost = costmap.cost(gx, gy);
  if (IsTraversableCost(goal_cost, options)) {
    ep.goal_cells.emplace_back(gx, gy);
    return ep;
  }
  // Every traversable cell whose centre lies within the tolerance, nearest
  // first (ties broken by cell order, so the choice is deterministic).
  const double res = costmap.resolution();
  const double tol = options.default_tolerance;
  const int r = static_cast<int>(std::ceil(tol / res)) + 1;
  std::vector<std::pair<double, std::pair<int, int>>> candidates;
  for (int y = std::max(0, gy - r); y <= std::min(costmap.size_y() - 1, gy + r);
       ++y) {
    for (int x = std::max(0, gx - r);
         x <= std::min(costmap.size_x() - 1, gx + r); ++x) {
      double cx, cy;
      costmap.MapToWorld(x, y, &cx, &cy);
      const double d = std::hypot(cx - goal.x, cy - goal.y);
      if (d <= tol && IsTraversableCost(costmap.cost(x, y), options)) {
        candidates.push_back({d, {x, y}});
      }
    }
  }
  if (candidates.empty()) {
    throw PlanningError(
        Code::kGoalOccupied,
        "goal " + FormatXY(goal.x, goal.y) + " is in " + cell_text(gx, gy) +
            " of cost " + DescribeCost(goal_cost) +
            (goal_cost == kNoInformation ? " (allow_unknown is false)"
                                         : " >= lethal_cost " +
                                               std::to_string(options.lethal_cost)) +
            " and no traversable cell is within default_tolerance " +
            Num(tol) + " m");
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& c : candidates) ep.goal_cells.push_back(c.second);
  ep.goal_substituted = true;
  return ep;
}

}  // namespace nav
}  // namespace minibot3d_navigation
