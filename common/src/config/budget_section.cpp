// SPDX-License-Identifier: Apache-2.0
// The `budget:` section of a machine config (ncqual/common/config/budget.hpp).
#include "node.hpp"

#include "ncqual/common/enum_names.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace ncqual {
namespace solver {

namespace {
// The names of the enums, in enumerator order: in the config and in every output.
constexpr std::array<std::string_view, 3> kAxisNames = {"y", "z", "s"};
constexpr std::array<std::string_view, 4> kDirectionNames = {"y", "z", "s", "yz"};
constexpr std::array<std::string_view, 2> kMethodNames = {"rss", "monte_carlo"};
constexpr std::array<std::string_view, 3> kDistributionNames = {"normal", "uniform", "weibull"};
}  // namespace

std::string_view to_string(BudgetAxis axis) { return name_of(kAxisNames, axis); }
std::string_view to_string(BudgetDirection direction) {
  return name_of(kDirectionNames, direction);
}
std::string_view to_string(BudgetMethod method) { return name_of(kMethodNames, method); }
std::string_view to_string(BudgetDistribution distribution) {
  return name_of(kDistributionNames, distribution);
}

std::vector<BudgetAxis> axes_of(BudgetDirection d) {
  switch (d) {
    case BudgetDirection::Y: return {BudgetAxis::Y};
    case BudgetDirection::Z: return {BudgetAxis::Z};
    case BudgetDirection::S: return {BudgetAxis::S};
    case BudgetDirection::YZ: return {BudgetAxis::Y, BudgetAxis::Z};
  }
  return {};
}

double SourceError::along(BudgetAxis axis) const {
  return axis == BudgetAxis::Y ? y_mm : axis == BudgetAxis::Z ? z_mm : s_mm;
}

double& SourceError::along(BudgetAxis axis) {
  return axis == BudgetAxis::Y ? y_mm : axis == BudgetAxis::Z ? z_mm : s_mm;
}

}  // namespace solver

namespace config {
namespace {

using namespace solver;

bool has_axis(BudgetDirection d, BudgetAxis axis) {
  const auto axes = axes_of(d);
  return std::find(axes.begin(), axes.end(), axis) != axes.end();
}

// The unit a metric's name ends in ("center_dy_mm" -> mm, "c_angle_error_arcsec" -> arcsec).
std::string unit_from_name(const std::string& name) {
  for (const char* unit : {"mm", "um", "in", "arcsec", "urad", "mrad", "rad", "deg"}) {
    const std::string suffix = std::string("_") + unit;
    if (name.size() > suffix.size() &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
      return unit;
    }
  }
  return "";
}

std::optional<double> positive_length(const Node& v) {
  const auto mm = v.quantity(units::Dimension::Length, "mm");
  if (mm && !(*mm > 0)) {
    v.problem("must be positive");
    return std::nullopt;
  }
  return mm;
}

// A bound written as a length ("0.004 in") or, for a source measured by an angle, as an angle
// ("15 arcsec"); a bare number is mm.
struct LengthOrAngle {
  double value = 0;
  bool angle = false;
};
std::optional<LengthOrAngle> length_or_angle(const Node& v) {
  if (!v.is_scalar()) {
    v.problem("expected a length or an angle with its unit");
    return std::nullopt;
  }
  try {
    return LengthOrAngle{units::parse_quantity(units::Dimension::Length, v.scalar(), "mm"), false};
  } catch (const std::invalid_argument&) {}
  try {
    return LengthOrAngle{units::parse_quantity(units::Dimension::Angle, v.scalar(), "rad"), true};
  } catch (const std::invalid_argument&) {
    v.problem("expected a length (mm, um, m, in) or an angle (rad, mrad, urad, deg, arcsec)");
    return std::nullopt;
  }
}

// One of the names of `names`, or a problem `why`.
template <typename Enum, std::size_t N>
std::optional<Enum> read_name(const Node& v, const std::array<std::string_view, N>& names,
                              const std::string& why) {
  const auto value = enum_named<Enum>(names, v.scalar());
  if (!value) v.problem(why);
  return value;
}

std::optional<BudgetAxis> read_axis(const Node& v) {
  return read_name<BudgetAxis>(v, kAxisNames, "expected y, z or s");
}

std::optional<BudgetDirection> read_direction(const Node& v) {
  return read_name<BudgetDirection>(
      v, kDirectionNames,
      "expected y (ΔS = ΔY cos θ), z (ΔS = ΔZ sin θ), yz (both) or s (along the surface)");
}

// A metric: its name alone, or {name, axis, unit, lever_arm}.
BudgetMetric read_metric(const Node& node, BudgetDirection direction) {
  BudgetMetric m;
  if (node.is_scalar()) {
    m.name = node.scalar();
  } else if (node.map_of({"name", "axis", "unit", "lever_arm"})) {
    const Node name = node["name"];
    if (name.require() && !name.is_scalar()) name.problem("expected a metric name");
    m.name = name.scalar();
  } else {
    node.problem("expected a metric name or {name, axis, unit, lever_arm}");
    return m;
  }
  if (m.name.empty()) {
    node.problem("the metric name is empty");
    return m;
  }
  const Node axis = node["axis"], unit = node["unit"], lever = node["lever_arm"];
  const std::vector<BudgetAxis> axes = axes_of(direction);
  if (axis.present()) {
    if (const auto a = read_axis(axis)) {
      m.axis = *a;
      if (!has_axis(direction, m.axis)) {
        axis.problem("the source's direction is '" + std::string(to_string(direction)) +
                     "'; its metrics measure that");
      }
    }
  } else if (axes.size() == 1) {
    m.axis = axes.front();
  } else {
    axis.problem("required for a source of direction yz: does metric '" + m.name +
                 "' measure y or z?");
  }

  if (unit.present()) {
    if (!unit.is_scalar()) unit.problem("expected a unit");
    m.unit = unit.scalar();
  } else {
    m.unit = unit_from_name(m.name);
    if (m.unit.empty()) {
      unit.problem("required: the name of metric '" + m.name + "' does not end in its unit");
      return m;
    }
  }
  if (const auto f = units::to_internal_factor(units::Dimension::Length, m.unit)) {
    m.angle = false;
    m.mm_per_unit = *f;
    if (lever.present()) {
      lever.problem("only an angle metric has a lever arm; '" + m.name + "' is a length in " +
                    m.unit);
    }
  } else if (const auto r = units::to_internal_factor(units::Dimension::Angle, m.unit)) {
    m.angle = true;
    if (!lever.present()) {
      lever.problem(
          "required for an angle metric: the length (e.g. the composite tool length L) "
          "that turns its angle into a tool-tip displacement");
    }
    m.lever_arm_mm = positive_length(lever).value_or(0);
    m.mm_per_unit = *r * m.lever_arm_mm;
  } else {
    (unit.present()     ? unit
     : node.is_scalar() ? node
                        : node["name"])
        .problem("unit '" + m.unit + "' is not one of mm, um, m, in, rad, mrad, urad, deg, arcsec");
  }
  return m;
}

// The source's default capability or fixed allowance along each of its axes, from `<stem>` (every
// axis) or `<stem>_y`, `<stem>_z`, `<stem>_s`.
SourceError read_bound(const Node& node, const std::string& stem, const BudgetSource& src) {
  SourceError bound;
  const Node all = node[stem];
  for (BudgetAxis axis : axes_of(src.direction)) {
    const Node own = node[stem + "_" + std::string(to_string(axis))];
    if (all.present() && own.present()) own.problem("also given as " + stem + "; give one");
    const Node v = own.present() ? own : all;
    if (!v.present()) {
      all.problem("required" + std::string(axes_of(src.direction).size() > 1
                                               ? " (or " + stem + "_y and " + stem + "_z)"
                                               : ""));
      continue;
    }
    const auto q = length_or_angle(v);
    if (!q) continue;
    double mm = q->value;
    if (q->angle) {
      // An angle bound becomes a length through the lever arm of the axis's angle metric.
      const auto m = std::find_if(src.metrics.begin(), src.metrics.end(),
                                  [&](const auto& m) { return m.axis == axis && m.angle; });
      if (m == src.metrics.end()) {
        v.problem("an angle needs an angle metric with a lever arm on axis " +
                  std::string(to_string(axis)) + "; write a length");
        continue;
      }
      mm = q->value * m->lever_arm_mm;
    }
    if (!(mm > 0)) v.problem("must be positive");
    bound.along(axis) = mm;
  }
  // Components the direction does not have are refused rather than silently ignored.
  for (BudgetAxis axis : {BudgetAxis::Y, BudgetAxis::Z, BudgetAxis::S}) {
    const Node own = node[stem + "_" + std::string(to_string(axis))];
    if (own.present() && !has_axis(src.direction, axis)) {
      own.problem("the source's direction is '" + std::string(to_string(src.direction)) + "'");
    }
  }
  return bound;
}

// The first of the keys present (for naming the offending key in a message).
Node first_present(const Node& node, std::initializer_list<const char*> keys) {
  for (const char* k : keys) {
    if (node[k].present()) return node[k];
  }
  return node[*keys.begin()];
}

BudgetSource read_source(const Node& node) {
  BudgetSource s;
  if (!node.map_of({"name", "description", "direction", "metrics", "capability", "capability_y",
                    "capability_z", "capability_s", "allowance", "allowance_y", "allowance_z",
                    "allowance_s", "distribution", "weibull_shape"})) {
    node.problem("expected a mapping");
    return s;
  }
  s.name = node["name"].required_text().value_or("");
  if (node["name"].present() && s.name.empty()) node["name"].problem("expected a name");
  s.description = node["description"].text("");
  if (node["direction"].require()) {
    s.direction = read_direction(node["direction"]).value_or(BudgetDirection::Y);
  }
  const Node metrics = node["metrics"];
  if (metrics.present() && !metrics.is_list()) metrics.problem("expected a list");
  for (const Node& m : metrics.items()) s.metrics.push_back(read_metric(m, s.direction));

  const std::initializer_list<const char*> capability = {"capability", "capability_y",
                                                         "capability_z", "capability_s"};
  const std::initializer_list<const char*> allowance = {"allowance", "allowance_y", "allowance_z",
                                                        "allowance_s"};
  if (s.fixed()) {
    if (const Node c = first_present(node, capability); c.present()) {
      c.problem("source '" + s.name +
                "' has no metrics: no check measures it, so give its fixed "
                "`allowance` instead");
    }
    s.bound = read_bound(node, "allowance", s);
  } else {
    if (const Node a = first_present(node, allowance); a.present()) {
      a.problem("source '" + s.name +
                "' is measured (it has metrics): its allowance is allocated "
                "from the budget; give its default `capability`");
    }
    s.bound = read_bound(node, "capability", s);
  }

  if (node["distribution"].present()) {
    s.distribution = read_name<BudgetDistribution>(node["distribution"], kDistributionNames,
                                                   "expected normal, uniform or weibull")
                         .value_or(s.distribution);
  }
  const Node shape = node["weibull_shape"];
  if (s.distribution == BudgetDistribution::Weibull) {
    if (shape.require()) {
      s.weibull_shape = shape.number().value_or(0);
      if (!(s.weibull_shape > 0)) shape.problem("must be positive");
    }
  } else if (shape.present()) {
    shape.problem("only for distribution: weibull");
  }
  return s;
}

}  // namespace

ErrorBudgetConfig read_budget(const Node& budget) {
  ErrorBudgetConfig c;
  c.where = budget.file();
  if (!budget.present()) {
    budget.problem("no error budget is configured for this machine");
    return c;
  }
  if (!budget.map_of({"allowable_total", "part", "statistics", "sources"})) return c;
  if (budget["allowable_total"].require()) {
    c.allowable_total_mm = positive_length(budget["allowable_total"]).value_or(0);
  }

  const Node part = budget["part"];
  if (!part.present()) part.problem("required: panel_radius, theta_min, theta_max");
  if (part.map_of({"panel_radius", "theta_min", "theta_max"})) {
    if (part["panel_radius"].require()) {
      c.panel_radius_mm = positive_length(part["panel_radius"]).value_or(0);
    }
    auto inclination = [](const Node& v) -> double {
      const auto rad = v.quantity(units::Dimension::Angle, "rad");
      if (rad && std::abs(*rad) > units::kPi / 2 + 1e-12) {
        v.problem("an inclination lies within -90 deg .. 90 deg (a bare number is in rad)");
      }
      return rad.value_or(0);
    };
    c.theta_min_rad = inclination(part["theta_min"]);
    if (part["theta_max"].require()) c.theta_max_rad = inclination(part["theta_max"]);
    if (c.theta_min_rad > c.theta_max_rad) part["theta_min"].problem("exceeds theta_max");
  }

  if (const Node st = budget["statistics"]; st.map_of({"method", "coverage", "samples", "seed"})) {
    if (st["method"].present()) {
      c.method = read_name<BudgetMethod>(st["method"], kMethodNames, "expected rss or monte_carlo")
                     .value_or(c.method);
    }
    c.coverage = st["coverage"].number(c.coverage);
    if (!(c.coverage > 0 && c.coverage < 1)) {
      st["coverage"].problem("must lie strictly between 0 and 1");
    }
    c.samples = st["samples"].integer(1000, 10000000, c.samples);
    const double seed = st["seed"].number(static_cast<double>(c.seed));
    if (!(seed >= 0 && seed < 9007199254740992.0) || seed != std::floor(seed)) {
      st["seed"].problem("must be a non-negative integer");
    } else {
      c.seed = static_cast<std::uint64_t>(seed);
    }
  }

  const Node sources = budget["sources"];
  if (!sources.require()) return c;
  if (!sources.is_list() || sources.size() == 0) {
    sources.problem("expected a non-empty list of error sources");
    return c;
  }
  std::set<std::string> names, metric_names;
  for (const Node& node : sources.items()) {
    BudgetSource s = read_source(node);
    if (!s.name.empty() && !names.insert(s.name).second) {
      node["name"].problem("another source has this name");
    }
    for (std::size_t k = 0; k < s.metrics.size(); ++k) {
      // A metric counted in two sources would count its error twice.
      if (!s.metrics[k].name.empty() && !metric_names.insert(s.metrics[k].name).second) {
        node["metrics"][k].problem("metric '" + s.metrics[k].name +
                                   "' already measures another source");
      }
    }
    c.sources.push_back(std::move(s));
  }
  return c;
}

}  // namespace config
}  // namespace ncqual
