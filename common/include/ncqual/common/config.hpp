// SPDX-License-Identifier: Apache-2.0
// Plant and machine configuration: the typed result of reading the YAML files.
//
// The configuration layer (common/src/config/) is the only code that reads YAML: every section
// of a plant and its machines is read at load into the structs below (and those of fixture.hpp,
// global_check.hpp, calendar.hpp, config/simulator.hpp, config/budget.hpp), every key name is
// written once there, and unknown keys are refused everywhere.
//
// Lengths and angles may be written as a bare number in the unit the key names (`_mm`, `_rad`)
// or as a string with a unit: "0.5 in", "30 arcsec", "12 um". Everything is stored internally in
// mm and rad. Every problem names the file, the key and the value; a load reports all of them.
#pragma once

#include "ncqual/common/calendar.hpp"
#include "ncqual/common/error.hpp"
#include "ncqual/common/config/budget.hpp"
#include "ncqual/common/config/simulator.hpp"
#include "ncqual/common/fixture.hpp"
#include "ncqual/common/global_check.hpp"
#include "ncqual/common/kinematics.hpp"

#include <Eigen/Core>

#include <map>
#include <set>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual {

// Thrown for problems in config files: what() has every problem, one per line, each
// "<file>: <key> = <value>: <why>"; problems() has them one by one.
class ConfigError : public Error {
 public:
  explicit ConfigError(const std::string& problem) : Error(problem), problems_{problem} {}
  explicit ConfigError(std::vector<std::string> problems);
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  std::vector<std::string> problems_;
};

// A value as the loader resolved it, for `ncqual config check --print`: in mm and rad with what
// was written when that was another unit ("0.762 mm (written 0.03 in)"); `defaulted` when the
// key was absent and the default was taken.
struct ResolvedValue {
  std::string file;
  std::string key;
  std::string value;
  bool defaulted = false;
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
  double face_z_mm = 0;       // taught Z of the gauge face (top, parallel to XY)
  double probe_depth_mm = 0;  // depth below the face at which the hole edge is touched
  double gauge_width_mm = 0;  // between the opposite vertical edges (along X)
  double face_offset_mm = 0;  // where on the face (radially from the hole centre, +X) to touch Z
  int hole_touches = 4;       // edge touches for the hole centre (at least 3)
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

// The `probing:` section: how the machine's control runs the touch plans of the probe checks
// (ncqual/probing/plan.hpp: the simulator runs the same plans) and in which coordinates and units
// it writes them and logs the touches (docs/connecting-a-machine.md). The defaults are the
// simulator's.
inline constexpr double kDefaultProbingClearanceMm = 5.0;
inline constexpr double kDefaultProbingOvertravelMm = 5.0;
struct ProbingConfig {
  double clearance_mm = kDefaultProbingClearanceMm;    // ball to surface at a probing move's start
  double overtravel_mm = kDefaultProbingOvertravelMm;  // searched beyond the expected contact
  double probe_feed_mm_per_min = 100.0;                // the probing moves (G38.2, G31)
  double approach_feed_mm_per_min = 1000.0;            // straight G1 approaches and retracts
  // Pivot Z of the moves between touches (head turns, moves over the next start); none: 50 mm
  // above the highest start of the plan.
  std::optional<double> safe_z_mm;
  // Pivot Z (machine coordinates) where a program starts and where the head turns: the top of the
  // Z travel, so that the first move goes up from any state and the probe clears everything in
  // any orientation; none: the highest start + the tool length + 50 mm.
  std::optional<double> retract_z_mm;
  std::string work_offset = "G54";  // G54 .. G59: the programs' and the logs' coordinates
  // That offset's value in machine coordinates: pivot = program coordinates + work_offset_mm.
  Eigen::Vector3d work_offset_mm = Eigen::Vector3d::Zero();
  bool inch = false;  // units: mm (G21) or inch (G20), of the programs and the logs
  // The axes the control has, of X Y Z W A C (X, Y and Z always): a program commands each of W,
  // A and C it has before its first move, and refuses a check whose plan needs one it lacks.
  std::string axes = "XYZWAC";
  bool has_axis(char axis) const { return axes.find(axis) != std::string::npos; }
};

// The language of a control's probing programs and touch logs (ncqual/probing/program.hpp).
enum class ControlDialect { LinuxCnc, Fanuc, GenericCsv };
std::string_view to_string(ControlDialect dialect);  // "linuxcnc", "fanuc", "generic-csv"
std::optional<ControlDialect> control_dialect_from(std::string_view name);
std::string control_dialect_names();  // "linuxcnc, fanuc, generic-csv"

// The `instrument:` section: what measures the machine's checks for ncqual-acquisition
// (ncqual/acquisition/instruments.hpp; docs/connecting-a-machine.md).
//   simulator      the simulator: section stands in for the machine and its instruments (the
//                  default without an instrument: section; a plant takes such a machine only
//                  when it says `simulated: true`);
//   control-files  for each request the probing program is written into `outbox` (a folder the
//                  control reads: a network share, a DNC folder) and the control's touch log is
//                  awaited in `inbox`; both are moved to `archive` once read. What does not come
//                  back within `timeout_s` is a MeasurementSet with its error.
enum class InstrumentDriver { Simulator, ControlFiles };
std::string_view to_string(InstrumentDriver driver);  // "simulator", "control-files"
struct InstrumentConfig {
  InstrumentDriver driver = InstrumentDriver::Simulator;
  ControlDialect dialect = ControlDialect::LinuxCnc;
  std::string outbox, inbox, archive;  // absolute; archive defaults to <inbox>/archive
  double timeout_s = 3600;             // from the program written to its results read
  bool configured = false;  // the machine file has an instrument: section (else all defaults)
};

struct MachineConfig {
  std::string machine_id;
  std::string description;
  std::string source_path;                      // file it was read from
  ProbeGeometry probe;                          // nominal
  MonumentConfig monument;                      // nominal, as taught
  std::map<std::string, Tolerance> tolerances;  // by metric name
  sim::SimulatorConfig simulator;  // the `simulator:` section (ground truth; acquisition only)
  std::optional<solver::ErrorBudgetConfig> budget;  // the `budget:` section, if any
  std::optional<FixtureConfig>
      fixture;                    // the `fixture:` section (ncqual/common/fixture.hpp), if any
  PartSetPointsConfig setpoints;  // the `setpoints:` section
  ProbingConfig probing;          // the `probing:` section
  InstrumentConfig instrument;    // the `instrument:` section
  std::optional<GlobalCheckConfig> global_check;  // the `global_check:` section (monthly, tracker)

  // Tolerance of a metric; throws ConfigError naming the machine and metric when absent.
  const Tolerance& tolerance(const std::string& metric) const;
};

// The `network:` section of a plant: how its participants find each other. Each way is a
// participant profile of deploy/qos/ncqual-qos.xml; the addresses here, when given, replace the
// profile's (docs/deploy.md).
//   multicast  SPDP multicast on one LAN (the default, and Fast DDS's own);
//   server     clients of the plant's discovery servers (`fastdds discovery -i N`): only unicast,
//              across routed subnets, where multicast is blocked;
//   peers      unicast to a fixed list of hosts (initial peers), no multicast at all.
enum class Discovery { Multicast, Server, Peers };
std::string_view to_string(Discovery discovery);  // "multicast", "server", "peers"
struct NetworkAddress {
  std::string host;  // an IPv4 address or a host name
  int port = 0;      // 0: the default (11811 for a discovery server; the domain's for a peer)
};
// "host" or "host:port" (IPv4 dotted quad or a DNS name, port 1..65535); nullopt when it is not.
std::optional<NetworkAddress> parse_network_address(std::string_view text);
std::string to_string(const NetworkAddress& address);  // "host" or "host:port"
struct NetworkConfig {
  Discovery discovery = Discovery::Multicast;
  // The discovery servers, in the order of their ids: servers[i] runs `fastdds discovery -i i`
  // (its GUID prefix follows from the id, as with ROS_DISCOVERY_SERVER).
  std::vector<NetworkAddress> servers;
  std::vector<NetworkAddress> peers;  // every host a participant of the plant may run on
  // The participant profile (in the QoS profiles file) to run with; empty: discovery's own,
  // ncqual_participant, ncqual_participant_discovery_client or ncqual_participant_peers.
  std::string participant_profile;
  std::string source_path;  // the plant file it was read from, for messages
};

// The `security:` section of a plant: DDS Security from the material deploy/security/ncqual-pki
// makes (docs/deploy.md, "Security"). `dir` empty: not secured.
struct SecurityConfig {
  std::string dir;  // absolute: ca/, governance.p7s, identities/<name>/
  // The identity a process runs as (identities/<identity>/); set per process, not in the plant
  // file: a service's own name, acquisition-<machine>, or --identity / NCQUAL_IDENTITY.
  std::string identity;
};

// The `historian.retention:` section: what `ncqual db thin` deletes as the data ages when it is
// run without --before (docs/export.md, "Retention"; the historian does not run it by itself).
// Off unless configured: every point is kept.
struct RetentionConfig {
  // Delete the raw points (touches, tracker points) of measurement sets older than this many
  // calendar months, keeping every request, set row, result, metric, verdict, cause, correction,
  // compensation and status change (storage::Database::thin_points). Nothing: keep them all.
  std::optional<int> thin_points_after_months;
  // The time before which sets are thinned at `now_ns`: the same UTC date and time so many months
  // earlier (the month's last day when it is shorter: 31 March less one month is 28 or 29
  // February); nothing when off.
  std::optional<std::int64_t> thin_points_before_ns(std::int64_t now_ns) const;
};

// The `web:` section: where the dashboard (ncqual-web, docs/dashboard.md) listens. Read-only
// pages and JSON of the historian, plain HTTP without authentication: by default on the loopback
// address only; another address exposes it to that network (put a proxy with TLS and logins in
// front when it leaves a trusted network).
inline constexpr int kDefaultWebPort = 8470;
struct WebConfig {
  std::string bind = "127.0.0.1";  // an IPv4 address to listen on (0.0.0.0: every interface)
  int port = kDefaultWebPort;      // 1..65535
};

struct PlantConfig {
  std::string plant;
  std::string source_path;
  int domain_id = 0;
  std::string qos_profiles_file;  // absolute, or empty for the built-in default search
  // Without it, a process whose QoS profiles do not load refuses to start: on Fast DDS's
  // defaults nothing is durable, and what is published while a reader is down is lost. True
  // only for experiments (allow_default_qos: true).
  bool allow_default_qos = false;
  // True for a demo or a test bench (simulated: true): only then may a machine be measured by
  // the simulator (is_simulated); without it, a plant with such a machine is refused at load, so
  // that an installed plant never simulates unnoticed.
  bool simulated = false;
  NetworkConfig network;           // the `network:` section
  SecurityConfig security;         // the `security:` section (its identity is left empty)
  std::string historian_database;  // absolute
  RetentionConfig retention;       // historian.retention
  WebConfig web;                   // the `web:` section (the dashboard)
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

// True when the simulator measures the machine (instrument.driver simulator, the default without an
// instrument: section): its sets and results are simulated, not measured.
bool is_simulated(const MachineConfig& machine);

// The plant config file to use: `flag_value` (--plant) when given, else NCQUAL_PLANT, else "".
std::string plant_config_path(const std::string& flag_value);

// Loaders: throw ConfigError with every problem found in the files.
MachineConfig load_machine_config(const std::string& path);
PlantConfig load_plant_config(const std::string& path);
// A machine config from YAML text, as if read from the file `source` (`extends:` is resolved
// relative to it).
MachineConfig parse_machine_config(std::string_view yaml_text, const std::string& source);

// One section from YAML text (the section's own mapping), as the loader reads it under its key
// in the file `source`: for tests and tools that hold a section alone.
CalendarConfig parse_calendar_config(std::string_view yaml_text, const std::string& source);
solver::ErrorBudgetConfig parse_error_budget(std::string_view yaml_text, const std::string& source);
// The `simulator:` key of a machine-file fragment (YAML text whose top level holds `simulator:`),
// read against `machine`'s other sections (its set points and fixture), as the loader reads it.
sim::SimulatorConfig parse_simulator_config(std::string_view machine_yaml_text,
                                            const MachineConfig& machine);

// Everything a load finds, without throwing: for `ncqual config check`.
struct ConfigReport {
  std::vector<std::string> problems;  // all of them, in file order
  std::vector<ResolvedValue> values;  // every value read or defaulted, in file order
  std::optional<PlantConfig> plant;   // when there is no problem
};
ConfigReport check_plant_config(const std::string& path);

}  // namespace ncqual
