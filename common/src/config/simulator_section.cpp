// SPDX-License-Identifier: Apache-2.0
// The `simulator:` section of a machine config (ncqual/common/config/simulator.hpp).
#include "node.hpp"

#include "ncqual/common/clock.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace ncqual::config {
namespace {

using namespace sim;

// An angle that may be written under one of several keys, each naming its unit:
// <stem>_arcsec, <stem>_rad, <stem>_deg, <stem>_urad (then `tail`, e.g. "_per_day"). At most one
// may be present.
const std::vector<std::string> kAngleSuffixes = {"_arcsec", "_rad", "_deg", "_urad"};

double angle_under_any_unit_key(const Node& node, const std::string& stem,
                                const std::string& tail = "") {
  std::string found;
  double value = 0;
  for (const auto& suffix : kAngleSuffixes) {
    const Node v = node[stem + suffix + tail];
    if (!v.present()) continue;
    if (!found.empty()) {
      v.problem("also given as " + found + "; give one");
      continue;
    }
    found = stem + suffix + tail;
    value = v.quantity(units::Dimension::Angle, suffix.substr(1)).value_or(0);
  }
  return value;
}

void add_angle_keys(std::set<std::string>& known, const std::string& stem,
                    const std::string& tail = "") {
  for (const auto& suffix : kAngleSuffixes) known.insert(stem + suffix + tail);
}

double non_negative(const Node& v, double value) {
  if (!(value >= 0)) v.problem("must not be negative");
  return value;
}

SimulatorErrors read_errors(const Node& node, const MachineConfig& machine) {
  SimulatorErrors e;
  std::set<std::string> known = {"machine_shift_mm", "monument_shift_mm", "stylus_offset_mm",
                                 "tool_length_error_mm", "setpoint_shift_mm"};
  add_angle_keys(known, "c_angle_error");
  add_angle_keys(known, "a_home_error");
  if (!node.map_of(known)) return e;
  e.machine_shift_mm = node["machine_shift_mm"].lengths(3, e.machine_shift_mm);
  e.monument_shift_mm = node["monument_shift_mm"].lengths(3, e.monument_shift_mm);
  e.stylus_offset_mm = node["stylus_offset_mm"].lengths(2, e.stylus_offset_mm);
  e.tool_length_error_mm = node["tool_length_error_mm"].length(0.0);
  e.c_angle_error_rad = angle_under_any_unit_key(node, "c_angle_error");
  e.a_home_error_rad = angle_under_any_unit_key(node, "a_home_error");
  const Node shifts = node["setpoint_shift_mm"];
  if (shifts.present() && !shifts.is_map()) shifts.problem("expected a mapping");
  for (const auto& [name, shift] : shifts.entries()) {
    const bool known_point =
        std::any_of(machine.setpoints.points.begin(), machine.setpoints.points.end(),
                    [&point = name](const SetPointConfig& p) { return p.name == point; });
    if (!known_point) {
      shift.problem("not a set point of the machine's `setpoints:` section");
      continue;
    }
    e.setpoint_shift_mm[name] = shift.lengths(3, Eigen::VectorXd::Zero(3));
  }
  return e;
}

// One fixture axis: `axis` 0, 1, 2 (X, Y, Z) names the misalignment keys of the other two.
FixtureAxisErrors read_fixture_axis(const Node& node, int axis) {
  FixtureAxisErrors e;
  static const char* kAxes[] = {"x", "y", "z"};
  std::set<std::string> known = {"offset_mm", "scale_ppm", "curvature_um_per_m2",
                                 "sine_amplitude_mm", "sine_period_mm"};
  add_angle_keys(known, "sine_phase");
  for (int other = 0; other < 3; ++other) {
    if (other != axis) add_angle_keys(known, std::string("misalignment_") + kAxes[other]);
  }
  if (!node.map_of(known)) return e;
  e.offset_mm = node["offset_mm"].length(0.0);
  e.scale_ppm = node["scale_ppm"].number(0.0);
  e.curvature_um_per_m2 = node["curvature_um_per_m2"].number(0.0);
  e.sine_amplitude_mm = node["sine_amplitude_mm"].length(0.0);
  e.sine_period_mm = node["sine_period_mm"].length(0.0);
  e.sine_phase_rad = angle_under_any_unit_key(node, "sine_phase");
  if (e.sine_amplitude_mm != 0 && !(e.sine_period_mm > 0)) {
    node["sine_period_mm"].problem("must be positive when sine_amplitude_mm is not zero");
  }
  for (int other = 0; other < 3; ++other) {
    if (other == axis) continue;
    e.misalignment_rad[other] =
        angle_under_any_unit_key(node, std::string("misalignment_") + kAxes[other]);
  }
  return e;
}

FixtureErrors read_fixture_errors(const Node& node, const MachineConfig& machine) {
  FixtureErrors e;
  if (!node.present()) return e;
  if (!machine.fixture) {
    node.problem("the machine has no `fixture:` section to simulate");
    return e;
  }
  if (!node.map_of({"column_x", "pogo_y", "pogo_z", "pogo_offsets_mm", "wear_sigma_mm"})) return e;
  e.column_x = read_fixture_axis(node["column_x"], 0);
  e.pogo_y = read_fixture_axis(node["pogo_y"], 1);
  e.pogo_z = read_fixture_axis(node["pogo_z"], 2);
  const Node offsets = node["pogo_offsets_mm"];
  if (offsets.present() && !offsets.is_map()) offsets.problem("expected a mapping");
  for (const auto& [label, offset] : offsets.entries()) {
    const auto id = parse_pogo_label(label);
    if (!id || !fixture_has_pogo(*machine.fixture, *id)) {
      offset.problem("not a pogo of fixture '" + machine.fixture->fixture_id + "' (C1R1 to C" +
                     std::to_string(machine.fixture->columns()) + "R" +
                     std::to_string(machine.fixture->rows()) + ")");
      continue;
    }
    e.pogo_offsets_mm[label] = offset.lengths(3, Eigen::VectorXd::Zero(3));
  }
  e.wear_sigma_mm = non_negative(node["wear_sigma_mm"], node["wear_sigma_mm"].length(0.0));
  return e;
}

TrackerModel read_tracker(const Node& node) {
  TrackerModel t;
  if (!node.map_of({"position_mm", "yaw_deg", "pitch_deg", "roll_deg", "angular_sigma_urad",
                    "radial_sigma_um", "radial_sigma_um_per_m", "linear_run_standoff_mm",
                    "ifm_sigma_um", "ifm_sigma_um_per_m", "samples_per_point"})) {
    return t;
  }
  t.position_mm = node["position_mm"].lengths(3, t.position_mm);
  t.ypr_rad =
      Eigen::Vector3d(node["yaw_deg"].angle(t.ypr_rad[0]), node["pitch_deg"].angle(t.ypr_rad[1]),
                      node["roll_deg"].angle(t.ypr_rad[2]));
  auto sigma = [&](const char* key, double value) { return non_negative(node[key], value); };
  t.angular_sigma_rad =
      sigma("angular_sigma_urad", node["angular_sigma_urad"].angle(t.angular_sigma_rad));
  t.radial_sigma_mm = sigma("radial_sigma_um", node["radial_sigma_um"].length(t.radial_sigma_mm));
  t.radial_sigma_mm_per_m =
      sigma("radial_sigma_um_per_m",
            node["radial_sigma_um_per_m"].number(t.radial_sigma_mm_per_m * 1000) / 1000);
  t.samples_per_point = node["samples_per_point"].integer(1, 100000, 1);
  t.linear_run_standoff_mm = sigma("linear_run_standoff_mm",
                                   node["linear_run_standoff_mm"].length(t.linear_run_standoff_mm));
  t.ifm_sigma_mm = sigma("ifm_sigma_um", node["ifm_sigma_um"].length(t.ifm_sigma_mm));
  t.ifm_sigma_mm_per_m = sigma(
      "ifm_sigma_um_per_m", node["ifm_sigma_um_per_m"].number(t.ifm_sigma_mm_per_m * 1000) / 1000);
  return t;
}

// Two angles under one key (e.g. c_axis_tilt_urad: [about X, about Y]); zero when absent.
Eigen::Vector2d angle_pair(const Node& v) { return v.angles(2).value_or(Eigen::Vector2d::Zero()); }

VolumetricTruth read_volumetric(const Node& node) {
  VolumetricTruth v;
  std::set<std::string> known = {"repeatability_sigma_mm",
                                 "backlash_mm",
                                 "expansion_ppm_per_K",
                                 "temperature_C",
                                 "range_mm",
                                 "c_axis_tilt_urad",
                                 "c_periodic_arcsec",
                                 "c_periodic_phase_deg",
                                 "a_axis_tilt_urad",
                                 "a_periodic_arcsec",
                                 "w_scale_ppm",
                                 "w_misalignment_urad",
                                 "EC(0X)Y_urad",
                                 "EB(0X)Z_urad",
                                 "EA(0Y)Z_urad"};
  auto function_key = [](int i) {
    return std::string(volumetric::function_name(i)) + (i % 6 < 3 ? "_um" : "_urad");
  };
  for (int i = 0; i < 18; ++i) known.insert(function_key(i));
  if (!node.map_of(known)) return v;
  v.repeatability_sigma_mm =
      non_negative(node["repeatability_sigma_mm"], node["repeatability_sigma_mm"].length(0.0));
  v.backlash_mm = node["backlash_mm"].lengths(3, v.backlash_mm);
  if (const auto ppm = node["expansion_ppm_per_K"].numbers(3)) v.expansion_per_K = *ppm * 1e-6;
  v.temperature_C = node["temperature_C"].numbers(3).value_or(v.temperature_C);
  bool any_function = false;
  for (int i = 0; i < 18; ++i) {
    const Node c = node[function_key(i)];
    if (!c.present()) continue;
    if (!c.is_list() || c.size() == 0 || c.size() > 12) {
      c.problem("expected a list of 1 to 12 Legendre coefficients");
      continue;
    }
    any_function = true;
    auto& f = v.rigid_body.functions[static_cast<std::size_t>(i)];
    for (const Node& k : c.items()) {
      // um -> mm, urad -> rad
      f.coefficients.push_back(k.number().value_or(0) * (i % 6 < 3 ? 1e-3 : 1e-6));
    }
  }
  const Node ranges = node["range_mm"];
  if (any_function || ranges.present()) {
    if (!ranges.is_map()) {
      ranges.problem("required with error functions: {x: [lo, hi], y: .., z: ..}");
    } else if (ranges.map_of({"x", "y", "z"})) {
      const char* axes[] = {"x", "y", "z"};
      for (int a = 0; a < 3; ++a) {
        const Node r = ranges[axes[a]];
        if (!r.is_list() || r.size() != 2) {
          r.problem("expected [low, high] in mm");
          continue;
        }
        const auto range = r.lengths(2);
        if (!range) continue;
        if (!((*range)[1] > (*range)[0])) r.problem("high must exceed low");
        for (int k = 0; k < 6; ++k) {
          auto& f = v.rigid_body.functions[static_cast<std::size_t>(a * 6 + k)];
          f.lo_mm = (*range)[0];
          f.hi_mm = (*range)[1];
        }
      }
    }
  }
  v.rigid_body.ec0xy_rad = node["EC(0X)Y_urad"].angle(0.0);
  v.rigid_body.eb0xz_rad = node["EB(0X)Z_urad"].angle(0.0);
  v.rigid_body.ea0yz_rad = node["EA(0Y)Z_urad"].angle(0.0);
  v.c_axis_tilt_rad = angle_pair(node["c_axis_tilt_urad"]);
  v.c_periodic_rad = node["c_periodic_arcsec"].angle(0.0);
  v.c_periodic_phase_rad = node["c_periodic_phase_deg"].angle(0.0);
  v.a_axis_tilt_rad = angle_pair(node["a_axis_tilt_urad"]);
  v.a_periodic_rad = node["a_periodic_arcsec"].angle(0.0);
  v.w_scale_ppm = node["w_scale_ppm"].number(0.0);
  v.w_misalignment_rad = angle_pair(node["w_misalignment_urad"]);
  return v;
}

// `since`: "YYYY-MM-DDTHH:MM[:SS[.fff]]Z". The year is checked first: ns since 1970 in 64 bits
// reach only to 2262.
std::int64_t read_since(const Node& v) {
  const char* expected = "expected an ISO 8601 UTC time, e.g. \"2026-01-05T00:00:00Z\"";
  if (!v.present()) {
    v.problem("required: the time the drift starts from");
    return 0;
  }
  const std::string text = v.scalar();
  if (text.size() < 4 ||
      !std::all_of(text.begin(), text.begin() + 4, [](char c) { return c >= '0' && c <= '9'; })) {
    v.problem(expected);
    return 0;
  }
  const int year = std::stoi(text.substr(0, 4));
  if (year < 1900 || year > 2200) {
    v.problem("the year must be from 1900 to 2200");
    return 0;
  }
  const auto since = parse_iso8601(text);
  if (!since) v.problem(expected);
  return since.value_or(0);
}

SimulatorDrift read_drift(const Node& node, const MachineConfig& machine) {
  SimulatorDrift d;
  std::set<std::string> known = {"since",
                                 "machine_shift_mm_per_day",
                                 "monument_shift_mm_per_day",
                                 "tool_length_error_mm_per_day",
                                 "fixture_column_x_offset_mm_per_day",
                                 "fixture_pogo_y_offset_mm_per_day",
                                 "fixture_pogo_z_offset_mm_per_day"};
  for (const char* stem : {"c_angle_error", "a_home_error", "squareness_ec0xy"}) {
    add_angle_keys(known, stem, "_per_day");
  }
  if (!node.map_of(known)) return d;
  d.since_ns = read_since(node["since"]);
  d.machine_shift_mm_per_day =
      node["machine_shift_mm_per_day"].lengths(3, d.machine_shift_mm_per_day);
  d.monument_shift_mm_per_day =
      node["monument_shift_mm_per_day"].lengths(3, d.monument_shift_mm_per_day);
  d.tool_length_error_mm_per_day = node["tool_length_error_mm_per_day"].length(0.0);
  d.c_angle_error_rad_per_day = angle_under_any_unit_key(node, "c_angle_error", "_per_day");
  d.a_home_error_rad_per_day = angle_under_any_unit_key(node, "a_home_error", "_per_day");
  d.squareness_ec0xy_rad_per_day = angle_under_any_unit_key(node, "squareness_ec0xy", "_per_day");
  const std::pair<const char*, double*> fixture_rates[] = {
      {"fixture_column_x_offset_mm_per_day", &d.fixture_column_x_offset_mm_per_day},
      {"fixture_pogo_y_offset_mm_per_day", &d.fixture_pogo_y_offset_mm_per_day},
      {"fixture_pogo_z_offset_mm_per_day", &d.fixture_pogo_z_offset_mm_per_day}};
  for (const auto& [key, rate] : fixture_rates) {
    *rate = node[key].length(0.0);
    if (node[key].present() && !machine.fixture) {
      node[key].problem("the machine has no `fixture:` section to drift");
    }
  }
  return d;
}

}  // namespace

SimulatorConfig read_simulator(const Node& node, const MachineConfig& machine) {
  SimulatorConfig config;
  if (!node.map_of({"seed", "trigger_noise_sigma_mm", "plate_thickness_mm", "errors", "fixture",
                    "part_seating_sigma_mm", "tracker", "volumetric", "drift"})) {
    return config;
  }
  // Integers up to 2^53 are exact in a double.
  const double seed = node["seed"].number(1);
  if (seed < 0 || seed > 9007199254740992.0 || seed != std::floor(seed)) {
    node["seed"].problem("must be a non-negative integer up to 2^53");
  } else {
    config.seed = static_cast<std::uint64_t>(seed);
  }
  config.trigger_noise_sigma_mm =
      non_negative(node["trigger_noise_sigma_mm"],
                   node["trigger_noise_sigma_mm"].length(config.trigger_noise_sigma_mm));
  config.plate_thickness_mm = node["plate_thickness_mm"].length(config.plate_thickness_mm);
  if (config.plate_thickness_mm <= 0) node["plate_thickness_mm"].problem("must be positive");
  config.errors = read_errors(node["errors"], machine);
  config.part_seating_sigma_mm =
      non_negative(node["part_seating_sigma_mm"], node["part_seating_sigma_mm"].length(0.0));
  config.fixture = read_fixture_errors(node["fixture"], machine);
  config.tracker = read_tracker(node["tracker"]);
  config.volumetric = read_volumetric(node["volumetric"]);
  if (node["drift"].present()) config.drift = read_drift(node["drift"], machine);
  return config;
}

}  // namespace ncqual::config
