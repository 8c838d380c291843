// Plant and machine configuration (YAML, read with yaml-cpp).
//
// Lengths and angles may be written as a bare number in the unit the key names (`_mm`, `_rad`)
// or as a string with a unit: "0.5 in", "30 arcsec", "12 um". Everything is stored internally in
// mm and rad. Errors name the file, the key and the value.
#pragma once

#include "ncqual/calendar.hpp"
#include "ncqual/fixture.hpp"
#include "ncqual/global_check.hpp"
#include "ncqual/kinematics.hpp"

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>

#include <map>
#include <set>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual {

// Thrown for any problem in a config file; what() names file, key and value.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Tolerance {
  double lower = 0;
  double upper = 0;
  bool contains(double v) const { return v >= lower && v <= upper; }
};

// The fixed monument beside the machine: a ring gauge plate with a hole of known diameter,
// a face parallel to XY and vertical edges a known width apart, on a pedestal.
struct MonumentConfig {
  Eigen::Vector2d hole_center_mm = Eigen::Vector2d::Zero();  // taught X, Y of the hole centre
  double hole_diameter_mm = 0;
  double face_z_mm = 0;        // taught Z of the gauge face (top, parallel to XY)
  double probe_depth_mm = 0;   // depth below the face at which the hole edge is touched
  double gauge_width_mm = 0;   // between the opposite vertical edges (along X)
  double face_offset_mm = 0;   // where on the face (radially from the hole centre, +X) to touch Z
  int hole_touches = 4;        // edge touches for the hole centre (at least 3)
};

// The set points of a loaded part: reference blocks on the fixturing devices (the patent's
// "set point block"), each probed on its top face (Z) and on the two side faces that meet at
// its reference corner (X from -X, Y from -Y). `intended_mm` is that corner as the part program
// expects it: x of the -X face, y of the -Y face, z of the top face (machine frame).
struct SetPointConfig {
  std::string name;  // "primary", "secondary", ...
  Eigen::Vector3d intended_mm = Eigen::Vector3d::Zero();
};
struct PartSetPointsConfig {
  double probe_depth_mm = 5.0;  // side faces touched this far below the top face
  double inset_mm = 10.0;       // touches this far in from the reference corner along each face
  std::vector<SetPointConfig> points;  // empty: the machine has no set-point check
};

struct MachineConfig {
  std::string machine_id;
  std::string description;
  std::string source_path;     // file it was read from
  ProbeGeometry probe;         // nominal
  MonumentConfig monument;     // nominal, as taught
  std::map<std::string, Tolerance> tolerances;  // by metric name
  YAML::Node simulator;        // the `simulator:` section, for the acquisition service only
  YAML::Node budget;           // the `budget:` section (error budget), read by solver::parse_error_budget
  std::optional<FixtureConfig> fixture;  // the `fixture:` section (ncqual/fixture.hpp), if any
  PartSetPointsConfig setpoints;         // the `setpoints:` section
  std::optional<GlobalCheckConfig> global_check;  // the `global_check:` section (monthly, tracker)

  // Tolerance of a metric; throws ConfigError naming the machine and metric when absent.
  const Tolerance& tolerance(const std::string& metric) const;
};

struct PlantConfig {
  std::string plant;
  std::string source_path;
  int domain_id = 0;
  std::string qos_profiles_file;   // absolute, or empty for the built-in default search
  std::string historian_database;  // absolute
  std::vector<MachineConfig> machines;
  // Without a calendar: the checks the scheduler runs for every machine when it starts, in order
  // (scheduler.startup_checks), once.
  std::vector<CheckKind> startup_checks{CheckKind::MonumentPositioning};
  // With one (scheduler.calendar): the plant's shifts and periods; the scheduler runs them.
  std::optional<CalendarConfig> calendar;
  // The scheduler's durable state (scheduler.state_database, absolute): what passed when, what is
  // pending, which check holds a machine, each fixture's next configuration. Default: beside the
  // historian's database, "scheduler.db".
  std::string scheduler_state_database;
  // clock.mode: wall (services run on the wall clock) or simulated: the scheduler owns a simulated
  // clock that starts at clock.start (an ISO 8601 UTC time, the first time; it is then kept in the
  // state database) and jumps to the next thing due whenever nothing is pending; the acquisition
  // and the solver stamp their samples with the time of the request they answer. The demo and
  // the tests run weeks of shifts this way in seconds.
  bool simulated_clock = false;
  std::int64_t simulated_start_ns = 0;

  const MachineConfig* find_machine(const std::string& machine_id) const;
  // The machines named in `list` (ids separated by commas), in that order, for a service that
  // serves some of the plant's machines. Refuses an empty entry, an id the plant does not
  // configure and an id named twice, naming `what` (the flag, e.g. "--machine") and the entry.
  std::vector<MachineConfig> machines_named(const std::string& list, const std::string& what) const;
};

// True when the machine config has what a check of `kind` needs: the global_check: section for the
// tracker checks, the fixture: section for the fixture checks (every machine has a monument and
// set points). The scheduler plans only such checks; `ncqual status` shows only those.
bool has_sections_for(const MachineConfig& machine, CheckKind kind);

// The plant config file to use: `flag_value` (--plant) when given, else NCQUAL_PLANT, else "".
std::string plant_config_path(const std::string& flag_value);

MachineConfig load_machine_config(const std::string& path);
MachineConfig parse_machine_config(const YAML::Node& root, const std::string& source);
PlantConfig load_plant_config(const std::string& path);

// Helpers for reading quantities out of YAML with units, used by the config loaders and by the
// simulator's section. `where` names the file for error messages.
namespace yaml {
// Throws ConfigError "<where>: <key> = '<value>': <why>", the one shape of every config error.
[[noreturn]] void fail(const std::string& where, const std::string& key, const YAML::Node& value,
                       const std::string& why);
// Refuses any key of the mapping `section` not in `known`, so a misspelt key never silently
// takes its default: ConfigError "<where>: <prefix><key> = ...: unknown key; expected one of: ...".
void refuse_unknown_keys(const YAML::Node& section, const std::set<std::string>& known,
                         const std::string& prefix, const std::string& where);
double length_mm(const YAML::Node& node, const std::string& key, const std::string& where);
double length_mm_or(const YAML::Node& node, const std::string& key, double fallback,
                    const std::string& where);
double angle_rad_or(const YAML::Node& node, const std::string& key, double fallback,
                    const std::string& where);
// A 2- or 3-element list of lengths, e.g. [0.01, -0.02, 0] or ["0.001 in", 0, 0].
Eigen::VectorXd lengths_mm_or(const YAML::Node& node, const std::string& key, int size,
                              const Eigen::VectorXd& fallback, const std::string& where);
double number_or(const YAML::Node& node, const std::string& key, double fallback,
                 const std::string& where);
std::string string_or(const YAML::Node& node, const std::string& key, const std::string& fallback,
                      const std::string& where);
}  // namespace yaml

}  // namespace ncqual
