// SPDX-License-Identifier: Apache-2.0
// The plant and machine files: the top level of the configuration layer. It reads the files,
// resolves `extends:` and relative paths, reads every section into its typed struct (the readers
// of the other files of this folder) and reports every problem at once.
#include "node.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/common/text.hpp"

#include <date/date.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <set>

namespace ncqual {
namespace fs = std::filesystem;

namespace {

std::string join_lines(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += (out.empty() ? "" : "\n") + l;
  return out;
}

}  // namespace

ConfigError::ConfigError(std::vector<std::string> problems)
    : Error(join_lines(problems)), problems_(std::move(problems)) {}

namespace config {
namespace {

std::string resolve(const std::string& base_file, const std::string& path) {
  if (path.empty()) return path;
  fs::path p(path);
  if (p.is_absolute()) return p.lexically_normal().string();
  return (fs::absolute(base_file).parent_path() / p).lexically_normal().string();
}

// A tolerance bound is in the unit of its metric, which the metric's name ends in: a length
// metric (_mm) takes any length ("0.001 in"), an angle metric (_arcsec, _deg, _urad, _rad) any
// angle ("2 urad" for an arcsec metric), both converted to the metric's unit; a bare number is
// in the metric's unit. Other metrics take a plain number.
std::optional<double> tolerance_bound(const Node& v, const std::string& metric) {
  if (key_ends_with(metric, "_mm")) return v.quantity(units::Dimension::Length, "mm");
  const std::string_view angle_unit = angle_unit_of(metric);
  if (angle_unit != "rad" || key_ends_with(metric, "_rad")) {
    const auto rad = v.quantity(units::Dimension::Angle, angle_unit);
    if (!rad) return std::nullopt;
    return *rad / units::parse_quantity(units::Dimension::Angle, "1", angle_unit);
  }
  return v.number();
}

// Either a symmetric band "0.025" / "0.001 in" (the half-width), or {lower: .., upper: ..}.
std::optional<Tolerance> read_tolerance(const Node& node, const std::string& metric) {
  Tolerance t;
  if (node.is_scalar()) {
    const auto half = tolerance_bound(node, metric);
    if (!half) return std::nullopt;
    if (!(*half > 0)) {
      node.problem("a symmetric tolerance must be positive");
      return std::nullopt;
    }
    t.lower = -*half;
    t.upper = *half;
    return t;
  }
  if (!node.is_map()) {
    node.problem("expected a number or {lower, upper}");
    return std::nullopt;
  }
  node.map_of({"lower", "upper"});
  auto read = [&](const char* which) -> std::optional<double> {
    const Node v = node[which];
    if (!v.present()) {
      v.problem("missing");
      return std::nullopt;
    }
    return tolerance_bound(v, metric);
  };
  const auto lower = read("lower"), upper = read("upper");
  if (!lower || !upper) return std::nullopt;
  t.lower = *lower;
  t.upper = *upper;
  if (t.lower > t.upper) node.problem("lower exceeds upper");
  return t;
}

// "; did you mean 'center_dx_mm'?" for a key a few edits away from a known one, else "".
std::string closest_tolerance_key(const std::string& key) {
  std::vector<std::string_view> known;
  for (const auto& row : check_kinds()) {
    known.insert(known.end(), row.tolerances.begin(), row.tolerances.end());
  }
  const auto best = closest_word(key, known);
  return best ? "; did you mean '" + std::string(*best) + "'?" : "";
}

PartSetPointsConfig read_setpoints(const Node& node) {
  PartSetPointsConfig c;
  if (!node.map_of({"probe_depth_mm", "inset_mm", "points"})) return c;
  c.probe_depth_mm = node["probe_depth_mm"].length(c.probe_depth_mm);
  c.inset_mm = node["inset_mm"].length(c.inset_mm);
  if (!(c.probe_depth_mm > 0)) node["probe_depth_mm"].problem("must be positive");
  if (!(c.inset_mm > 0)) node["inset_mm"].problem("must be positive");
  const Node points = node["points"];
  if (!points.is_list() || points.size() == 0) {
    points.problem("expected a non-empty list of {name, intended_mm}");
    return c;
  }
  for (const Node& p : points.items()) {
    if (!p.is_map() || !p["name"].present() || !p["intended_mm"].present()) {
      p.problem("expected {name, intended_mm: [x, y, z]}");
      continue;
    }
    p.map_of({"name", "intended_mm"});
    SetPointConfig sp;
    sp.name = p["name"].text("");
    if (sp.name.empty() || sp.name.find_first_of(" :") != std::string::npos) {
      p["name"].problem("must be a non-empty name without spaces or ':'");
    }
    for (const auto& other : c.points) {
      if (other.name == sp.name) p["name"].problem("duplicate set point name");
    }
    sp.intended_mm = p["intended_mm"].lengths(3, Eigen::VectorXd::Zero(3));
    c.points.push_back(sp);
  }
  return c;
}

ProbingConfig read_probing(const Node& node) {
  ProbingConfig c;
  if (!node.map_of({"clearance_mm", "overtravel_mm", "probe_feed_mm_per_min",
                    "approach_feed_mm_per_min", "safe_z_mm", "work_offset", "work_offset_mm",
                    "units", "axes", "retract_z_mm"})) {
    return c;
  }
  c.clearance_mm = node["clearance_mm"].length(c.clearance_mm);
  c.overtravel_mm = node["overtravel_mm"].length(c.overtravel_mm);
  if (!(c.clearance_mm > 0)) node["clearance_mm"].problem("must be positive");
  if (!(c.overtravel_mm > 0)) node["overtravel_mm"].problem("must be positive");
  c.probe_feed_mm_per_min = node["probe_feed_mm_per_min"].number(c.probe_feed_mm_per_min);
  c.approach_feed_mm_per_min = node["approach_feed_mm_per_min"].number(c.approach_feed_mm_per_min);
  if (!(c.probe_feed_mm_per_min > 0)) node["probe_feed_mm_per_min"].problem("must be positive");
  if (!(c.approach_feed_mm_per_min > 0)) {
    node["approach_feed_mm_per_min"].problem("must be positive");
  }
  if (node["safe_z_mm"].present()) c.safe_z_mm = node["safe_z_mm"].length();
  if (node["retract_z_mm"].present()) c.retract_z_mm = node["retract_z_mm"].length();
  c.work_offset = node["work_offset"].text(c.work_offset);
  if (c.work_offset.size() != 3 || c.work_offset.compare(0, 2, "G5") != 0 ||
      c.work_offset[2] < '4' || c.work_offset[2] > '9') {
    node["work_offset"].problem("expected one of G54, G55, G56, G57, G58, G59");
  }
  c.work_offset_mm = node["work_offset_mm"].lengths(3, Eigen::VectorXd::Zero(3));
  const std::string units = node["units"].text("mm");
  if (units != "mm" && units != "inch") node["units"].problem("expected mm or inch");
  c.inch = units == "inch";
  const std::string axes = node["axes"].text(c.axes);
  std::string known = "XYZWAC";
  bool valid = axes.size() >= 3;
  for (char a : axes) {
    const auto at = known.find(a);
    valid = valid && at != std::string::npos;
    if (at != std::string::npos) known[at] = '.';  // each once
  }
  if (!valid || known.compare(0, 3, "...") != 0) {
    node["axes"].problem("expected X, Y and Z and any of W, A and C, each once (e.g. XYZAC)");
  } else {
    c.axes = axes;
  }
  return c;
}

InstrumentConfig read_instrument(const Node& node) {
  InstrumentConfig c;
  if (!node.map_of({"driver", "dialect", "outbox", "inbox", "archive", "timeout_s"})) return c;
  c.configured = true;
  const std::string driver = node["driver"].text(std::string(to_string(c.driver)));
  if (driver == to_string(InstrumentDriver::ControlFiles)) {
    c.driver = InstrumentDriver::ControlFiles;
  } else if (driver != to_string(InstrumentDriver::Simulator)) {
    node["driver"].problem("expected " + std::string(to_string(InstrumentDriver::Simulator)) +
                           " or " + std::string(to_string(InstrumentDriver::ControlFiles)));
  }
  const std::string dialect = node["dialect"].text("linuxcnc");
  if (const auto d = control_dialect_from(dialect)) {
    c.dialect = *d;
  } else {
    node["dialect"].problem("expected one of " + control_dialect_names());
  }
  c.timeout_s = node["timeout_s"].number(c.timeout_s);
  if (!(c.timeout_s > 0)) node["timeout_s"].problem("must be positive");
  if (c.driver != InstrumentDriver::ControlFiles) {
    for (const char* key : {"outbox", "inbox", "archive"}) {
      if (node[key].present()) node[key].problem("only the control-files driver reads it");
    }
    return c;
  }
  // Folders relative to the machine file, so a plant's config tree can be moved as a whole.
  c.outbox = resolve(node.file(), node["outbox"].required_text().value_or(""));
  c.inbox = resolve(node.file(), node["inbox"].required_text().value_or(""));
  c.archive = node["archive"].present()
                  ? resolve(node.file(), node["archive"].text(""))
                  : (c.inbox.empty() ? "" : (fs::path(c.inbox) / "archive").string());
  if (!c.outbox.empty() && c.outbox == c.inbox) {
    node["inbox"].problem("must not be the outbox: programs and results need folders of their own");
  }
  return c;
}

MachineConfig read_machine(const Node& root) {
  MachineConfig m;
  m.source_path = root.file();
  if (!root.present()) return m;  // the file's problem is recorded already
  if (!root.is_map()) {
    root.problem("expected a mapping at the top level");
    return m;
  }
  root.map_of({"machine_id", "description", "probe", "monument", "tolerances", "simulator",
               "budget", "setpoints", "fixture", "global_check", "probing", "instrument"});
  const Node id = root["machine_id"];
  m.machine_id = id.required_text().value_or("");
  if (id.present() && !valid_id(m.machine_id)) {
    id.problem(m.machine_id.empty() ? "required" : "use letters, digits, '-', '_' and '.' only");
  }
  m.description = root["description"].text("");

  const Node probe = root["probe"];
  if (probe.required_map_of({"tool_length_mm", "ball_radius_mm"})) {
    m.probe.tool_length_mm = probe["tool_length_mm"].required_length().value_or(0);
    m.probe.ball_radius_mm = probe["ball_radius_mm"].required_length().value_or(0);
    if (m.probe.tool_length_mm <= 0) probe["tool_length_mm"].problem("must be positive");
    if (m.probe.ball_radius_mm < 0) probe["ball_radius_mm"].problem("must not be negative");
  }

  const Node mon = root["monument"];
  if (mon.required_map_of({"hole_center_mm", "hole_diameter_mm", "face_z_mm", "probe_depth_mm",
                           "gauge_width_mm", "face_offset_mm", "hole_touches"})) {
    mon["hole_center_mm"].require();
    m.monument.hole_center_mm = mon["hole_center_mm"].lengths(2, Eigen::VectorXd::Zero(2));
    m.monument.hole_diameter_mm = mon["hole_diameter_mm"].required_length().value_or(0);
    m.monument.face_z_mm = mon["face_z_mm"].required_length().value_or(0);
    m.monument.probe_depth_mm = mon["probe_depth_mm"].length(5.0);
    m.monument.gauge_width_mm = mon["gauge_width_mm"].length(0.0);
    m.monument.face_offset_mm =
        mon["face_offset_mm"].length(m.monument.hole_diameter_mm / 2 + 10.0);
    m.monument.hole_touches = mon["hole_touches"].integer(3, 64, 4);
    if (m.monument.hole_diameter_mm <= 2 * m.probe.ball_radius_mm) {
      mon["hole_diameter_mm"].problem("must exceed the stylus ball diameter");
    }
  }

  const Node tol = root["tolerances"];
  if (tol.present() && !tol.is_map()) tol.problem("expected a mapping of metric: tolerance");
  for (const auto& [metric, node] : tol.entries()) {
    if (!is_tolerance_key(metric)) {
      node.problem("no check reads this tolerance" + closest_tolerance_key(metric) +
                   " (each check kind's tolerance keys: docs/architecture.md)");
      continue;
    }
    if (const auto t = read_tolerance(node, metric)) m.tolerances[metric] = *t;
  }
  if (root["setpoints"].present()) m.setpoints = read_setpoints(root["setpoints"]);
  if (root["probing"].present()) m.probing = read_probing(root["probing"]);
  if (root["instrument"].present()) m.instrument = read_instrument(root["instrument"]);
  if (root["fixture"].present()) m.fixture = read_fixture(root["fixture"]);
  if (root["global_check"].present()) m.global_check = read_global_check(root["global_check"]);
  if (root["budget"].present()) m.budget = read_budget(root["budget"]);
  // Last: the simulator's errors name the set points and pogos of the sections above.
  m.simulator = read_simulator(root["simulator"], m);
  return m;
}

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
// errors of a plant's machine. Chains are followed; a cycle is an error. `text`, when given,
// stands for the contents of `path`.
YAML::Node machine_yaml(const std::string& path, std::vector<std::string>& seen,
                        Diagnostics& diagnostics, std::optional<std::string_view> text = {}) {
  const std::string canonical = fs::absolute(path).lexically_normal().string();
  for (const auto& s : seen) {
    if (s == canonical) {
      diagnostics.file_problem(path, "extends: files extend each other in a cycle");
      return YAML::Node();
    }
  }
  seen.push_back(canonical);
  Node root = text ? parse_text(*text, path, diagnostics) : load_file(path, diagnostics);
  if (!root.present()) return YAML::Node();
  if (!root.is_map()) {
    root.problem("expected a mapping at the top level");
    return YAML::Node();
  }
  const Node base_name = root["extends"];
  YAML::Node own = YAML::Clone(root.yaml());
  if (!base_name.present()) return own;
  own.remove("extends");
  if (!base_name.is_scalar() || base_name.scalar().empty()) {
    base_name.problem("expected the path of a machine config file");
    return own;
  }
  const std::string base_path = resolve(path, base_name.scalar());
  if (!fs::exists(base_path)) {
    base_name.problem("file not found: " + base_path);
    return own;
  }
  return overlay(machine_yaml(base_path, seen, diagnostics), own);
}

MachineConfig read_machine_file(const std::string& path, Diagnostics& diagnostics,
                                std::optional<std::string_view> text = {}) {
  std::vector<std::string> seen;
  const YAML::Node merged = machine_yaml(path, seen, diagnostics, text);
  if (!merged.IsDefined() || merged.IsNull()) {
    MachineConfig m;
    m.source_path = path;
    return m;
  }
  return read_machine(Node(merged, path, diagnostics));
}

// The `network:` section. Addresses are checked for their shape here; a host name is resolved
// when a participant starts (ncqual/dds/participant.hpp).
NetworkConfig read_network(const Node& node) {
  NetworkConfig n;
  if (!node.map_of({"discovery", "servers", "peers", "participant_profile"})) return n;
  const Node discovery = node["discovery"];
  const std::string mode = discovery.text(std::string(to_string(Discovery::Multicast)));
  bool known = false;
  for (Discovery d : {Discovery::Multicast, Discovery::Server, Discovery::Peers}) {
    if (mode == to_string(d)) {
      n.discovery = d;
      known = true;
    }
  }
  if (!known) discovery.problem("expected multicast, server or peers");
  n.participant_profile = node["participant_profile"].text("");
  const auto addresses = [](const Node& list, std::vector<NetworkAddress>& out) {
    if (!list.present()) return;
    if (!list.is_list()) {
      list.problem("expected a list of addresses, host or host:port");
      return;
    }
    for (const Node& item : list.items()) {
      const auto address = item.is_scalar() ? parse_network_address(item.scalar()) : std::nullopt;
      if (!address) {
        item.problem("expected an address: an IPv4 address or host name, and :port (1..65535)");
        continue;
      }
      out.push_back(*address);
    }
  };
  addresses(node["servers"], n.servers);
  addresses(node["peers"], n.peers);
  // Each way needs its addresses, unless a profile of the plant's own carries them.
  if (n.participant_profile.empty()) {
    if (n.discovery == Discovery::Server && !node["servers"].present()) {
      node["servers"].problem(
          "required with discovery: server: the discovery servers' addresses, in id order");
    }
    if (n.discovery == Discovery::Peers && !node["peers"].present()) {
      node["peers"].problem("required with discovery: peers: the addresses of the plant's hosts");
    }
  }
  if (n.discovery != Discovery::Server && node["servers"].present()) {
    node["servers"].problem("only with discovery: server");
  }
  if (n.discovery != Discovery::Peers && node["peers"].present()) {
    node["peers"].problem("only with discovery: peers");
  }
  return n;
}

// The `web:` section (the dashboard, ncqual-web): the address it listens on, an IPv4 address
// (a host name would listen wherever it resolves to today), and the port.
WebConfig read_web(const Node& node) {
  WebConfig w;
  if (!node.map_of({"bind", "port"})) return w;
  w.bind = node["bind"].text(w.bind);
  const auto address = parse_network_address(w.bind);
  if (!address || address->port != 0 ||
      w.bind.find_first_not_of("0123456789.") != std::string::npos) {
    node["bind"].problem("expected an IPv4 address to listen on, e.g. 127.0.0.1 or 0.0.0.0");
  }
  w.port = node["port"].integer(1, 65535, w.port);
  return w;
}

// A plant that does not say `simulated: true` takes no machine the simulator measures: an installed
// plant must not hand out simulated results as measured ones. The problem is the plant's entry of
// the machine (naming the machine's file and id); a machine without an id or whose instrument:
// section has a problem of its own is not judged again here.
void refuse_simulated(const Node& entry, const MachineConfig& m, const Diagnostics& diagnostics) {
  if (!is_simulated(m) || m.machine_id.empty() ||
      diagnostics.has_problem_under(m.source_path, "instrument")) {
    return;
  }
  const std::string what =
      m.instrument.configured ? "says instrument.driver = simulator" : "has no instrument: section";
  entry.problem("machine '" + m.machine_id + "' (" + m.source_path + ") " + what +
                ", so the simulator would measure it and its results would be simulated; give it "
                "an instrument: section (docs/connecting-a-machine.md) or, for a demo or test "
                "bench, say `simulated: true` in the plant");
}

std::optional<PlantConfig> read_plant(const std::string& path, Diagnostics& diagnostics) {
  const Node root = load_file(path, diagnostics);
  if (!root.present()) return std::nullopt;
  if (!root.is_map()) {
    root.problem("expected a mapping at the top level");
    return std::nullopt;
  }
  root.map_of({"plant", "domain_id", "qos_profiles", "allow_default_qos", "simulated", "network",
               "security", "historian", "scheduler", "clock", "machines", "web"});
  PlantConfig p;
  p.source_path = fs::absolute(path).lexically_normal().string();
  p.plant = root["plant"].text("plant");
  p.domain_id = root["domain_id"].integer(0, 232, 0);
  p.qos_profiles_file = resolve(path, root["qos_profiles"].text(""));
  p.allow_default_qos = root["allow_default_qos"].flag().value_or(false);
  const Node simulated = root["simulated"];
  p.simulated = simulated.flag(false);
  // A misspelt value is its own problem, not one more for every simulated machine.
  const bool refuse_simulators =
      !p.simulated && !diagnostics.has_problem_under(simulated.file(), simulated.path());
  p.network = read_network(root["network"]);
  p.network.source_path = p.source_path;
  if (const Node security = root["security"]; security.map_of({"dir"})) {
    p.security.dir = resolve(path, security["dir"].required_text().value_or(""));
  }
  const Node hist = root["historian"];
  hist.map_of({"database", "retention"});
  p.historian_database = resolve(path, hist["database"].text("historian.db"));
  if (const Node retention = hist["retention"]; retention.map_of({"thin_points_after_months"})) {
    // At least a month: the points of a check just made are what its result was judged on.
    p.retention.thin_points_after_months = retention["thin_points_after_months"].integer(1, 1200);
  }
  p.web = read_web(root["web"]);
  p.scheduler_state_database =
      (fs::path(p.historian_database).parent_path() / "scheduler.db").string();
  if (const Node sched = root["scheduler"];
      sched.map_of({"startup_checks", "calendar", "state_database"})) {
    if (sched["calendar"].present()) p.calendar = read_calendar(sched["calendar"]);
    if (sched["state_database"].present()) {
      p.scheduler_state_database = resolve(path, sched["state_database"].text(""));
    }
    if (const Node checks = sched["startup_checks"]; checks.present()) {
      if (!checks.is_list()) checks.problem("expected a list of check kinds");
      p.startup_checks.clear();
      for (const Node& item : checks.items()) {
        const auto kind = item.is_scalar() ? parse_check_kind(item.scalar()) : std::nullopt;
        if (!kind) {
          item.problem("not a check kind (e.g. monument_positioning)");
          continue;
        }
        p.startup_checks.push_back(*kind);
      }
    }
  }
  if (const Node clock = root["clock"]; clock.present()) {
    if (!clock.is_map()) {
      clock.problem("expected {mode: wall | simulated, start}");
    } else {
      clock.map_of({"mode", "start"});
      const std::string mode = clock["mode"].text("wall");
      if (mode != "wall" && mode != "simulated")
        clock["mode"].problem("expected wall or simulated");
      p.simulated_clock = mode == "simulated";
      if (p.simulated_clock) {
        const Node start = clock["start"];
        if (!start.present()) {
          start.problem("missing: the simulated clock's start (ISO 8601 UTC)");
        } else if (const auto t = parse_iso8601(start.text("")); !t) {
          start.problem("expected an ISO 8601 UTC time, e.g. 2026-01-05T00:00:00Z");
        } else {
          p.simulated_start_ns = *t;
        }
      }
    }
  }
  const Node machines = root["machines"];
  if (machines.present() && !machines.is_list()) {
    machines.problem("expected a list of machine files");
  }
  for (const Node& entry : machines.items()) {
    if (!entry.is_scalar()) {
      entry.problem("expected a file name");
      continue;
    }
    MachineConfig m = read_machine_file(resolve(path, entry.scalar()), diagnostics);
    if (!m.machine_id.empty() && p.find_machine(m.machine_id)) {
      entry.problem("machine_id '" + m.machine_id + "' is configured twice");
      continue;
    }
    if (refuse_simulators) refuse_simulated(entry, m, diagnostics);
    p.machines.push_back(std::move(m));
  }
  return p;
}

// A section read from text alone, as it would be under `key` of `source`.
template <typename Read>
auto read_section_text(std::string_view text, const std::string& source, const std::string& key,
                       Read read) {
  Diagnostics diagnostics;
  const Node parsed = parse_text(text, source, diagnostics);
  auto result = read(Node(parsed.yaml(), source, diagnostics, key, key));
  diagnostics.throw_if_any();
  return result;
}

}  // namespace
}  // namespace config

const Tolerance& MachineConfig::tolerance(const std::string& metric) const {
  const auto it = tolerances.find(metric);
  if (it == tolerances.end()) {
    throw ConfigError(source_path + ": machine '" + machine_id + "' has no tolerance for metric '" +
                      metric + "'");
  }
  return it->second;
}

std::optional<std::int64_t> RetentionConfig::thin_points_before_ns(std::int64_t now_ns) const {
  if (!thin_points_after_months) return std::nullopt;
  const date::sys_time<std::chrono::nanoseconds> now{std::chrono::nanoseconds(now_ns)};
  const date::sys_days day = date::floor<date::days>(now);
  date::year_month_day then = date::year_month_day(day) - date::months(*thin_points_after_months);
  if (!then.ok()) then = then.year() / then.month() / date::last;  // 31 March -> 28/29 February
  return (date::sys_days(then) + (now - day)).time_since_epoch().count();
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
  for (const std::string& id : split_at(list, ',')) {
    if (id.empty()) throw ConfigError(what + " '" + list + "': an empty machine id");
    const MachineConfig* m = find_machine(id);
    if (!m) throw ConfigError(what + " '" + id + "' is not configured in " + source_path);
    if (!seen.insert(id).second) throw ConfigError(what + " '" + id + "' is named twice");
    out.push_back(*m);
  }
  return out;
}

std::string plant_config_path(const std::string& flag_value) {
  if (!flag_value.empty()) return flag_value;
  if (const char* env = std::getenv("NCQUAL_PLANT"); env && *env) return env;
  return "";
}

bool is_simulated(const MachineConfig& machine) {
  return machine.instrument.driver == InstrumentDriver::Simulator;
}

bool has_sections_for(const MachineConfig& machine, CheckKind kind) {
  switch (check_kind_info(kind).needs) {
    case Needs::GlobalCheck: return machine.global_check.has_value();
    case Needs::Fixture: return machine.fixture.has_value();
    case Needs::Monument:
    case Needs::SetPoints: break;
  }
  return true;  // every machine has a monument and set points
}

MachineConfig load_machine_config(const std::string& path) {
  config::Diagnostics diagnostics;
  MachineConfig m = config::read_machine_file(path, diagnostics);
  diagnostics.throw_if_any();
  return m;
}

MachineConfig parse_machine_config(std::string_view yaml_text, const std::string& source) {
  config::Diagnostics diagnostics;
  MachineConfig m = config::read_machine_file(source, diagnostics, yaml_text);
  diagnostics.throw_if_any();
  return m;
}

PlantConfig load_plant_config(const std::string& path) {
  config::Diagnostics diagnostics;
  std::optional<PlantConfig> plant = config::read_plant(path, diagnostics);
  diagnostics.throw_if_any();
  return std::move(*plant);
}

ConfigReport check_plant_config(const std::string& path) {
  config::Diagnostics diagnostics;
  ConfigReport report;
  std::optional<PlantConfig> plant = config::read_plant(path, diagnostics);
  report.problems = diagnostics.problems();
  report.values = diagnostics.values();
  if (report.problems.empty()) report.plant = std::move(plant);
  return report;
}

CalendarConfig parse_calendar_config(std::string_view yaml_text, const std::string& source) {
  return config::read_section_text(yaml_text, source, "scheduler.calendar", config::read_calendar);
}

solver::ErrorBudgetConfig parse_error_budget(std::string_view yaml_text,
                                             const std::string& source) {
  return config::read_section_text(yaml_text, source, "budget", config::read_budget);
}

sim::SimulatorConfig parse_simulator_config(std::string_view machine_yaml_text,
                                            const MachineConfig& machine) {
  config::Diagnostics diagnostics;
  const config::Node root = config::parse_text(machine_yaml_text, machine.source_path, diagnostics);
  sim::SimulatorConfig c = config::read_simulator(root["simulator"], machine);
  diagnostics.throw_if_any();
  return c;
}

std::string_view to_string(ControlDialect dialect) {
  switch (dialect) {
    case ControlDialect::LinuxCnc: return "linuxcnc";
    case ControlDialect::Fanuc: return "fanuc";
    case ControlDialect::GenericCsv: return "generic-csv";
  }
  return "?";
}

std::optional<ControlDialect> control_dialect_from(std::string_view name) {
  for (ControlDialect d :
       {ControlDialect::LinuxCnc, ControlDialect::Fanuc, ControlDialect::GenericCsv}) {
    if (to_string(d) == name) return d;
  }
  return std::nullopt;
}

std::string control_dialect_names() { return "linuxcnc, fanuc, generic-csv"; }

std::string_view to_string(InstrumentDriver driver) {
  return driver == InstrumentDriver::ControlFiles ? "control-files" : "simulator";
}

std::string_view to_string(Discovery discovery) {
  switch (discovery) {
    case Discovery::Multicast: return "multicast";
    case Discovery::Server: return "server";
    case Discovery::Peers: return "peers";
  }
  return "?";
}

std::optional<NetworkAddress> parse_network_address(std::string_view text) {
  NetworkAddress a;
  const auto colon = text.rfind(':');
  a.host = std::string(text.substr(0, colon));
  if (colon != std::string_view::npos) {
    const std::string port(text.substr(colon + 1));
    if (port.empty() || port.size() > 5 ||
        port.find_first_not_of("0123456789") != std::string::npos) {
      return std::nullopt;
    }
    a.port = std::stoi(port);
    if (a.port < 1 || a.port > 65535) return std::nullopt;
  }
  // A host name (RFC 1123 letters, digits, '-' and '.') or a dotted quad: the same characters.
  if (a.host.empty() || a.host.size() > 253 || a.host.front() == '.' || a.host.front() == '-' ||
      a.host.find_first_not_of(
          "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-.") !=
          std::string::npos) {
    return std::nullopt;
  }
  // All digits and dots: an IPv4 address, four numbers of 0..255 (not a name to look up).
  if (a.host.find_first_not_of("0123456789.") == std::string::npos) {
    int parts = 0;
    for (std::size_t start = 0; start <= a.host.size(); ++parts) {
      const std::size_t dot = std::min(a.host.find('.', start), a.host.size());
      const std::string part = a.host.substr(start, dot - start);
      if (part.empty() || part.size() > 3 || std::stoi(part) > 255) return std::nullopt;
      start = dot + 1;
    }
    if (parts != 4) return std::nullopt;
  }
  return a;
}

std::string to_string(const NetworkAddress& address) {
  return address.port == 0 ? address.host : address.host + ":" + std::to_string(address.port);
}

}  // namespace ncqual
