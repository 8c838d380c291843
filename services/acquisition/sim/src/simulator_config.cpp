#include "ncqual/sim/simulator_config.hpp"

#include <cmath>
#include <set>
#include <string>
#include <vector>

namespace ncqual::sim {
namespace {

using yaml::fail;

void refuse_unknown_keys(const YAML::Node& section, const std::set<std::string>& known,
                         const std::string& where) {
  for (const auto& kv : section) {
    const std::string key = kv.first.as<std::string>();
    if (known.count(key)) continue;
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    fail(where, key, kv.second, "unknown key; expected one of: " + list);
  }
}

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

SimulatorErrors parse_errors(const YAML::Node& node, const std::string& where) {
  SimulatorErrors e;
  if (!node || node.IsNull()) return e;
  std::set<std::string> known = {"machine_shift_mm", "monument_shift_mm", "stylus_offset_mm",
                                 "tool_length_error_mm"};
  for (const auto& suffix : kAngleSuffixes) {
    known.insert("c_angle_error" + suffix);
    known.insert("a_home_error" + suffix);
  }
  refuse_unknown_keys(node, known, where);
  e.machine_shift_mm =
      yaml::lengths_mm_or(node, "machine_shift_mm", 3, Eigen::VectorXd::Zero(3), where);
  e.monument_shift_mm =
      yaml::lengths_mm_or(node, "monument_shift_mm", 3, Eigen::VectorXd::Zero(3), where);
  e.stylus_offset_mm =
      yaml::lengths_mm_or(node, "stylus_offset_mm", 2, Eigen::VectorXd::Zero(2), where);
  e.tool_length_error_mm = yaml::length_mm_or(node, "tool_length_error_mm", 0.0, where);
  e.c_angle_error_rad = angle_under_any_unit_key(node, "c_angle_error", where);
  e.a_home_error_rad = angle_under_any_unit_key(node, "a_home_error", where);
  return e;
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

SimulatorConfig parse_simulator_config(const MachineConfig& machine) {
  SimulatorConfig config;
  const YAML::Node& node = machine.simulator;
  if (!node || node.IsNull()) return config;
  const std::string file =
      machine.source_path.empty() ? "machine '" + machine.machine_id + "'" : machine.source_path;
  if (!node.IsMap()) fail(file, "simulator", node, "expected a mapping");

  const std::string where = file + " [simulator]";
  refuse_unknown_keys(node, {"seed", "trigger_noise_sigma_mm", "plate_thickness_mm", "errors"},
                      where);
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
      parse_errors(optional_map(node, "errors", where), file + " [simulator.errors]");
  return config;
}

}  // namespace ncqual::sim
