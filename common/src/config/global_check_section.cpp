// SPDX-License-Identifier: Apache-2.0
// The `global_check:` section of a machine config (ncqual/common/global_check.hpp): the monthly
// laser-tracker check and the planned verification's uncertainty.
#include "node.hpp"

#include <cmath>

namespace ncqual::config {
namespace {

// Positions along one axis: a list of lengths under `<stem>_mm` (or `_in`), or a mapping
// {from_mm, to_mm, points} of evenly spaced ones. `min_points` is what the check needs.
std::vector<double> positions(const Node& parent, const std::string& stem, std::size_t min_points) {
  std::vector<double> out;
  std::string given;
  for (const char* unit : {"_mm", "_in"}) {
    const Node list = parent[stem + unit];
    if (!list.present()) continue;
    if (!given.empty()) {
      list.problem("also given in another unit; give one");
      continue;
    }
    given = unit;
    if (!list.is_list()) {
      list.problem("expected a list of lengths");
      return {};
    }
    for (const Node& item : list.items()) {
      const auto mm = item.length();
      if (!mm) return {};
      out.push_back(*mm);
    }
  }
  const Node range = parent[stem];
  if (given.empty()) {
    if (!range.is_map()) {
      range.problem("required: a list " + stem + "_mm: [...] or " + stem +
                    ": {from_mm, to_mm, points}");
      return {};
    }
    range.map_of({"from_mm", "to_mm", "from_in", "to_in", "points"});
    const Node from_node = range["from_in"].present() ? range["from_in"] : range["from_mm"];
    const Node to_node = range["to_in"].present() ? range["to_in"] : range["to_mm"];
    const auto from = from_node.required_length(), to = to_node.required_length();
    const Node points = range["points"];
    if (!points.present()) points.problem("must be an integer from 2 to 1000");
    const auto n = points.integer(2, 1000);
    if (from && to && !(*to > *from)) range["to_mm"].problem("must exceed from_mm");
    if (!from || !to || !n) return {};
    for (int i = 0; i < *n; ++i) out.push_back(*from + (*to - *from) * i / (*n - 1));
  }
  if (out.size() < min_points) {
    range.problem("needs at least " + std::to_string(min_points) + " positions");
  }
  for (std::size_t i = 1; i < out.size(); ++i) {
    if (!(out[i] > out[i - 1])) {
      parent[stem + "_mm"].problem("positions must be strictly ascending");
      break;
    }
  }
  return out;
}

// Angles: {from_deg, to_deg, points} (to inclusive) or a list under `angles_deg`.
std::vector<double> angles(const Node& parent, std::size_t min_points) {
  std::vector<double> out;
  if (const Node list = parent["angles_deg"]; list.present()) {
    if (!list.is_list()) {
      list.problem("expected a list of angles");
      return out;
    }
    for (const Node& item : list.items()) out.push_back(item.angle(0.0));
  } else {
    const auto from = parent["from_deg"].angle(), to = parent["to_deg"].angle();
    if (!parent["from_deg"].present() || !parent["to_deg"].present()) {
      parent.problem("expected {from_deg, to_deg, points} or angles_deg: [...]");
      return out;
    }
    const Node points = parent["points"];
    if (!points.present()) points.problem("must be an integer from 2 to 3600");
    const auto n = points.integer(2, 3600);
    if (from && to && !(*to > *from)) parent["to_deg"].problem("must exceed from_deg");
    if (!from || !to || !n) return out;
    for (int i = 0; i < *n; ++i) out.push_back(*from + (*to - *from) * i / (*n - 1));
  }
  if (out.size() < min_points) {
    parent.problem("needs at least " + std::to_string(min_points) + " angles");
  }
  return out;
}

// A required point of `n` lengths.
Eigen::VectorXd point(const Node& node, int n) {
  if (!node.require()) return Eigen::VectorXd::Zero(n);
  return node.lengths(n, Eigen::VectorXd::Zero(n));
}

// `<stem>_in` or `<stem>_mm`, required.
double length_in_either(const Node& parent, const std::string& stem) {
  const Node in = parent[stem + "_in"];
  return (in.present() ? in : parent[stem + "_mm"]).required_length().value_or(0);
}

ProbeGeometry read_target(const Node& node) {
  ProbeGeometry t;
  if (!node.is_map()) {
    node.problem("expected {tool_length_mm, offset_mm: [x, y]}");
    return t;
  }
  node.map_of({"tool_length_mm", "tool_length_in", "offset_mm"});
  t.tool_length_mm = length_in_either(node, "tool_length");
  if (!(t.tool_length_mm > 0)) node["tool_length_mm"].problem("must be positive");
  t.stylus_offset_mm = node["offset_mm"].lengths(2, Eigen::VectorXd::Zero(2));
  return t;
}

// ---- global_check.uncertainty ------------------------------------------------------------------

double sigma(const Node& v, double value) {
  if (value < 0) v.problem("a sigma must be >= 0");
  return value;
}

// A list of 3 values per machine axis X, Y, Z: lengths, angles or plain numbers by the key;
// `sigmas`: each must be >= 0.
enum class Kind { Length, Angle, Number };
Eigen::Vector3d per_axis(const Node& v, Kind kind, const Eigen::Vector3d& fallback,
                         bool sigmas = false) {
  const auto read = kind == Kind::Length  ? v.lengths(3)
                    : kind == Kind::Angle ? v.angles(3)
                                          : v.numbers(3);
  if (!read) return fallback;
  if (sigmas) {
    for (std::size_t i = 0; i < 3; ++i) sigma(v[i], (*read)[static_cast<int>(i)]);
  }
  return *read;
}

PlannedTrackerConfig read_planned_tracker(const Node& t) {
  PlannedTrackerConfig c;
  if (!t.required_map_of({"position_mm", "ypr_deg", "angular_sigma_urad", "radial_sigma_mm",
                          "radial_sigma_mm_per_m", "samples_per_point", "position_sigma_mm",
                          "orientation_sigma_urad"})) {
    return c;
  }
  t["position_mm"].require();
  c.position_mm = per_axis(t["position_mm"], Kind::Length, c.position_mm);
  c.ypr_rad = per_axis(t["ypr_deg"], Kind::Angle, c.ypr_rad);
  c.angular_sigma_rad =
      sigma(t["angular_sigma_urad"], t["angular_sigma_urad"].angle(c.angular_sigma_rad));
  c.radial_sigma_mm = sigma(t["radial_sigma_mm"], t["radial_sigma_mm"].length(c.radial_sigma_mm));
  c.radial_sigma_mm_per_m =
      sigma(t["radial_sigma_mm_per_m"], t["radial_sigma_mm_per_m"].length(c.radial_sigma_mm_per_m));
  c.samples_per_point = t["samples_per_point"].integer(1, 1000000, c.samples_per_point);
  c.position_sigma_mm =
      sigma(t["position_sigma_mm"], t["position_sigma_mm"].length(c.position_sigma_mm));
  c.orientation_sigma_rad = sigma(t["orientation_sigma_urad"],
                                  t["orientation_sigma_urad"].angle(c.orientation_sigma_rad));
  return c;
}

UncertaintySourcesConfig read_uncertainty_sources(const Node& s) {
  UncertaintySourcesConfig c;
  if (!s.map_of({"repeatability_sigma_mm", "expansion_per_K", "expansion_sigma_per_K",
                 "temperature_deviation_K", "temperature_sigma_K"})) {
    return c;
  }
  c.repeatability_sigma_mm =
      per_axis(s["repeatability_sigma_mm"], Kind::Length, c.repeatability_sigma_mm, true);
  c.expansion_per_K = per_axis(s["expansion_per_K"], Kind::Number, c.expansion_per_K);
  c.expansion_sigma_per_K =
      per_axis(s["expansion_sigma_per_K"], Kind::Number, c.expansion_sigma_per_K, true);
  c.temperature_deviation_K =
      per_axis(s["temperature_deviation_K"], Kind::Number, c.temperature_deviation_K);
  c.temperature_sigma_K =
      per_axis(s["temperature_sigma_K"], Kind::Number, c.temperature_sigma_K, true);
  return c;
}

TrackerSearchConfig read_tracker_search(const Node& s) {
  TrackerSearchConfig c;
  if (!s.map_of({"x_mm", "y_mm", "z_mm", "step_mm", "envelope_clearance_mm", "min_range_mm",
                 "max_range_mm"})) {
    return c;
  }
  const char* axes[] = {"x_mm", "y_mm", "z_mm"};
  for (int k = 0; k < 3; ++k) {
    const Node v = s[axes[k]];
    if (!v.present()) {
      v.problem("required: [min, max]");
      continue;
    }
    const auto range = v.lengths(2);
    if (!range) continue;
    if ((*range)[0] > (*range)[1]) v[1].problem("max must be >= min");
    c.lo_mm[k] = (*range)[0];
    c.hi_mm[k] = (*range)[1];
  }
  const Node step = s["step_mm"];
  c.step_mm = step.required_length().value_or(0);
  if (step.present() && !(c.step_mm > 0)) step.problem("must be positive");
  if (c.step_mm > 0) {
    double candidates = 1;
    for (int k = 0; k < 3; ++k) {
      // Neighbours at most step_mm apart (a hair of rounding does not add a step).
      const double intervals = std::ceil((c.hi_mm[k] - c.lo_mm[k]) / c.step_mm - 1e-9);
      candidates *= std::max(intervals, 0.0) + 1;
      c.steps[k] = static_cast<int>(std::max(intervals, 0.0)) + 1;
    }
    if (candidates > 1e6) {
      step.problem("gives more than 1e6 candidate positions in the box; take a larger step");
    }
  }
  c.envelope_clearance_mm = s["envelope_clearance_mm"].length(c.envelope_clearance_mm);
  if (c.envelope_clearance_mm < 0) s["envelope_clearance_mm"].problem("must be >= 0");
  c.min_range_mm = s["min_range_mm"].length(c.min_range_mm);
  if (c.min_range_mm < 0) s["min_range_mm"].problem("must be >= 0");
  c.max_range_mm = s["max_range_mm"].length(c.max_range_mm);
  if (!(c.max_range_mm > c.min_range_mm)) {
    s["max_range_mm"].problem("must exceed min_range_mm (" + std::to_string(c.min_range_mm) + ")");
  }
  return c;
}

VerificationUncertaintyConfig read_verification_uncertainty(const Node& node) {
  VerificationUncertaintyConfig c;
  if (!node.map_of({"tracker", "sources", "trials", "seed", "search"})) return c;
  c.tracker = read_planned_tracker(node["tracker"]);
  c.sources = read_uncertainty_sources(node["sources"]);
  c.trials = node["trials"].integer(1, 1000000, c.trials);
  if (const Node seed = node["seed"]; seed.present()) {
    const std::string text = seed.scalar();
    const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
    try {
      if (!digits) throw std::invalid_argument(text);
      c.seed = std::stoull(text);
    } catch (const std::logic_error&) {
      seed.problem("expected an integer from 0 to 18446744073709551615");
    }
  }
  if (node["search"].present()) c.search = read_tracker_search(node["search"]);
  return c;
}

}  // namespace

GlobalCheckConfig read_global_check(const Node& node) {
  GlobalCheckConfig c;
  if (!node.map_of(
          {"targets", "master_frame", "grid", "rotary", "circles", "linear_run", "uncertainty"})) {
    return c;
  }
  const Node targets = node["targets"];
  if (!targets.is_list() || targets.size() == 0) {
    targets.problem("expected a non-empty list of {tool_length_mm, offset_mm}");
  }
  for (const Node& t : targets.items()) c.targets.push_back(read_target(t));

  const Node mf = node["master_frame"];
  if (mf.required_map_of({"x_run", "y_run"})) {
    const Node xr = mf["x_run"], yr = mf["y_run"];
    if (xr.required_map_of({"x", "x_mm", "x_in", "at_mm"})) {
      c.x_run_mm = positions(xr, "x", 3);
      c.x_run_at_mm = point(xr["at_mm"], 2);
    }
    if (yr.required_map_of({"y", "y_mm", "y_in", "at_mm"})) {
      c.y_run_mm = positions(yr, "y", 3);
      c.y_run_at_mm = point(yr["at_mm"], 2);
    }
    if (c.x_run_at_mm.y() != c.y_run_at_mm.y()) {
      yr["at_mm"].problem("the X and Y runs must be at the same Z (the master frame's XY plane)");
    }
  }

  const Node grid = node["grid"];
  if (grid.required_map_of({"x", "x_mm", "x_in", "y", "y_mm", "y_in", "z", "z_mm", "z_in"})) {
    c.grid_x_mm = positions(grid, "x", 2);
    c.grid_y_mm = positions(grid, "y", 2);
    c.grid_z_mm = positions(grid, "z", 2);
  }

  const Node rot = node["rotary"];
  if (rot.required_map_of({"at_mm", "c", "a", "w"})) {
    c.rotary_at_mm = point(rot["at_mm"], 3);
    const Node rc = rot["c"];
    if (rc.required_map_of({"a_deg", "from_deg", "to_deg", "points", "angles_deg"})) {
      c.c_check_a_rad = rc["a_deg"].angle(units::deg_to_rad(45));
      if (std::abs(std::sin(c.c_check_a_rad)) < 0.1) {
        rc["a_deg"].problem(
            "A must be tilted (|sin A| >= 0.1) so the target sweeps a circle as C turns");
      }
      c.c_check_c_rad = angles(rc, 5);
    }
    const Node ra = rot["a"];
    if (ra.required_map_of({"c_deg", "from_deg", "to_deg", "points", "angles_deg"})) {
      c.a_check_c_rad = ra["c_deg"].angle(0.0);
      c.a_check_a_rad = angles(ra, 5);
    }
    const Node rw = rot["w"];
    if (rw.required_map_of({"w", "w_mm", "w_in"})) c.w_check_w_mm = positions(rw, "w", 5);
  }

  const Node circ = node["circles"];
  if (circ.required_map_of({"centre_mm", "radius_mm", "radius_in", "points", "bidirectional"})) {
    c.circle.centre_mm = point(circ["centre_mm"], 3);
    c.circle.radius_mm = length_in_either(circ, "radius");
    if (!(c.circle.radius_mm > 0)) circ["radius_mm"].problem("must be positive");
    c.circle.points = circ["points"].integer(8, 3600, 36);
    c.circle.bidirectional = circ["bidirectional"].flag().value_or(c.circle.bidirectional);
  }

  const Node lr = node["linear_run"];
  if (lr.required_map_of(
          {"axis", "at_mm", "targets", "targets_mm", "targets_in", "cycles", "overrun_mm"})) {
    const std::string axis = lr["axis"].text("");
    if (axis != "x" && axis != "y" && axis != "z") {
      lr["axis"].problem("expected x, y or z");
    } else {
      c.linear_run.axis = axis[0] - 'x';
    }
    c.linear_run.at_mm = point(lr["at_mm"], 3);
    c.linear_run.targets_mm = positions(lr, "targets", 2);
    c.linear_run.cycles = lr["cycles"].integer(2, 100, 5);
    c.linear_run.overrun_mm = lr["overrun_mm"].length(c.linear_run.overrun_mm);
    if (!(c.linear_run.overrun_mm > 0)) lr["overrun_mm"].problem("must be positive");
  }

  if (node["uncertainty"].present()) {
    c.uncertainty = read_verification_uncertainty(node["uncertainty"]);
  }
  return c;
}

}  // namespace ncqual::config
