#include "ncqual/sim/simulator_config.hpp"

#include "ncqual/clock.hpp"
#include "ncqual/units.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ncqual::sim {
namespace {

using yaml::fail;


const YAML::Node optional_map(const YAML::Node& parent, const std::string& key,
                              const std::string& where) {
  const YAML::Node node = parent[key];
  if (node && !node.IsNull() && !node.IsMap()) fail(where, key, node, "expected a mapping");
  return node;
}

// An angle that may be written under one of several keys, each naming its unit:
// <stem>_arcsec, <stem>_rad, <stem>_deg, <stem>_urad. At most one may be present.
const std::vector<std::string> kAngleSuffixes = {"_arcsec", "_rad", "_deg", "_urad"};

double angle_under_any_unit_key(const YAML::Node& node, const std::string& stem,
                                const std::string& where) {
  std::string found;
  double value = 0;
  for (const auto& suffix : kAngleSuffixes) {
    const std::string key = stem + suffix;
    if (!node[key]) continue;
    if (!found.empty()) fail(where, key, node[key], "also given as " + found + "; give one");
    found = key;
    value = yaml::angle_rad_or(node, key, 0.0, where);
  }
  return value;
}

SimulatorErrors parse_errors(const YAML::Node& node, const MachineConfig& machine,
                             const std::string& where) {
  SimulatorErrors e;
  if (!node || node.IsNull()) return e;
  std::set<std::string> known = {"machine_shift_mm", "monument_shift_mm", "stylus_offset_mm",
                                 "tool_length_error_mm", "setpoint_shift_mm"};
  for (const auto& suffix : kAngleSuffixes) {
    known.insert("c_angle_error" + suffix);
    known.insert("a_home_error" + suffix);
  }
  yaml::refuse_unknown_keys(node, known, "", where);
  e.machine_shift_mm =
      yaml::lengths_mm_or(node, "machine_shift_mm", 3, Eigen::VectorXd::Zero(3), where);
  e.monument_shift_mm =
      yaml::lengths_mm_or(node, "monument_shift_mm", 3, Eigen::VectorXd::Zero(3), where);
  e.stylus_offset_mm =
      yaml::lengths_mm_or(node, "stylus_offset_mm", 2, Eigen::VectorXd::Zero(2), where);
  e.tool_length_error_mm = yaml::length_mm_or(node, "tool_length_error_mm", 0.0, where);
  e.c_angle_error_rad = angle_under_any_unit_key(node, "c_angle_error", where);
  e.a_home_error_rad = angle_under_any_unit_key(node, "a_home_error", where);
  if (const YAML::Node shifts = optional_map(node, "setpoint_shift_mm", where);
      shifts && !shifts.IsNull()) {
    for (const auto& kv : shifts) {
      const std::string name = kv.first.as<std::string>();
      bool known_point = false;
      for (const auto& p : machine.setpoints.points) known_point |= p.name == name;
      if (!known_point) {
        fail(where, "setpoint_shift_mm." + name, kv.second,
             "not a set point of the machine's `setpoints:` section");
      }
      e.setpoint_shift_mm[name] =
          yaml::lengths_mm_or(shifts, name, 3, Eigen::VectorXd::Zero(3), where + " setpoint_shift_mm");
    }
  }
  return e;
}

// One fixture axis: `axis` 0, 1, 2 (X, Y, Z) names the misalignment keys of the other two.
FixtureAxisErrors parse_fixture_axis(const YAML::Node& node, int axis, const std::string& where) {
  FixtureAxisErrors e;
  if (!node || node.IsNull()) return e;
  static const char* kAxes[] = {"x", "y", "z"};
  std::set<std::string> known = {"offset_mm", "scale_ppm", "curvature_um_per_m2",
                                 "sine_amplitude_mm", "sine_period_mm"};
  for (const auto& suffix : kAngleSuffixes) {
    known.insert("sine_phase" + suffix);
    for (int other = 0; other < 3; ++other) {
      if (other != axis) known.insert(std::string("misalignment_") + kAxes[other] + suffix);
    }
  }
  yaml::refuse_unknown_keys(node, known, "", where);
  e.offset_mm = yaml::length_mm_or(node, "offset_mm", 0.0, where);
  e.scale_ppm = yaml::number_or(node, "scale_ppm", 0.0, where);
  e.curvature_um_per_m2 = yaml::number_or(node, "curvature_um_per_m2", 0.0, where);
  e.sine_amplitude_mm = yaml::length_mm_or(node, "sine_amplitude_mm", 0.0, where);
  e.sine_period_mm = yaml::length_mm_or(node, "sine_period_mm", 0.0, where);
  e.sine_phase_rad = angle_under_any_unit_key(node, "sine_phase", where);
  if (e.sine_amplitude_mm != 0 && !(e.sine_period_mm > 0)) {
    fail(where, "sine_period_mm", node["sine_period_mm"],
         "must be positive when sine_amplitude_mm is not zero");
  }
  for (int other = 0; other < 3; ++other) {
    if (other == axis) continue;
    e.misalignment_rad[other] =
        angle_under_any_unit_key(node, std::string("misalignment_") + kAxes[other], where);
  }
  if (!std::isfinite(e.scale_ppm)) fail(where, "scale_ppm", node["scale_ppm"], "must be finite");
  if (!std::isfinite(e.curvature_um_per_m2)) {
    fail(where, "curvature_um_per_m2", node["curvature_um_per_m2"], "must be finite");
  }
  return e;
}

FixtureErrors parse_fixture_errors(const YAML::Node& node, const MachineConfig& machine,
                                   const std::string& where) {
  FixtureErrors e;
  if (!node || node.IsNull()) return e;
  if (!machine.fixture) {
    fail(where, "fixture", node, "the machine has no `fixture:` section to simulate");
  }
  yaml::refuse_unknown_keys(
      node, {"column_x", "pogo_y", "pogo_z", "pogo_offsets_mm", "wear_sigma_mm"}, "", where);
  e.column_x = parse_fixture_axis(optional_map(node, "column_x", where), 0, where + " column_x");
  e.pogo_y = parse_fixture_axis(optional_map(node, "pogo_y", where), 1, where + " pogo_y");
  e.pogo_z = parse_fixture_axis(optional_map(node, "pogo_z", where), 2, where + " pogo_z");
  if (const YAML::Node offsets = optional_map(node, "pogo_offsets_mm", where);
      offsets && !offsets.IsNull()) {
    for (const auto& kv : offsets) {
      const std::string label = kv.first.as<std::string>();
      const auto id = parse_pogo_label(label);
      if (!id || !fixture_has_pogo(*machine.fixture, *id)) {
        fail(where, "pogo_offsets_mm." + label, kv.second,
             "not a pogo of fixture '" + machine.fixture->fixture_id + "' (C1R1 to C" +
                 std::to_string(machine.fixture->columns()) + "R" +
                 std::to_string(machine.fixture->rows()) + ")");
      }
      e.pogo_offsets_mm[label] =
          yaml::lengths_mm_or(offsets, label, 3, Eigen::VectorXd::Zero(3), where + " pogo_offsets_mm");
    }
  }
  e.wear_sigma_mm = yaml::length_mm_or(node, "wear_sigma_mm", 0.0, where);
  if (!(e.wear_sigma_mm >= 0)) fail(where, "wear_sigma_mm", node["wear_sigma_mm"], "must not be negative");
  return e;
}

TrackerModel parse_tracker(const YAML::Node& node, const std::string& where) {
  TrackerModel t;
  if (!node || node.IsNull()) return t;
  yaml::refuse_unknown_keys(node,
                            {"position_mm", "yaw_deg", "pitch_deg", "roll_deg",
                             "angular_sigma_urad", "radial_sigma_um", "radial_sigma_um_per_m",
                             "linear_run_standoff_mm", "ifm_sigma_um", "ifm_sigma_um_per_m",
                             "samples_per_point"},
                            "", where);
  t.position_mm = yaml::lengths_mm_or(node, "position_mm", 3, t.position_mm, where);
  t.ypr_rad = Eigen::Vector3d(yaml::angle_rad_or(node, "yaw_deg", t.ypr_rad[0], where),
                              yaml::angle_rad_or(node, "pitch_deg", t.ypr_rad[1], where),
                              yaml::angle_rad_or(node, "roll_deg", t.ypr_rad[2], where));
  t.angular_sigma_rad = yaml::angle_rad_or(node, "angular_sigma_urad", t.angular_sigma_rad, where);
  t.radial_sigma_mm = yaml::length_mm_or(node, "radial_sigma_um", t.radial_sigma_mm, where);
  t.radial_sigma_mm_per_m =
      yaml::number_or(node, "radial_sigma_um_per_m", t.radial_sigma_mm_per_m * 1000, where) / 1000;
  const double samples = yaml::number_or(node, "samples_per_point", 1, where);
  if (samples < 1 || samples > 100000 || samples != std::floor(samples)) {
    fail(where, "samples_per_point", node["samples_per_point"], "must be an integer from 1 to 100000");
  }
  t.samples_per_point = static_cast<int>(samples);
  t.linear_run_standoff_mm =
      yaml::length_mm_or(node, "linear_run_standoff_mm", t.linear_run_standoff_mm, where);
  t.ifm_sigma_mm = yaml::length_mm_or(node, "ifm_sigma_um", t.ifm_sigma_mm, where);
  t.ifm_sigma_mm_per_m =
      yaml::number_or(node, "ifm_sigma_um_per_m", t.ifm_sigma_mm_per_m * 1000, where) / 1000;
  for (const auto& [key, value] : {std::pair<const char*, double>{"angular_sigma_urad", t.angular_sigma_rad},
                                   {"radial_sigma_um", t.radial_sigma_mm},
                                   {"radial_sigma_um_per_m", t.radial_sigma_mm_per_m},
                                   {"linear_run_standoff_mm", t.linear_run_standoff_mm},
                                   {"ifm_sigma_um", t.ifm_sigma_mm},
                                   {"ifm_sigma_um_per_m", t.ifm_sigma_mm_per_m}}) {
    if (!(value >= 0) || !std::isfinite(value)) fail(where, key, node[key], "must not be negative");
  }
  return t;
}

// Two angles under one key (e.g. c_axis_tilt_urad: [about X, about Y]).
Eigen::Vector2d angle_pair(const YAML::Node& node, const std::string& key, const std::string& where) {
  const YAML::Node v = node[key];
  if (!v) return Eigen::Vector2d::Zero();
  if (!v.IsSequence() || v.size() != 2) fail(where, key, v, "expected a list of 2 angles");
  Eigen::Vector2d out;
  for (int i = 0; i < 2; ++i) {
    YAML::Node wrapper;
    wrapper[key] = v[static_cast<std::size_t>(i)];
    out[i] = yaml::angle_rad_or(wrapper, key, 0, where);
  }
  return out;
}

Eigen::Vector2d axis_range(const YAML::Node& ranges, const char* axis, const std::string& where) {
  const YAML::Node r = ranges[axis];
  if (!r || !r.IsSequence() || r.size() != 2) {
    fail(where, std::string("range_mm.") + axis, r, "expected [low, high] in mm");
  }
  const Eigen::Vector2d out = yaml::lengths_mm_or(ranges, axis, 2, Eigen::VectorXd::Zero(2), where);
  if (!(out[1] > out[0])) fail(where, std::string("range_mm.") + axis, r, "high must exceed low");
  return out;
}

VolumetricTruth parse_volumetric(const YAML::Node& node, const std::string& where) {
  VolumetricTruth v;
  if (!node || node.IsNull()) return v;
  std::set<std::string> known = {"repeatability_sigma_mm", "backlash_mm", "expansion_ppm_per_K",
                                 "temperature_C", "range_mm", "c_axis_tilt_urad",
                                 "c_periodic_arcsec", "c_periodic_phase_deg", "a_axis_tilt_urad",
                                 "a_periodic_arcsec", "w_scale_ppm", "w_misalignment_urad",
                                 "EC(0X)Y_urad", "EB(0X)Z_urad", "EA(0Y)Z_urad"};
  for (int i = 0; i < 18; ++i) {
    const std::string name(volumetric::function_name(i));
    known.insert(name + (i % 6 < 3 ? "_um" : "_urad"));
  }
  yaml::refuse_unknown_keys(node, known, "", where);
  v.repeatability_sigma_mm = yaml::length_mm_or(node, "repeatability_sigma_mm", 0.0, where);
  if (!(v.repeatability_sigma_mm >= 0)) {
    fail(where, "repeatability_sigma_mm", node["repeatability_sigma_mm"], "must not be negative");
  }
  v.backlash_mm = yaml::lengths_mm_or(node, "backlash_mm", 3, v.backlash_mm, where);
  if (const YAML::Node e = node["expansion_ppm_per_K"]) {
    if (!e.IsSequence() || e.size() != 3) fail(where, "expansion_ppm_per_K", e, "expected 3 numbers");
    for (int i = 0; i < 3; ++i) {
      YAML::Node w;
      w["v"] = e[static_cast<std::size_t>(i)];
      v.expansion_per_K[i] = yaml::number_or(w, "v", 0, where + " expansion_ppm_per_K") * 1e-6;
    }
  }
  if (const YAML::Node t = node["temperature_C"]) {
    if (!t.IsSequence() || t.size() != 3) fail(where, "temperature_C", t, "expected 3 numbers");
    for (int i = 0; i < 3; ++i) {
      YAML::Node w;
      w["v"] = t[static_cast<std::size_t>(i)];
      v.temperature_C[i] = yaml::number_or(w, "v", 20, where + " temperature_C");
    }
  }
  bool any_function = false;
  for (int i = 0; i < 18; ++i) {
    const std::string key =
        std::string(volumetric::function_name(i)) + (i % 6 < 3 ? "_um" : "_urad");
    const YAML::Node c = node[key];
    if (!c) continue;
    if (!c.IsSequence() || c.size() == 0 || c.size() > 12) {
      fail(where, key, c, "expected a list of 1 to 12 Legendre coefficients");
    }
    any_function = true;
    auto& f = v.rigid_body.functions[static_cast<std::size_t>(i)];
    for (std::size_t k = 0; k < c.size(); ++k) {
      YAML::Node w;
      w["v"] = c[k];
      const double value = yaml::number_or(w, "v", 0, where + " " + key);
      if (!std::isfinite(value)) fail(where, key, c, "must be finite");
      f.coefficients.push_back(value * (i % 6 < 3 ? 1e-3 : 1e-6));  // um -> mm, urad -> rad
    }
  }
  const YAML::Node ranges = node["range_mm"];
  if (any_function || ranges) {
    if (!ranges || !ranges.IsMap()) {
      fail(where, "range_mm", ranges, "required with error functions: {x: [lo, hi], y: .., z: ..}");
    }
    yaml::refuse_unknown_keys(ranges, {"x", "y", "z"}, "range_mm.", where);
    const char* axes[] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
      const Eigen::Vector2d r = axis_range(ranges, axes[a], where);
      for (int k = 0; k < 6; ++k) {
        auto& f = v.rigid_body.functions[static_cast<std::size_t>(a * 6 + k)];
        f.lo_mm = r[0];
        f.hi_mm = r[1];
      }
    }
  }
  v.rigid_body.ec0xy_rad = yaml::angle_rad_or(node, "EC(0X)Y_urad", 0, where);
  v.rigid_body.eb0xz_rad = yaml::angle_rad_or(node, "EB(0X)Z_urad", 0, where);
  v.rigid_body.ea0yz_rad = yaml::angle_rad_or(node, "EA(0Y)Z_urad", 0, where);
  v.c_axis_tilt_rad = angle_pair(node, "c_axis_tilt_urad", where);
  v.c_periodic_rad = yaml::angle_rad_or(node, "c_periodic_arcsec", 0, where);
  v.c_periodic_phase_rad = yaml::angle_rad_or(node, "c_periodic_phase_deg", 0, where);
  v.a_axis_tilt_rad = angle_pair(node, "a_axis_tilt_urad", where);
  v.a_periodic_rad = yaml::angle_rad_or(node, "a_periodic_arcsec", 0, where);
  v.w_scale_ppm = yaml::number_or(node, "w_scale_ppm", 0, where);
  v.w_misalignment_rad = angle_pair(node, "w_misalignment_urad", where);
  return v;
}

// A rate per day whose key names its unit (e.g. c_angle_error_arcsec_per_day: a bare number is
// in arcsec per day; "2 urad" is 2 urad per day), in mm or rad per day.
double rate_per_day(const YAML::Node& node, const std::string& key, units::Dimension dim,
                    std::string_view default_unit, const std::string& where) {
  const YAML::Node v = node[key];
  if (!v) return 0.0;
  if (!v.IsScalar()) fail(where, key, v, "expected a number (per day)");
  try {
    return units::parse_quantity(dim, v.Scalar(), default_unit);
  } catch (const std::invalid_argument& e) {
    fail(where, key, v, e.what());
  }
}

// An angle rate under one of <stem>_arcsec_per_day, _rad_per_day, _deg_per_day, _urad_per_day;
// at most one may be present.
double angle_rate_under_any_unit_key(const YAML::Node& node, const std::string& stem,
                                     const std::string& where) {
  std::string found;
  double value = 0;
  for (const auto& suffix : kAngleSuffixes) {
    const std::string key = stem + suffix + "_per_day";
    if (!node[key]) continue;
    if (!found.empty()) fail(where, key, node[key], "also given as " + found + "; give one");
    found = key;
    value = rate_per_day(node, key, units::Dimension::Angle, suffix.substr(1), where);
  }
  return value;
}

// `since`: "YYYY-MM-DDTHH:MM[:SS[.fff]]Z". The year is checked first: ns since 1970 in 64 bits
// reach only to 2262.
std::int64_t parse_since(const YAML::Node& node, const std::string& where) {
  const YAML::Node v = node["since"];
  const char* expected = "expected an ISO 8601 UTC time, e.g. \"2026-01-05T00:00:00Z\"";
  if (!v) fail(where, "since", v, "required: the time the drift starts from");
  if (!v.IsScalar()) fail(where, "since", v, expected);
  const std::string& text = v.Scalar();
  if (text.size() < 4 || !std::all_of(text.begin(), text.begin() + 4,
                                      [](char c) { return c >= '0' && c <= '9'; })) {
    fail(where, "since", v, expected);
  }
  const int year = std::stoi(text.substr(0, 4));
  if (year < 1900 || year > 2200) fail(where, "since", v, "the year must be from 1900 to 2200");
  const auto since = parse_iso8601(text);
  if (!since) fail(where, "since", v, expected);
  return *since;
}

SimulatorDrift parse_drift(const YAML::Node& node, const MachineConfig& machine,
                           const std::string& where) {
  std::set<std::string> known = {"since",
                                 "machine_shift_mm_per_day",
                                 "monument_shift_mm_per_day",
                                 "tool_length_error_mm_per_day",
                                 "fixture_column_x_offset_mm_per_day",
                                 "fixture_pogo_y_offset_mm_per_day",
                                 "fixture_pogo_z_offset_mm_per_day"};
  for (const auto& suffix : kAngleSuffixes) {
    known.insert("c_angle_error" + suffix + "_per_day");
    known.insert("a_home_error" + suffix + "_per_day");
    known.insert("squareness_ec0xy" + suffix + "_per_day");
  }
  yaml::refuse_unknown_keys(node, known, "", where);
  SimulatorDrift d;
  d.since_ns = parse_since(node, where);
  d.machine_shift_mm_per_day = yaml::lengths_mm_or(node, "machine_shift_mm_per_day", 3,
                                                   Eigen::VectorXd::Zero(3), where);
  d.monument_shift_mm_per_day = yaml::lengths_mm_or(node, "monument_shift_mm_per_day", 3,
                                                    Eigen::VectorXd::Zero(3), where);
  d.tool_length_error_mm_per_day = rate_per_day(node, "tool_length_error_mm_per_day",
                                                units::Dimension::Length, "mm", where);
  d.c_angle_error_rad_per_day = angle_rate_under_any_unit_key(node, "c_angle_error", where);
  d.a_home_error_rad_per_day = angle_rate_under_any_unit_key(node, "a_home_error", where);
  d.squareness_ec0xy_rad_per_day = angle_rate_under_any_unit_key(node, "squareness_ec0xy", where);
  const std::pair<const char*, double*> fixture_rates[] = {
      {"fixture_column_x_offset_mm_per_day", &d.fixture_column_x_offset_mm_per_day},
      {"fixture_pogo_y_offset_mm_per_day", &d.fixture_pogo_y_offset_mm_per_day},
      {"fixture_pogo_z_offset_mm_per_day", &d.fixture_pogo_z_offset_mm_per_day}};
  for (const auto& [key, rate] : fixture_rates) {
    *rate = rate_per_day(node, key, units::Dimension::Length, "mm", where);
    if (node[key] && !machine.fixture) {
      fail(where, key, node[key], "the machine has no `fixture:` section to drift");
    }
  }
  return d;
}

std::uint64_t parse_seed(const YAML::Node& node, const std::string& where) {
  const double seed = yaml::number_or(node, "seed", 1, where);
  // Integers up to 2^53 are exact in a double.
  if (!std::isfinite(seed) || seed < 0 || seed > 9007199254740992.0 || seed != std::floor(seed)) {
    fail(where, "seed", node["seed"], "must be a non-negative integer up to 2^53");
  }
  return static_cast<std::uint64_t>(seed);
}

}  // namespace

double FixtureAxisErrors::error_mm(double u_mm) const {
  constexpr double kTwoPi = 2 * 3.14159265358979323846;
  double e = offset_mm + scale_ppm * 1e-6 * u_mm + curvature_um_per_m2 * 1e-3 * (u_mm / 1000) * (u_mm / 1000);
  if (sine_amplitude_mm != 0 && sine_period_mm > 0) {
    e += sine_amplitude_mm * std::sin(kTwoPi * u_mm / sine_period_mm + sine_phase_rad);
  }
  return e;
}

Eigen::Matrix3d TrackerModel::rotation() const { return rotation_from_ypr(ypr_rad); }

Eigen::Vector3d FixtureAxisErrors::direction(int axis) const {
  Eigen::Vector3d d = misalignment_rad;
  d[axis] = 1.0;
  return d;
}

SimulatorConfig parse_simulator_config(const MachineConfig& machine) {
  SimulatorConfig config;
  const YAML::Node& node = machine.simulator;
  if (!node || node.IsNull()) return config;
  const std::string file =
      machine.source_path.empty() ? "machine '" + machine.machine_id + "'" : machine.source_path;
  if (!node.IsMap()) fail(file, "simulator", node, "expected a mapping");

  const std::string where = file + " [simulator]";
  yaml::refuse_unknown_keys(node,
                            {"seed", "trigger_noise_sigma_mm", "plate_thickness_mm", "errors",
                             "fixture", "part_seating_sigma_mm", "tracker", "volumetric", "drift"},
                            "", where);
  config.seed = parse_seed(node, where);
  config.trigger_noise_sigma_mm =
      yaml::length_mm_or(node, "trigger_noise_sigma_mm", config.trigger_noise_sigma_mm, where);
  if (config.trigger_noise_sigma_mm < 0) {
    fail(where, "trigger_noise_sigma_mm", node["trigger_noise_sigma_mm"], "must not be negative");
  }
  config.plate_thickness_mm =
      yaml::length_mm_or(node, "plate_thickness_mm", config.plate_thickness_mm, where);
  if (config.plate_thickness_mm <= 0) {
    fail(where, "plate_thickness_mm", node["plate_thickness_mm"], "must be positive");
  }
  config.errors =
      parse_errors(optional_map(node, "errors", where), machine, file + " [simulator.errors]");
  config.part_seating_sigma_mm = yaml::length_mm_or(node, "part_seating_sigma_mm", 0.0, where);
  if (!(config.part_seating_sigma_mm >= 0)) {
    fail(where, "part_seating_sigma_mm", node["part_seating_sigma_mm"], "must not be negative");
  }
  config.fixture = parse_fixture_errors(optional_map(node, "fixture", where), machine,
                                        file + " [simulator.fixture]");
  config.tracker = parse_tracker(optional_map(node, "tracker", where), file + " [simulator.tracker]");
  config.volumetric =
      parse_volumetric(optional_map(node, "volumetric", where), file + " [simulator.volumetric]");
  if (const YAML::Node drift = optional_map(node, "drift", where); drift && !drift.IsNull()) {
    config.drift = parse_drift(drift, machine, file + " [simulator.drift]");
  }
  return config;
}

double drift_days(const SimulatorDrift& drift, std::int64_t now_ns) {
  if (now_ns <= drift.since_ns) return 0.0;
  // The difference is positive and below 2^64: exact in unsigned arithmetic, whatever the signs.
  const std::uint64_t elapsed_ns =
      static_cast<std::uint64_t>(now_ns) - static_cast<std::uint64_t>(drift.since_ns);
  return static_cast<double>(elapsed_ns) / kNsPerDay;
}

SimulatorErrors errors_at(const SimulatorErrors& base, const std::optional<SimulatorDrift>& drift,
                          std::int64_t now_ns) {
  if (!drift) return base;
  const double days = drift_days(*drift, now_ns);
  if (days <= 0) return base;
  SimulatorErrors e = base;
  e.machine_shift_mm += drift->machine_shift_mm_per_day * days;
  e.monument_shift_mm += drift->monument_shift_mm_per_day * days;
  e.tool_length_error_mm += drift->tool_length_error_mm_per_day * days;
  e.c_angle_error_rad += drift->c_angle_error_rad_per_day * days;
  e.a_home_error_rad += drift->a_home_error_rad_per_day * days;
  return e;
}

SimulatorErrors errors_at(const SimulatorConfig& config, std::int64_t now_ns) {
  return errors_at(config.errors, config.drift, now_ns);
}

FixtureErrors fixture_errors_at(const FixtureErrors& base,
                                const std::optional<SimulatorDrift>& drift, std::int64_t now_ns) {
  if (!drift) return base;
  const double days = drift_days(*drift, now_ns);
  if (days <= 0) return base;
  FixtureErrors e = base;
  e.column_x.offset_mm += drift->fixture_column_x_offset_mm_per_day * days;
  e.pogo_y.offset_mm += drift->fixture_pogo_y_offset_mm_per_day * days;
  e.pogo_z.offset_mm += drift->fixture_pogo_z_offset_mm_per_day * days;
  return e;
}

VolumetricTruth volumetric_at(const VolumetricTruth& base,
                              const std::optional<SimulatorDrift>& drift, std::int64_t now_ns) {
  if (!drift) return base;
  const double days = drift_days(*drift, now_ns);
  if (days <= 0) return base;
  VolumetricTruth v = base;
  v.rigid_body.ec0xy_rad += drift->squareness_ec0xy_rad_per_day * days;
  return v;
}

SimulatorConfig config_at(const SimulatorConfig& config, std::int64_t now_ns) {
  SimulatorConfig c = config;
  if (!config.drift) return c;
  c.errors = errors_at(config.errors, config.drift, now_ns);
  c.fixture = fixture_errors_at(config.fixture, config.drift, now_ns);
  c.volumetric = volumetric_at(config.volumetric, config.drift, now_ns);
  c.drift.reset();
  return c;
}

double check_duration_min(CheckKind kind) {
  switch (kind) {
    case CheckKind::MonumentCAlignment: return 8;
    case CheckKind::MonumentToolLength: return 4;
    case CheckKind::MonumentPositioning: return 6;
    case CheckKind::MonumentCRotation: return 8;
    case CheckKind::FixturePreCalibration: return 25;
    case CheckKind::FixturePostCalibration: return 60;
    case CheckKind::PartSetPoints: return 5;
    case CheckKind::GlobalMasterFrame: return 20;
    case CheckKind::GlobalGrid: return 90;
    case CheckKind::RotaryW:
    case CheckKind::RotaryA:
    case CheckKind::RotaryC: return 20;
    case CheckKind::CircleXY:
    case CheckKind::CircleYZ:
    case CheckKind::CircleXZ: return 15;
    case CheckKind::LinearAxisRun: return 45;
  }
  return 10;
}

}  // namespace ncqual::sim
