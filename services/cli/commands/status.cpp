// SPDX-License-Identifier: Apache-2.0
// `ncqual status`: the plant's machines as the qualification process sees them.
//
//   ncqual status [--plant F] [--db F] [--machine M] [--json]
//     Per configured machine: its newest status from the historian (state, detail, time), and per
//     period of the plant calendar (scheduler.calendar, else the default process) its checks,
//     when the period last passed (the oldest of its checks' newest PASS: a period is current only
//     when all its checks are), whether it is due or overdue now, and when it falls due next.
//     "Now" is the wall clock, or with a simulated clock the time of the machine's newest status
//     (heartbeats carry wall time). Read only; the scheduler need not run.
//     --json names (stable): {"plant", "now_ns", "machines": [{"machine_id", "state", "detail",
//       "status_time_ns", "periods": [{"name", "every", "checks": [{"kind", "last_pass_ns"}],
//       "last_pass_ns", "due", "overdue", "next_due_ns"}]}]} (StatusDocument below); times are
//       ns since the Unix epoch UTC or null; the text form prints them in the plant's time zone.
//
// Exit codes: 0, 2 bad usage (and a machine the plant does not configure), 6 no historian
// database at the path.
#include "commands.hpp"

#include "ncqual/check_kinds.hpp"

#include "ncqual/calendar.hpp"
#include "ncqual/clock.hpp"
#include "ncqual/json.hpp"
#include "ncqual/storage.hpp"

#include <fmt/format.h>

#include <iostream>

namespace ncqual::cli {
namespace {

// The --json document; its names are stable (append, never rename).
struct CheckDocument {
  CheckKind kind = CheckKind::MonumentPositioning;
  std::optional<std::int64_t> last_pass_ns;
};
struct PeriodDocument {
  std::string name;
  std::string every;
  std::vector<CheckDocument> checks;
  std::optional<std::int64_t> last_pass_ns;  // of the period: the oldest of its checks' newest
  bool due = false;
  bool overdue = false;
  std::int64_t next_due_ns = 0;
};
struct MachineDocument {
  std::string machine_id;
  MachineState state = MachineState::Unknown;
  std::string detail;
  std::optional<std::int64_t> status_time_ns;
  std::vector<PeriodDocument> periods;
};
struct StatusDocument {
  std::string plant;
  std::optional<std::int64_t> now_ns;  // of the last machine; null without machines
  std::vector<MachineDocument> machines;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CheckDocument, kind, last_pass_ns)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(PeriodDocument, name, every, checks, last_pass_ns, due, overdue,
                                   next_due_ns)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(MachineDocument, machine_id, state, detail, status_time_ns,
                                   periods)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(StatusDocument, plant, now_ns, machines)

struct Options {
  std::string plant;
  std::optional<std::string> db, machine;
  bool json = false;
};

int run(const Options& o) {
  const PlantConfig plant = plant_from(o.plant);
  const std::string db_path = o.db.value_or(plant.historian_database);
  auto opened = open_historian(db_path, "status");
  if (!opened) return kExitNotFound;
  storage::Database& db = *opened;
  const Calendar calendar(plant.calendar.value_or(default_calendar_config()));
  const auto& machine_filter = o.machine;
  if (machine_filter) (void)configured_machine(plant, *machine_filter);
  StatusDocument out{plant.plant, std::nullopt, {}};
  std::int64_t plant_now = WallClock().now_ns();
  for (const auto& m : plant.machines) {
    if (machine_filter && m.machine_id != *machine_filter) continue;
    const auto status = db.latest_status(m.machine_id);
    // On a simulated clock "now" is the scheduler's newest word on the machine (heartbeats carry
    // wall time, so the machine's last-seen time would not do).
    const std::int64_t now =
        plant.simulated_clock ? (status ? status->time_ns : plant.simulated_start_ns) : plant_now;
    MachineDocument& machine = out.machines.emplace_back();
    machine.machine_id = m.machine_id;
    machine.state = status ? status->state : MachineState::Unknown;
    machine.detail = status ? status->detail : "no status stored yet";
    if (status) machine.status_time_ns = status->time_ns;
    for (const auto& period : calendar.config().periods) {
      PeriodDocument p{period.name, std::string(to_string(period.unit))};
      std::optional<std::int64_t> oldest;
      bool all = true;
      for (CheckKind k : period.checks) {
        if (!has_sections_for(m, k)) continue;
        // The newest pass of the kind or of one that satisfies it (a fixture loop that ended in a
        // passed post-calibration completes the week too): the check-kind table says which.
        std::optional<std::int64_t> last;
        for (CheckKind passing : kinds_passing(k)) {
          const auto t = db.last_pass_ns(m.machine_id, passing);
          if (t && (!last || *t > *last)) last = t;
        }
        p.checks.push_back({k, last});
        if (!last) {
          all = false;
        } else if (!oldest || *last < *oldest) {
          oldest = last;
        }
      }
      if (p.checks.empty()) continue;
      p.last_pass_ns = all ? oldest : std::nullopt;
      p.due = calendar.due(period, p.last_pass_ns, now);
      p.overdue = calendar.overdue(period, p.last_pass_ns, now);
      p.next_due_ns = calendar.next_due(period, p.last_pass_ns, now);
      machine.periods.push_back(std::move(p));
    }
    out.now_ns = now;
  }
  if (o.json) {
    std::cout << nlohmann::json(out).dump(2) << "\n";
    return kExitOk;
  }
  const auto when = [&](std::optional<std::int64_t> t) {
    return t ? calendar.local_text(*t) : std::string("never");
  };
  fmt::print("plant {} ({}{})\n", plant.plant, calendar.config().time_zone,
             plant.simulated_clock ? ", simulated clock" : "");
  constexpr const char* kRow = "  {:<10}{:<8}{:<24}{:<24}{}\n";
  for (const auto& machine : out.machines) {
    fmt::print("\n{}  {}  ({})\n  {}\n", machine.machine_id, to_string(machine.state),
               when(machine.status_time_ns), machine.detail);
    fmt::print(kRow, "period", "every", "last passed", "next due", "");
    for (const auto& p : machine.periods) {
      fmt::print(kRow, p.name, p.every, when(p.last_pass_ns),
                 p.due ? std::string("now") : when(p.next_due_ns),
                 p.overdue ? "OVERDUE"
                 : p.due   ? "due"
                           : "");
    }
  }
  return kExitOk;
}

}  // namespace

void add_status(CLI::App& app, Commands& commands) {
  auto [cmd, o] = add_command(
      app, commands, "status",
      "every machine's state, and per period its last pass and when it falls due next", run);
  add_historian_options(cmd, o->plant, o->db);
  add_machine_option(cmd, o->machine, "only this machine");
  add_json_flag(cmd, o->json);
}

}  // namespace ncqual::cli
