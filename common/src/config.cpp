#include "ncqual/config.hpp"

#include "ncqual/clock.hpp"
#include "ncqual/units.hpp"

#include <cstdlib>
#include <filesystem>
#include <set>

namespace ncqual {
namespace fs = std::filesystem;

namespace {

std::string describe(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "(missing)";
  if (node.IsScalar()) return "'" + node.Scalar() + "'";
  return "(not a single value)";
}

using yaml::fail;

double quantity(units::Dimension dim, const YAML::Node& value, const std::string& key,
                std::string_view default_unit, const std::string& where) {
  if (!value.IsScalar()) fail(where, key, value, "expected a number");
  try {
    return units::parse_quantity(dim, value.Scalar(), default_unit);
  } catch (const std::invalid_argument& e) {
    fail(where, key, value, e.what());
  }
}

// The unit a bare number is taken in follows the key's suffix.
std::string_view length_unit_of(const std::string& key) {
  if (key.size() > 3 && key.compare(key.size() - 3, 3, "_in") == 0) return "in";
  if (key.size() > 3 && key.compare(key.size() - 3, 3, "_um") == 0) return "um";
  return "mm";
}
std::string_view angle_unit_of(const std::string& key) {
  if (key.size() > 4 && key.compare(key.size() - 4, 4, "_deg") == 0) return "deg";
  if (key.size() > 7 && key.compare(key.size() - 7, 7, "_arcsec") == 0) return "arcsec";
  if (key.size() > 5 && key.compare(key.size() - 5, 5, "_urad") == 0) return "urad";
  return "rad";
}

std::string resolve(const std::string& base_file, const std::string& path) {
  if (path.empty()) return path;
  fs::path p(path);
  if (p.is_absolute()) return p.lexically_normal().string();
  return (fs::absolute(base_file).parent_path() / p).lexically_normal().string();
}

YAML::Node load_yaml(const std::string& path) {
  if (!fs::exists(path)) throw ConfigError(path + ": file not found");
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw ConfigError(path + ": not valid YAML: " + e.what());
  }
}

bool ends_with(const std::string& s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A tolerance bound is in the unit of its metric, which the metric's name ends in: a length
// metric (_mm) takes any length ("0.001 in"), an angle metric (_arcsec, _deg, _urad, _rad) any
// angle ("2 urad" for an arcsec metric), both converted to the metric's unit; a bare number is
// in the metric's unit. Other metrics take a plain number.
double tolerance_bound(const YAML::Node& v, const std::string& metric, const std::string& key,
                       const std::string& where) {
  if (ends_with(metric, "_mm")) return quantity(units::Dimension::Length, v, key, "mm", where);
  const std::string_view angle_unit = angle_unit_of(metric);
  if (angle_unit != "rad" || ends_with(metric, "_rad")) {
    const double rad = quantity(units::Dimension::Angle, v, key, angle_unit, where);
    return rad / units::parse_quantity(units::Dimension::Angle, "1", angle_unit);
  }
  if (!v.IsScalar()) fail(where, key, v, "expected a number");
  try {
    std::size_t used = 0;
    const double value = std::stod(v.Scalar(), &used);
    if (used == v.Scalar().size()) return value;
  } catch (const std::exception&) {
  }
  fail(where, key, v, "expected a number");
}

// Either a symmetric band "0.025" / "0.001 in" (the half-width), or {lower: .., upper: ..}.
// `metric` is the metric's name, `key` its place in the file for error messages.
Tolerance parse_tolerance(const YAML::Node& node, const std::string& metric,
                          const std::string& key, const std::string& where) {
  Tolerance t;
  if (node.IsScalar()) {
    const double half = tolerance_bound(node, metric, key, where);
    if (!(half > 0)) fail(where, key, node, "a symmetric tolerance must be positive");
    t.lower = -half;
    t.upper = half;
    return t;
  }
  if (node.IsMap()) {
    yaml::refuse_unknown_keys(node, {"lower", "upper"}, key + ".", where);
    auto read = [&](const char* which) {
      const YAML::Node v = node[which];
      if (!v) fail(where, key + "." + which, v, "missing");
      return tolerance_bound(v, metric, key + "." + which, where);
    };
    t.lower = read("lower");
    t.upper = read("upper");
    if (t.lower > t.upper) fail(where, key, node, "lower exceeds upper");
    return t;
  }
  fail(where, key, node, "expected a number or {lower, upper}");
}

PartSetPointsConfig parse_setpoints(const YAML::Node& node, const std::string& where) {
  if (!node.IsMap()) fail(where, "setpoints", node, "expected a mapping");
  yaml::refuse_unknown_keys(node, {"probe_depth_mm", "inset_mm", "points"}, "setpoints.", where);
  PartSetPointsConfig c;
  c.probe_depth_mm = yaml::length_mm_or(node, "probe_depth_mm", c.probe_depth_mm, where);
  c.inset_mm = yaml::length_mm_or(node, "inset_mm", c.inset_mm, where);
  if (!(c.probe_depth_mm > 0)) fail(where, "setpoints.probe_depth_mm", node["probe_depth_mm"], "must be positive");
  if (!(c.inset_mm > 0)) fail(where, "setpoints.inset_mm", node["inset_mm"], "must be positive");
  const YAML::Node points = node["points"];
  if (!points || !points.IsSequence() || points.size() == 0) {
    fail(where, "setpoints.points", points, "expected a non-empty list of {name, intended_mm}");
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string key = "setpoints.points[" + std::to_string(i) + "]";
    const YAML::Node p = points[i];
    if (!p.IsMap() || !p["name"] || !p["intended_mm"]) {
      fail(where, key, p, "expected {name, intended_mm: [x, y, z]}");
    }
    SetPointConfig sp;
    sp.name = yaml::string_or(p, "name", "", where);
    if (sp.name.empty() || sp.name.find_first_of(" :") != std::string::npos) {
      fail(where, key + ".name", p["name"], "must be a non-empty name without spaces or ':'");
    }
    for (const auto& other : c.points) {
      if (other.name == sp.name) fail(where, key + ".name", p["name"], "duplicate set point name");
    }
    sp.intended_mm = yaml::lengths_mm_or(p, "intended_mm", 3, Eigen::VectorXd::Zero(3), where);
    c.points.push_back(sp);
  }
  return c;
}

}  // namespace

namespace yaml {

void fail(const std::string& where, const std::string& key, const YAML::Node& value,
          const std::string& why) {
  throw ConfigError(where + ": " + key + " = " + describe(value) + ": " + why);
}

void refuse_unknown_keys(const YAML::Node& section, const std::set<std::string>& known,
                         const std::string& prefix, const std::string& where) {
  for (const auto& kv : section) {
    const std::string key = kv.first.as<std::string>();
    if (known.count(key)) continue;
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    fail(where, prefix + key, kv.second, "unknown key; expected one of: " + list);
  }
}

double length_mm(const YAML::Node& node, const std::string& key, const std::string& where) {
  const YAML::Node v = node[key];
  if (!v) fail(where, key, v, "required");
  return quantity(units::Dimension::Length, v, key, length_unit_of(key), where);
}

double length_mm_or(const YAML::Node& node, const std::string& key, double fallback,
                    const std::string& where) {
  const YAML::Node v = node[key];
  if (!v) return fallback;
  return quantity(units::Dimension::Length, v, key, length_unit_of(key), where);
}

double angle_rad_or(const YAML::Node& node, const std::string& key, double fallback,
                    const std::string& where) {
  const YAML::Node v = node[key];
  if (!v) return fallback;
  return quantity(units::Dimension::Angle, v, key, angle_unit_of(key), where);
}

Eigen::VectorXd lengths_mm_or(const YAML::Node& node, const std::string& key, int size,
                              const Eigen::VectorXd& fallback, const std::string& where) {
  const YAML::Node v = node[key];
  if (!v) return fallback;
  if (!v.IsSequence() || static_cast<int>(v.size()) != size) {
    fail(where, key, v, "expected a list of " + std::to_string(size) + " lengths");
  }
  Eigen::VectorXd out(size);
  for (int i = 0; i < size; ++i) {
    out[i] = quantity(units::Dimension::Length, v[i], key + "[" + std::to_string(i) + "]",
                      length_unit_of(key), where);
  }
  return out;
}

double number_or(const YAML::Node& node, const std::string& key, double fallback,
                 const std::string& where) {
  const YAML::Node v = node[key];
  if (!v) return fallback;
  if (!v.IsScalar()) fail(where, key, v, "expected a number");
  try {
    std::size_t used = 0;
    const double d = std::stod(v.Scalar(), &used);
    if (used != v.Scalar().size()) fail(where, key, v, "expected a number");
    return d;
  } catch (const std::logic_error&) {
    fail(where, key, v, "expected a number");
  }
}

std::string string_or(const YAML::Node& node, const std::string& key, const std::string& fallback,
                      const std::string& where) {
  const YAML::Node v = node[key];
  if (!v) return fallback;
  if (!v.IsScalar()) fail(where, key, v, "expected a string");
  return v.Scalar();
}

}  // namespace yaml

const Tolerance& MachineConfig::tolerance(const std::string& metric) const {
  const auto it = tolerances.find(metric);
  if (it == tolerances.end()) {
    throw ConfigError(source_path + ": machine '" + machine_id + "' has no tolerance for metric '" +
                      metric + "'");
  }
  return it->second;
}

const MachineConfig* PlantConfig::find_machine(const std::string& machine_id) const {
  for (const auto& m : machines) {
    if (m.machine_id == machine_id) return &m;
  }
  return nullptr;
}

std::vector<MachineConfig> PlantConfig::machines_named(const std::string& list,
                                                      const std::string& what) const {
  std::vector<MachineConfig> out;
  std::set<std::string> seen;
  std::size_t from = 0;
  while (from <= list.size()) {
    const std::size_t comma = std::min(list.find(',', from), list.size());
    const std::string id = list.substr(from, comma - from);
    from = comma + 1;
    if (id.empty()) throw ConfigError(what + " '" + list + "': an empty machine id");
    const MachineConfig* m = find_machine(id);
    if (!m) throw ConfigError(what + " '" + id + "' is not configured in " + source_path);
    if (!seen.insert(id).second) throw ConfigError(what + " '" + id + "' is named twice");
    out.push_back(*m);
  }
  return out;
}

MachineConfig parse_machine_config(const YAML::Node& root, const std::string& where) {
  if (!root.IsMap()) throw ConfigError(where + ": expected a mapping at the top level");
  MachineConfig m;
  m.source_path = where;
  m.machine_id = yaml::string_or(root, "machine_id", "", where);
  if (m.machine_id.empty()) fail(where, "machine_id", root["machine_id"], "required");
  for (char ch : m.machine_id) {
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_' || ch == '.')) {
      fail(where, "machine_id", root["machine_id"],
           "use letters, digits, '-', '_' and '.' only");
    }
  }
  m.description = yaml::string_or(root, "description", "", where);

  const YAML::Node probe = root["probe"];
  if (!probe) fail(where, "probe", probe, "required section");
  m.probe.tool_length_mm = yaml::length_mm(probe, "tool_length_mm", where);
  m.probe.ball_radius_mm = yaml::length_mm(probe, "ball_radius_mm", where);
  if (m.probe.tool_length_mm <= 0) fail(where, "probe.tool_length_mm", probe["tool_length_mm"], "must be positive");
  if (m.probe.ball_radius_mm < 0) fail(where, "probe.ball_radius_mm", probe["ball_radius_mm"], "must not be negative");

  const YAML::Node mon = root["monument"];
  if (!mon) fail(where, "monument", mon, "required section");
  m.monument.hole_center_mm =
      yaml::lengths_mm_or(mon, "hole_center_mm", 2, Eigen::VectorXd::Zero(2), where);
  if (!mon["hole_center_mm"]) fail(where, "monument.hole_center_mm", mon["hole_center_mm"], "required");
  m.monument.hole_diameter_mm = yaml::length_mm(mon, "hole_diameter_mm", where);
  m.monument.face_z_mm = yaml::length_mm(mon, "face_z_mm", where);
  m.monument.probe_depth_mm = yaml::length_mm_or(mon, "probe_depth_mm", 5.0, where);
  m.monument.gauge_width_mm = yaml::length_mm_or(mon, "gauge_width_mm", 0.0, where);
  m.monument.face_offset_mm = yaml::length_mm_or(
      mon, "face_offset_mm", m.monument.hole_diameter_mm / 2 + 10.0, where);
  const double touches = yaml::number_or(mon, "hole_touches", 4, where);
  if (touches < 3 || touches > 64 || touches != static_cast<int>(touches)) {
    fail(where, "monument.hole_touches", mon["hole_touches"], "must be an integer from 3 to 64");
  }
  m.monument.hole_touches = static_cast<int>(touches);
  if (m.monument.hole_diameter_mm <= 2 * m.probe.ball_radius_mm) {
    fail(where, "monument.hole_diameter_mm", mon["hole_diameter_mm"],
         "must exceed the stylus ball diameter");
  }

  const YAML::Node tol = root["tolerances"];
  if (tol) {
    if (!tol.IsMap()) fail(where, "tolerances", tol, "expected a mapping of metric: tolerance");
    for (const auto& kv : tol) {
      const std::string key = kv.first.as<std::string>();
      m.tolerances[key] = parse_tolerance(kv.second, key, "tolerances." + key, where);
    }
  }
  // Assigning a missing node would throw in yaml-cpp: copy only a present section.
  if (const YAML::Node sim = root["simulator"]) m.simulator = YAML::Clone(sim);
  if (const YAML::Node budget = root["budget"]) m.budget = YAML::Clone(budget);
  if (const YAML::Node sp = root["setpoints"]; sp && !sp.IsNull()) {
    m.setpoints = parse_setpoints(sp, where);
  }
  if (const YAML::Node fixture = root["fixture"]; fixture && !fixture.IsNull()) {
    m.fixture = parse_fixture_config(fixture, where);
  }
  if (const YAML::Node gc = root["global_check"]; gc && !gc.IsNull()) {
    m.global_check = parse_global_check_config(gc, where);
  }
  return m;
}

std::string plant_config_path(const std::string& flag_value) {
  if (!flag_value.empty()) return flag_value;
  if (const char* env = std::getenv("NCQUAL_PLANT"); env && *env) return env;
  return "";
}

namespace {

// `over` laid over `base`: mappings merge key by key (recursively), anything else in `over`
// replaces what `base` has.
YAML::Node overlay(const YAML::Node& base, const YAML::Node& over) {
  if (!base.IsMap() || !over.IsMap()) return YAML::Clone(over);
  YAML::Node merged = YAML::Clone(base);
  for (const auto& kv : over) {
    const std::string key = kv.first.as<std::string>();
    merged[key] = merged[key] ? overlay(merged[key], kv.second) : YAML::Clone(kv.second);
  }
  return merged;
}

// A machine file may start from another: `extends: FILE` (relative to it) gives every key it
// does not set itself; nested mappings merge. Scenarios use it to change only the simulator's
// errors of a plant's machine. Chains are followed; a cycle is an error.
YAML::Node load_machine_yaml(const std::string& path, std::vector<std::string>& seen) {
  const std::string canonical = fs::absolute(path).lexically_normal().string();
  for (const auto& s : seen) {
    if (s == canonical) throw ConfigError(path + ": extends: files extend each other in a cycle");
  }
  seen.push_back(canonical);
  YAML::Node root = load_yaml(path);
  if (!root.IsMap()) throw ConfigError(path + ": expected a mapping at the top level");
  const YAML::Node base_name = root["extends"];
  if (!base_name) return root;
  if (!base_name.IsScalar() || base_name.Scalar().empty()) {
    fail(path, "extends", base_name, "expected the path of a machine config file");
  }
  const std::string base_path = resolve(path, base_name.Scalar());
  if (!fs::exists(base_path)) fail(path, "extends", base_name, "file not found: " + base_path);
  YAML::Node own = YAML::Clone(root);
  own.remove("extends");
  return overlay(load_machine_yaml(base_path, seen), own);
}

}  // namespace

MachineConfig load_machine_config(const std::string& path) {
  std::vector<std::string> seen;
  return parse_machine_config(load_machine_yaml(path, seen), path);
}

bool has_sections_for(const MachineConfig& machine, CheckKind kind) {
  if (is_tracker_check(kind)) return machine.global_check.has_value();
  if (kind == CheckKind::FixturePreCalibration || kind == CheckKind::FixturePostCalibration) {
    return machine.fixture.has_value();
  }
  return true;
}

PlantConfig load_plant_config(const std::string& path) {
  const YAML::Node root = load_yaml(path);
  if (!root.IsMap()) throw ConfigError(path + ": expected a mapping at the top level");
  PlantConfig p;
  p.source_path = fs::absolute(path).lexically_normal().string();
  p.plant = yaml::string_or(root, "plant", "plant", path);
  const double domain = yaml::number_or(root, "domain_id", 0, path);
  if (domain < 0 || domain > 232 || domain != static_cast<int>(domain)) {
    fail(path, "domain_id", root["domain_id"], "must be an integer from 0 to 232");
  }
  p.domain_id = static_cast<int>(domain);
  p.qos_profiles_file = resolve(path, yaml::string_or(root, "qos_profiles", "", path));
  const YAML::Node hist = root["historian"];
  p.historian_database =
      resolve(path, hist ? yaml::string_or(hist, "database", "historian.db", path) : "historian.db");
  p.scheduler_state_database =
      (fs::path(p.historian_database).parent_path() / "scheduler.db").string();
  if (const YAML::Node sched = root["scheduler"]) {
    if (!sched.IsMap()) fail(path, "scheduler", sched, "expected a mapping");
    yaml::refuse_unknown_keys(sched, {"startup_checks", "calendar", "state_database"}, "scheduler.",
                              path);
    if (const YAML::Node cal = sched["calendar"]; cal && !cal.IsNull()) {
      p.calendar = parse_calendar_config(cal, path);
    }
    if (sched["state_database"]) {
      p.scheduler_state_database =
          resolve(path, yaml::string_or(sched, "state_database", "", path));
    }
    if (const YAML::Node checks = sched["startup_checks"]) {
      if (!checks.IsSequence()) fail(path, "scheduler.startup_checks", checks, "expected a list of check kinds");
      p.startup_checks.clear();
      for (std::size_t i = 0; i < checks.size(); ++i) {
        const auto kind = checks[i].IsScalar() ? parse_check_kind(checks[i].Scalar()) : std::nullopt;
        if (!kind) {
          fail(path, "scheduler.startup_checks[" + std::to_string(i) + "]", checks[i],
               "not a check kind (e.g. monument_positioning)");
        }
        p.startup_checks.push_back(*kind);
      }
    }
  }
  if (const YAML::Node clock = root["clock"]) {
    if (!clock.IsMap()) fail(path, "clock", clock, "expected {mode: wall | simulated, start}");
    yaml::refuse_unknown_keys(clock, {"mode", "start"}, "clock.", path);
    const std::string mode = yaml::string_or(clock, "mode", "wall", path);
    if (mode != "wall" && mode != "simulated") {
      fail(path, "clock.mode", clock["mode"], "expected wall or simulated");
    }
    p.simulated_clock = mode == "simulated";
    if (p.simulated_clock) {
      if (!clock["start"]) fail(path, "clock.start", clock, "missing: the simulated clock's start (ISO 8601 UTC)");
      const auto start = parse_iso8601(yaml::string_or(clock, "start", "", path));
      if (!start) {
        fail(path, "clock.start", clock["start"], "expected an ISO 8601 UTC time, e.g. 2026-01-05T00:00:00Z");
      }
      p.simulated_start_ns = *start;
    }
  }
  const YAML::Node machines = root["machines"];
  if (machines) {
    if (!machines.IsSequence()) fail(path, "machines", machines, "expected a list of machine files");
    for (std::size_t i = 0; i < machines.size(); ++i) {
      const YAML::Node entry = machines[i];
      if (!entry.IsScalar()) {
        fail(path, "machines[" + std::to_string(i) + "]", entry, "expected a file name");
      }
      MachineConfig m = load_machine_config(resolve(path, entry.Scalar()));
      if (p.find_machine(m.machine_id)) {
        fail(path, "machines[" + std::to_string(i) + "]", entry,
             "machine_id '" + m.machine_id + "' is configured twice");
      }
      p.machines.push_back(std::move(m));
    }
  }
  return p;
}

}  // namespace ncqual
