#include "ncqual/global_check.hpp"

#include "ncqual/config.hpp"
#include "ncqual/units.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace ncqual {
namespace {

using yaml::fail;

YAML::Node required_map(const YAML::Node& parent, const std::string& key, const std::string& path,
                        const std::string& where) {
  const YAML::Node node = parent[key];
  if (!node || !node.IsMap()) fail(where, path, node, "required mapping");
  return node;
}

// Positions along one axis: a list of lengths under `<stem>_mm` (or `_in`), or a mapping
// {from_mm, to_mm, points} of evenly spaced ones. `min_points` is what the check needs.
std::vector<double> positions(const YAML::Node& parent, const std::string& stem,
                              const std::string& path, std::size_t min_points,
                              const std::string& where) {
  std::vector<double> out;
  for (const char* unit : {"_mm", "_in"}) {
    const std::string key = stem + unit;
    const YAML::Node list = parent[key];
    if (!list) continue;
    if (!out.empty()) fail(where, path + unit, list, "also given in another unit; give one");
    if (!list.IsSequence()) fail(where, path + unit, list, "expected a list of lengths");
    const Eigen::VectorXd v =
        yaml::lengths_mm_or(parent, key, static_cast<int>(list.size()), {}, where);
    out.assign(v.data(), v.data() + v.size());
  }
  if (out.empty()) {
    const YAML::Node range = parent[stem];
    if (!range || !range.IsMap()) {
      fail(where, path, range, "required: a list " + stem + "_mm: [...] or " + stem +
                                   ": {from_mm, to_mm, points}");
    }
    yaml::refuse_unknown_keys(range, {"from_mm", "to_mm", "from_in", "to_in", "points"},
                              path + ".", where);
    const double from = range["from_in"] ? yaml::length_mm(range, "from_in", where)
                                         : yaml::length_mm(range, "from_mm", where);
    const double to = range["to_in"] ? yaml::length_mm(range, "to_in", where)
                                     : yaml::length_mm(range, "to_mm", where);
    const double n = yaml::number_or(range, "points", 0, where);
    if (n < 2 || n > 1000 || n != std::floor(n)) {
      fail(where, path + ".points", range["points"], "must be an integer from 2 to 1000");
    }
    if (!(to > from)) fail(where, path + ".to_mm", range["to_mm"], "must exceed from_mm");
    for (int i = 0; i < static_cast<int>(n); ++i) out.push_back(from + (to - from) * i / (n - 1));
  }
  if (out.size() < min_points) {
    fail(where, path, parent[stem], "needs at least " + std::to_string(min_points) + " positions");
  }
  for (std::size_t i = 1; i < out.size(); ++i) {
    if (!(out[i] > out[i - 1])) {
      fail(where, path, parent[stem + "_mm"], "positions must be strictly ascending");
    }
  }
  return out;
}

// Angles: {from_deg, to_deg, points} (to inclusive) or a list under `<stem>_deg`.
std::vector<double> angles(const YAML::Node& parent, const std::string& path,
                           std::size_t min_points, const std::string& where) {
  std::vector<double> out;
  if (const YAML::Node list = parent["angles_deg"]) {
    if (!list.IsSequence()) fail(where, path + ".angles_deg", list, "expected a list of angles");
    for (std::size_t i = 0; i < list.size(); ++i) {
      YAML::Node wrapper;
      wrapper["v_deg"] = list[i];
      out.push_back(yaml::angle_rad_or(wrapper, "v_deg", 0, where + " " + path + ".angles_deg[" +
                                                                   std::to_string(i) + "]"));
    }
  } else {
    const double from = yaml::angle_rad_or(parent, "from_deg", NAN, where);
    const double to = yaml::angle_rad_or(parent, "to_deg", NAN, where);
    const double n = yaml::number_or(parent, "points", 0, where);
    if (std::isnan(from) || std::isnan(to)) {
      fail(where, path, parent, "expected {from_deg, to_deg, points} or angles_deg: [...]");
    }
    if (n < 2 || n > 3600 || n != std::floor(n)) {
      fail(where, path + ".points", parent["points"], "must be an integer from 2 to 3600");
    }
    if (!(to > from)) fail(where, path + ".to_deg", parent["to_deg"], "must exceed from_deg");
    for (int i = 0; i < static_cast<int>(n); ++i) out.push_back(from + (to - from) * i / (n - 1));
  }
  if (out.size() < min_points) {
    fail(where, path, parent, "needs at least " + std::to_string(min_points) + " angles");
  }
  return out;
}

Eigen::Vector3d point3(const YAML::Node& node, const std::string& key, const std::string& path,
                       const std::string& where) {
  if (!node[key]) fail(where, path + "." + key, node[key], "required");
  return yaml::lengths_mm_or(node, key, 3, Eigen::VectorXd::Zero(3), where);
}

Eigen::Vector2d point2(const YAML::Node& node, const std::string& key, const std::string& path,
                       const std::string& where) {
  if (!node[key]) fail(where, path + "." + key, node[key], "required");
  return yaml::lengths_mm_or(node, key, 2, Eigen::VectorXd::Zero(2), where);
}

ProbeGeometry parse_target(const YAML::Node& node, const std::string& path,
                           const std::string& where) {
  if (!node.IsMap()) fail(where, path, node, "expected {tool_length_mm, offset_mm: [x, y]}");
  yaml::refuse_unknown_keys(node, {"tool_length_mm", "tool_length_in", "offset_mm"}, path + ".",
                            where);
  ProbeGeometry t;
  t.tool_length_mm = node["tool_length_in"] ? yaml::length_mm(node, "tool_length_in", where)
                                            : yaml::length_mm(node, "tool_length_mm", where);
  if (!(t.tool_length_mm > 0)) {
    fail(where, path + ".tool_length_mm", node["tool_length_mm"], "must be positive");
  }
  t.stylus_offset_mm = yaml::lengths_mm_or(node, "offset_mm", 2, Eigen::VectorXd::Zero(2), where);
  return t;
}

AxisPosition pivot(const Eigen::Vector3d& p) {
  AxisPosition a;
  a.x_mm = p.x();
  a.y_mm = p.y();
  a.z_mm = p.z();
  return a;
}

std::string indexed(const char* stem, std::size_t i) { return stem + std::to_string(i); }

void append_master_frame_runs(const GlobalCheckConfig& c, std::vector<TrackerMove>& moves) {
  for (std::size_t i = 0; i < c.x_run_mm.size(); ++i) {
    moves.push_back({indexed("x_run:", i),
                     pivot({c.x_run_mm[i], c.x_run_at_mm.x(), c.x_run_at_mm.y()}), 0});
  }
  for (std::size_t i = 0; i < c.y_run_mm.size(); ++i) {
    moves.push_back({indexed("y_run:", i),
                     pivot({c.y_run_at_mm.x(), c.y_run_mm[i], c.y_run_at_mm.y()}), 0});
  }
}

// Circle in the plane of axes (u, v) about the configured centre: ccw from angle 0, then cw back.
void append_circle(const CircleTestConfig& c, int u, int v, std::vector<TrackerMove>& moves) {
  auto at = [&](double angle) {
    Eigen::Vector3d p = c.centre_mm;
    p[u] += c.radius_mm * std::cos(angle);
    p[v] += c.radius_mm * std::sin(angle);
    return pivot(p);
  };
  const double step = 2 * units::kPi / c.points;
  // Approach angle 0 from below (as the ccw path continues) so the first point arrives like
  // the others.
  moves.push_back({"", at(-step), 0});
  for (int i = 0; i < c.points; ++i) moves.push_back({indexed("ccw:", i), at(i * step), 0});
  if (!c.bidirectional) return;
  moves.push_back({"", at(c.points * step), 0});  // past the last ccw point, to angle 0 again
  for (int i = c.points - 1; i >= 0; --i) moves.push_back({indexed("cw:", i), at(i * step), 0});
}


// ---- global_check.uncertainty ------------------------------------------------------------------

// How a number of the uncertainty mapping is read: a plain number, or a quantity whose bare
// number is in the unit its key names (the string may carry its own unit).
enum class Quantity { Number, LengthMm, AngleUrad, AngleDeg };

// One scalar `v`, named `key` (the full path) in errors; refuses non-finite values.
double read_quantity(const YAML::Node& v, Quantity q, const std::string& key,
                     const std::string& where) {
  if (!v.IsScalar()) fail(where, key, v, "expected a number");
  double d = 0;
  if (q == Quantity::Number) {
    try {
      std::size_t used = 0;
      d = std::stod(v.Scalar(), &used);
      if (used != v.Scalar().size()) fail(where, key, v, "expected a number");
    } catch (const std::logic_error&) {
      fail(where, key, v, "expected a number");
    }
  } else {
    const units::Dimension dim =
        q == Quantity::LengthMm ? units::Dimension::Length : units::Dimension::Angle;
    const char* unit = q == Quantity::LengthMm ? "mm" : q == Quantity::AngleUrad ? "urad" : "deg";
    try {
      d = units::parse_quantity(dim, v.Scalar(), unit);
    } catch (const std::invalid_argument& e) {
      fail(where, key, v, e.what());
    }
  }
  if (!std::isfinite(d)) fail(where, key, v, "must be finite");
  return d;
}

// `node[key]` (path + key in errors), or `fallback` when absent.
double quantity_or(const YAML::Node& node, const std::string& key, Quantity q, double fallback,
                   const std::string& path, const std::string& where) {
  const YAML::Node v = node[key];
  if (!v) return fallback;
  return read_quantity(v, q, path + key, where);
}

// A sigma: as quantity_or, and >= 0.
double sigma_or(const YAML::Node& node, const std::string& key, Quantity q, double fallback,
                const std::string& path, const std::string& where) {
  const double s = quantity_or(node, key, q, fallback, path, where);
  if (s < 0) fail(where, path + key, node[key], "a sigma must be >= 0");
  return s;
}

// A list of `n` quantities under `key`, or `fallback` when absent.
Eigen::VectorXd quantities_or(const YAML::Node& node, const std::string& key, int n, Quantity q,
                              const Eigen::VectorXd& fallback, const std::string& path,
                              const std::string& where) {
  const YAML::Node v = node[key];
  if (!v) return fallback;
  if (!v.IsSequence() || static_cast<int>(v.size()) != n) {
    fail(where, path + key, v, "expected a list of " + std::to_string(n) + " numbers");
  }
  Eigen::VectorXd out(n);
  for (int i = 0; i < n; ++i) {
    out[i] = read_quantity(v[static_cast<std::size_t>(i)], q, path + key + "[" + std::to_string(i) + "]",
                           where);
  }
  return out;
}

// Per machine axis X, Y, Z.
Eigen::Vector3d per_axis_or(const YAML::Node& node, const std::string& key, Quantity q,
                            const Eigen::Vector3d& fallback, const std::string& path,
                            const std::string& where) {
  return quantities_or(node, key, 3, q, fallback, path, where);
}

// Per-axis sigmas: each >= 0.
Eigen::Vector3d per_axis_sigmas_or(const YAML::Node& node, const std::string& key, Quantity q,
                                   const Eigen::Vector3d& fallback, const std::string& path,
                                   const std::string& where) {
  const Eigen::Vector3d s = per_axis_or(node, key, q, fallback, path, where);
  for (int i = 0; i < 3; ++i) {
    if (s[i] < 0) {
      fail(where, path + key + "[" + std::to_string(i) + "]", node[key][static_cast<std::size_t>(i)],
           "a sigma must be >= 0");
    }
  }
  return s;
}

// An integer from `lo` to `hi`.
int count_or(const YAML::Node& node, const std::string& key, int fallback, int lo, int hi,
             const std::string& path, const std::string& where) {
  const YAML::Node v = node[key];
  if (!v) return fallback;
  const double n = read_quantity(v, Quantity::Number, path + key, where);
  if (n < lo || n > hi || n != std::floor(n)) {
    fail(where, path + key, v,
         "must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
  }
  return static_cast<int>(n);
}

std::uint64_t seed_or(const YAML::Node& node, const std::string& key, std::uint64_t fallback,
                      const std::string& path, const std::string& where) {
  const YAML::Node v = node[key];
  if (!v) return fallback;
  const std::string text = v.IsScalar() ? v.Scalar() : std::string();
  const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
  try {
    if (digits) return std::stoull(text);
  } catch (const std::logic_error&) {
  }
  fail(where, path + key, v, "expected an integer from 0 to 18446744073709551615");
}

PlannedTrackerConfig parse_planned_tracker(const YAML::Node& t, const std::string& p,
                                           const std::string& where) {
  yaml::refuse_unknown_keys(t, {"position_mm", "ypr_deg", "angular_sigma_urad", "radial_sigma_mm",
                                "radial_sigma_mm_per_m", "samples_per_point", "position_sigma_mm",
                                "orientation_sigma_urad"},
                            p, where);
  PlannedTrackerConfig c;
  if (!t["position_mm"]) fail(where, p + "position_mm", t["position_mm"], "required");
  c.position_mm = per_axis_or(t, "position_mm", Quantity::LengthMm, c.position_mm, p, where);
  c.ypr_rad = per_axis_or(t, "ypr_deg", Quantity::AngleDeg, c.ypr_rad, p, where);
  c.angular_sigma_rad =
      sigma_or(t, "angular_sigma_urad", Quantity::AngleUrad, c.angular_sigma_rad, p, where);
  c.radial_sigma_mm = sigma_or(t, "radial_sigma_mm", Quantity::LengthMm, c.radial_sigma_mm, p, where);
  c.radial_sigma_mm_per_m =
      sigma_or(t, "radial_sigma_mm_per_m", Quantity::LengthMm, c.radial_sigma_mm_per_m, p, where);
  c.samples_per_point = count_or(t, "samples_per_point", c.samples_per_point, 1, 1000000, p, where);
  c.position_sigma_mm =
      sigma_or(t, "position_sigma_mm", Quantity::LengthMm, c.position_sigma_mm, p, where);
  c.orientation_sigma_rad =
      sigma_or(t, "orientation_sigma_urad", Quantity::AngleUrad, c.orientation_sigma_rad, p, where);
  return c;
}

UncertaintySourcesConfig parse_uncertainty_sources(const YAML::Node& s, const std::string& p,
                                                   const std::string& where) {
  yaml::refuse_unknown_keys(s, {"repeatability_sigma_mm", "expansion_per_K",
                                "expansion_sigma_per_K", "temperature_deviation_K",
                                "temperature_sigma_K"},
                            p, where);
  UncertaintySourcesConfig c;
  c.repeatability_sigma_mm = per_axis_sigmas_or(s, "repeatability_sigma_mm", Quantity::LengthMm,
                                                c.repeatability_sigma_mm, p, where);
  c.expansion_per_K = per_axis_or(s, "expansion_per_K", Quantity::Number, c.expansion_per_K, p, where);
  c.expansion_sigma_per_K = per_axis_sigmas_or(s, "expansion_sigma_per_K", Quantity::Number,
                                               c.expansion_sigma_per_K, p, where);
  c.temperature_deviation_K = per_axis_or(s, "temperature_deviation_K", Quantity::Number,
                                          c.temperature_deviation_K, p, where);
  c.temperature_sigma_K = per_axis_sigmas_or(s, "temperature_sigma_K", Quantity::Number,
                                             c.temperature_sigma_K, p, where);
  return c;
}

TrackerSearchConfig parse_tracker_search(const YAML::Node& s, const std::string& p,
                                         const std::string& where) {
  yaml::refuse_unknown_keys(s, {"x_mm", "y_mm", "z_mm", "step_mm", "envelope_clearance_mm",
                                "min_range_mm", "max_range_mm"},
                            p, where);
  TrackerSearchConfig c;
  const char* axes[] = {"x_mm", "y_mm", "z_mm"};
  for (int k = 0; k < 3; ++k) {
    if (!s[axes[k]]) fail(where, p + axes[k], s[axes[k]], "required: [min, max]");
    const Eigen::VectorXd range =
        quantities_or(s, axes[k], 2, Quantity::LengthMm, Eigen::VectorXd::Zero(2), p, where);
    if (range[0] > range[1]) fail(where, p + axes[k] + "[1]", s[axes[k]][1], "max must be >= min");
    c.lo_mm[k] = range[0];
    c.hi_mm[k] = range[1];
  }
  if (!s["step_mm"]) fail(where, p + "step_mm", s["step_mm"], "required");
  c.step_mm = quantity_or(s, "step_mm", Quantity::LengthMm, 0, p, where);
  if (!(c.step_mm > 0)) fail(where, p + "step_mm", s["step_mm"], "must be positive");
  double candidates = 1;
  for (int k = 0; k < 3; ++k) {
    // Neighbours at most step_mm apart (a hair of rounding does not add a step).
    const double intervals = std::ceil((c.hi_mm[k] - c.lo_mm[k]) / c.step_mm - 1e-9);
    candidates *= std::max(intervals, 0.0) + 1;
    if (candidates > 1e6) {
      fail(where, p + "step_mm", s["step_mm"],
           "gives more than 1e6 candidate positions in the box; take a larger step");
    }
    c.steps[k] = static_cast<int>(std::max(intervals, 0.0)) + 1;
  }
  c.envelope_clearance_mm = quantity_or(s, "envelope_clearance_mm", Quantity::LengthMm,
                                        c.envelope_clearance_mm, p, where);
  if (c.envelope_clearance_mm < 0) {
    fail(where, p + "envelope_clearance_mm", s["envelope_clearance_mm"], "must be >= 0");
  }
  c.min_range_mm = quantity_or(s, "min_range_mm", Quantity::LengthMm, c.min_range_mm, p, where);
  if (c.min_range_mm < 0) fail(where, p + "min_range_mm", s["min_range_mm"], "must be >= 0");
  c.max_range_mm = quantity_or(s, "max_range_mm", Quantity::LengthMm, c.max_range_mm, p, where);
  if (!(c.max_range_mm > c.min_range_mm)) {
    fail(where, p + "max_range_mm", s["max_range_mm"],
         "must exceed min_range_mm (" + std::to_string(c.min_range_mm) + ")");
  }
  return c;
}

VerificationUncertaintyConfig parse_verification_uncertainty(const YAML::Node& node,
                                                             const std::string& p,
                                                             const std::string& where) {
  if (!node.IsMap()) fail(where, "global_check.uncertainty", node, "expected a mapping");
  yaml::refuse_unknown_keys(node, {"tracker", "sources", "trials", "seed", "search"}, p, where);
  VerificationUncertaintyConfig c;
  c.tracker = parse_planned_tracker(required_map(node, "tracker", p + "tracker", where),
                                    p + "tracker.", where);
  if (const YAML::Node s = node["sources"]) {
    if (!s.IsMap()) fail(where, p + "sources", s, "expected a mapping");
    c.sources = parse_uncertainty_sources(s, p + "sources.", where);
  }
  c.trials = count_or(node, "trials", c.trials, 1, 1000000, p, where);
  c.seed = seed_or(node, "seed", c.seed, p, where);
  if (const YAML::Node s = node["search"]) {
    if (!s.IsMap()) fail(where, p + "search", s, "expected a mapping");
    c.search = parse_tracker_search(s, p + "search.", where);
  }
  return c;
}

}  // namespace

bool is_tracker_check(CheckKind kind) {
  switch (kind) {
    case CheckKind::GlobalMasterFrame:
    case CheckKind::GlobalGrid:
    case CheckKind::RotaryW:
    case CheckKind::RotaryA:
    case CheckKind::RotaryC:
    case CheckKind::CircleXY:
    case CheckKind::CircleYZ:
    case CheckKind::CircleXZ:
    case CheckKind::LinearAxisRun:
      return true;
    default:
      return false;
  }
}

GlobalCheckConfig parse_global_check_config(const YAML::Node& node, const std::string& where) {
  const std::string p = "global_check.";
  if (!node.IsMap()) fail(where, "global_check", node, "expected a mapping");
  yaml::refuse_unknown_keys(node, {"targets", "master_frame", "grid", "rotary", "circles",
                                   "linear_run", "uncertainty"},
                            p, where);
  GlobalCheckConfig c;

  const YAML::Node targets = node["targets"];
  if (!targets || !targets.IsSequence() || targets.size() == 0) {
    fail(where, p + "targets", targets, "expected a non-empty list of {tool_length_mm, offset_mm}");
  }
  for (std::size_t i = 0; i < targets.size(); ++i) {
    c.targets.push_back(parse_target(targets[i], p + "targets[" + std::to_string(i) + "]", where));
  }

  const YAML::Node mf = required_map(node, "master_frame", p + "master_frame", where);
  yaml::refuse_unknown_keys(mf, {"x_run", "y_run"}, p + "master_frame.", where);
  const YAML::Node xr = required_map(mf, "x_run", p + "master_frame.x_run", where);
  const YAML::Node yr = required_map(mf, "y_run", p + "master_frame.y_run", where);
  yaml::refuse_unknown_keys(xr, {"x", "x_mm", "x_in", "at_mm"}, p + "master_frame.x_run.", where);
  yaml::refuse_unknown_keys(yr, {"y", "y_mm", "y_in", "at_mm"}, p + "master_frame.y_run.", where);
  c.x_run_mm = positions(xr, "x", p + "master_frame.x_run.x", 3, where);
  c.y_run_mm = positions(yr, "y", p + "master_frame.y_run.y", 3, where);
  c.x_run_at_mm = point2(xr, "at_mm", p + "master_frame.x_run", where);
  c.y_run_at_mm = point2(yr, "at_mm", p + "master_frame.y_run", where);
  if (c.x_run_at_mm.y() != c.y_run_at_mm.y()) {
    fail(where, p + "master_frame.y_run.at_mm", yr["at_mm"],
         "the X and Y runs must be at the same Z (the master frame's XY plane)");
  }

  const YAML::Node grid = required_map(node, "grid", p + "grid", where);
  yaml::refuse_unknown_keys(grid, {"x", "x_mm", "x_in", "y", "y_mm", "y_in", "z", "z_mm", "z_in"},
                            p + "grid.", where);
  c.grid_x_mm = positions(grid, "x", p + "grid.x", 2, where);
  c.grid_y_mm = positions(grid, "y", p + "grid.y", 2, where);
  c.grid_z_mm = positions(grid, "z", p + "grid.z", 2, where);

  const YAML::Node rot = required_map(node, "rotary", p + "rotary", where);
  yaml::refuse_unknown_keys(rot, {"at_mm", "c", "a", "w"}, p + "rotary.", where);
  c.rotary_at_mm = point3(rot, "at_mm", p + "rotary", where);
  const YAML::Node rc = required_map(rot, "c", p + "rotary.c", where);
  yaml::refuse_unknown_keys(rc, {"a_deg", "from_deg", "to_deg", "points", "angles_deg"},
                            p + "rotary.c.", where);
  c.c_check_a_rad = yaml::angle_rad_or(rc, "a_deg", units::deg_to_rad(45), where);
  if (std::abs(std::sin(c.c_check_a_rad)) < 0.1) {
    fail(where, p + "rotary.c.a_deg", rc["a_deg"],
         "A must be tilted (|sin A| >= 0.1) so the target sweeps a circle as C turns");
  }
  c.c_check_c_rad = angles(rc, p + "rotary.c", 5, where);
  const YAML::Node ra = required_map(rot, "a", p + "rotary.a", where);
  yaml::refuse_unknown_keys(ra, {"c_deg", "from_deg", "to_deg", "points", "angles_deg"},
                            p + "rotary.a.", where);
  c.a_check_c_rad = yaml::angle_rad_or(ra, "c_deg", 0, where);
  c.a_check_a_rad = angles(ra, p + "rotary.a", 5, where);
  const YAML::Node rw = required_map(rot, "w", p + "rotary.w", where);
  yaml::refuse_unknown_keys(rw, {"w", "w_mm", "w_in"}, p + "rotary.w.", where);
  c.w_check_w_mm = positions(rw, "w", p + "rotary.w.w", 5, where);

  const YAML::Node circ = required_map(node, "circles", p + "circles", where);
  yaml::refuse_unknown_keys(circ, {"centre_mm", "radius_mm", "radius_in", "points", "bidirectional"},
                            p + "circles.", where);
  c.circle.centre_mm = point3(circ, "centre_mm", p + "circles", where);
  c.circle.radius_mm = circ["radius_in"] ? yaml::length_mm(circ, "radius_in", where)
                                         : yaml::length_mm(circ, "radius_mm", where);
  if (!(c.circle.radius_mm > 0)) fail(where, p + "circles.radius_mm", circ["radius_mm"], "must be positive");
  const double n = yaml::number_or(circ, "points", 36, where);
  if (n < 8 || n > 3600 || n != std::floor(n)) {
    fail(where, p + "circles.points", circ["points"], "must be an integer from 8 to 3600");
  }
  c.circle.points = static_cast<int>(n);
  if (const YAML::Node b = circ["bidirectional"]) {
    if (!b.IsScalar() || (b.Scalar() != "true" && b.Scalar() != "false")) {
      fail(where, p + "circles.bidirectional", b, "expected true or false");
    }
    c.circle.bidirectional = b.Scalar() == "true";
  }

  const YAML::Node lr = required_map(node, "linear_run", p + "linear_run", where);
  yaml::refuse_unknown_keys(lr, {"axis", "at_mm", "targets", "targets_mm", "targets_in", "cycles",
                                 "overrun_mm"},
                            p + "linear_run.", where);
  const std::string axis = yaml::string_or(lr, "axis", "", where);
  if (axis != "x" && axis != "y" && axis != "z") {
    fail(where, p + "linear_run.axis", lr["axis"], "expected x, y or z");
  }
  c.linear_run.axis = axis[0] - 'x';
  c.linear_run.at_mm = point3(lr, "at_mm", p + "linear_run", where);
  c.linear_run.targets_mm = positions(lr, "targets", p + "linear_run.targets", 2, where);
  const double cycles = yaml::number_or(lr, "cycles", 5, where);
  if (cycles < 2 || cycles > 100 || cycles != std::floor(cycles)) {
    fail(where, p + "linear_run.cycles", lr["cycles"], "must be an integer from 2 to 100");
  }
  c.linear_run.cycles = static_cast<int>(cycles);
  c.linear_run.overrun_mm = yaml::length_mm_or(lr, "overrun_mm", c.linear_run.overrun_mm, where);
  if (!(c.linear_run.overrun_mm > 0)) {
    fail(where, p + "linear_run.overrun_mm", lr["overrun_mm"], "must be positive");
  }

  if (const YAML::Node u = node["uncertainty"]; u && !u.IsNull()) {
    c.uncertainty = parse_verification_uncertainty(u, p + "uncertainty.", where);
  }
  return c;
}

std::vector<TrackerMove> global_check_program(CheckKind kind, const GlobalCheckConfig& c) {
  if (!is_tracker_check(kind)) {
    throw std::invalid_argument("check kind '" + std::string(to_string(kind)) +
                                "' is not a laser-tracker check");
  }
  std::vector<TrackerMove> moves;
  // The linear run is measured from its own station on the axis line (interferometer mode): the
  // master-frame runs of the session would be in another frame, so it has none.
  if (kind != CheckKind::LinearAxisRun) append_master_frame_runs(c, moves);
  switch (kind) {
    case CheckKind::GlobalMasterFrame:
      break;
    case CheckKind::GlobalGrid: {
      const std::size_t nx = c.grid_x_mm.size(), ny = c.grid_y_mm.size();
      for (std::size_t k = 0; k < c.targets.size(); ++k) {
        for (std::size_t iz = 0; iz < c.grid_z_mm.size(); ++iz) {
          for (std::size_t iy = 0; iy < ny; ++iy) {
            for (std::size_t ix = 0; ix < nx; ++ix) {
              const std::size_t i = (iz * ny + iy) * nx + ix;
              moves.push_back({"grid:" + std::to_string(i) + ":t" + std::to_string(k),
                               pivot({c.grid_x_mm[ix], c.grid_y_mm[iy], c.grid_z_mm[iz]}),
                               static_cast<int>(k)});
            }
          }
        }
      }
      break;
    }
    case CheckKind::RotaryC:
      for (std::size_t i = 0; i < c.c_check_c_rad.size(); ++i) {
        AxisPosition a = pivot(c.rotary_at_mm);
        a.a_rad = c.c_check_a_rad;
        a.c_rad = c.c_check_c_rad[i];
        moves.push_back({indexed("c:", i), a, 0});
      }
      break;
    case CheckKind::RotaryA:
      for (std::size_t i = 0; i < c.a_check_a_rad.size(); ++i) {
        AxisPosition a = pivot(c.rotary_at_mm);
        a.c_rad = c.a_check_c_rad;
        a.a_rad = c.a_check_a_rad[i];
        moves.push_back({indexed("a:", i), a, 0});
      }
      break;
    case CheckKind::RotaryW:
      for (std::size_t i = 0; i < c.w_check_w_mm.size(); ++i) {
        AxisPosition a = pivot(c.rotary_at_mm);
        a.w_mm = c.w_check_w_mm[i];
        moves.push_back({indexed("w:", i), a, 0});
      }
      break;
    case CheckKind::CircleXY:
      append_circle(c.circle, 0, 1, moves);
      break;
    case CheckKind::CircleYZ:
      append_circle(c.circle, 1, 2, moves);
      break;
    case CheckKind::CircleXZ:
      append_circle(c.circle, 0, 2, moves);
      break;
    case CheckKind::LinearAxisRun: {
      const LinearRunConfig& r = c.linear_run;
      auto at = [&](double q) {
        Eigen::Vector3d p = r.at_mm;
        p[r.axis] = q;
        return pivot(p);
      };
      const std::size_t n = r.targets_mm.size();
      for (int cycle = 1; cycle <= r.cycles; ++cycle) {
        // ISO 230-2 standard test cycle: approach every target upwards, overrun, then every
        // target downwards, overrun below the first.
        moves.push_back({"", at(r.targets_mm.front() - r.overrun_mm), 0});
        for (std::size_t i = 0; i < n; ++i) {
          moves.push_back({"run:" + std::to_string(cycle) + ":up:" + std::to_string(i),
                           at(r.targets_mm[i]), 0});
        }
        moves.push_back({"", at(r.targets_mm.back() + r.overrun_mm), 0});
        for (std::size_t i = n; i-- > 0;) {
          moves.push_back({"run:" + std::to_string(cycle) + ":down:" + std::to_string(i),
                           at(r.targets_mm[i]), 0});
        }
      }
      break;
    }
    default:
      break;
  }
  return moves;
}

}  // namespace ncqual
