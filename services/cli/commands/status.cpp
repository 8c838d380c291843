// SPDX-License-Identifier: Apache-2.0
// `ncqual status`: the plant's machines as the qualification process sees them.
//
//   ncqual status [--plant F] [--db F] [--machine M] [--json]
//     Per configured machine: its newest status from the historian (state, detail, time), and per
//     period of the plant calendar (scheduler.calendar, else the default process) its checks,
//     when the period last passed (the oldest of its checks' newest PASS: a period is current only
//     when all its checks are), whether it is due or overdue now, and when it falls due next.
//     "Now" is the wall clock, or with a simulated clock the time of the machine's newest status
//     (heartbeats carry wall time). Per machine also the samples the historian kept for
//     conflicting with stored ones (CONFLICT: n, when there are any) and its active trend
//     warnings (docs/trends.md, "Warnings": the metric, the kind, since when, and for a forecast
//     the earliest and expected dates it reaches its tolerance). Then the services: the last
//     heartbeat the historian stored of every service instance, with its state, health (and why,
//     when not ok), outbox depth and the age of its oldest unacknowledged sample, and how long ago
//     it was sent (wall clock); one older than 3 heartbeat periods is "silent since" then (or
//     "stopped" when its last word was "stopping"). A service whose health is "failed" is
//     printed again at the end, prominently (the exit code stays 0). Read only; the scheduler
//     need not run.
//     --json names (stable): {"plant", "now_ns", "machines": [{"machine_id", "state", "detail",
//       "status_time_ns", "periods": [{"name", "every", "checks": [{"kind", "last_pass_ns"}],
//       "last_pass_ns", "due", "overdue", "next_due_ns"}], "conflicts", "warnings": [{"metric",
//       "check_kind", "kind", "side", "started_ns", "raised_by", "raised_ns",
//       "expected_crossing_ns", "earliest_crossing_ns", "text"}]}], "wall_now_ns",
//       "heartbeat_period_ms", "services": [{"service", "instance", "machine_id", "state",
//       "health", "health_detail", "outbox_depth", "oldest_unacknowledged_ns",
//       "oldest_unacknowledged_age_ns", "time_ns", "age_ns", "silent"}]} (StatusDocument below);
//       times are ns since the Unix epoch UTC or null; the text form prints them in the plant's
//       time zone. oldest_unacknowledged_age_ns is as of the heartbeat (null: nothing waits).
//
// Exit codes: 0, 2 bad usage (and a machine the plant does not configure), 6 no historian
// database at the path.
#include "commands.hpp"

#include "ncqual/check_kinds.hpp"

#include "ncqual/calendar.hpp"
#include "ncqual/clock.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/json.hpp"
#include "ncqual/storage.hpp"
#include "ncqual/storage_trend.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
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
// An active trend warning (storage::TrendWarningRecord).
struct WarningDocument {
  std::string metric;
  CheckKind check_kind = CheckKind::MonumentPositioning;
  std::string kind;
  std::string side;
  std::int64_t started_ns = 0;
  std::string raised_by;
  std::int64_t raised_ns = 0;
  std::optional<std::int64_t> expected_crossing_ns;
  std::optional<std::int64_t> earliest_crossing_ns;
  std::string text;
};
struct MachineDocument {
  std::string machine_id;
  MachineState state = MachineState::Unknown;
  std::string detail;
  std::optional<std::int64_t> status_time_ns;
  std::vector<PeriodDocument> periods;
  std::int64_t conflicts = 0;             // samples kept beside stored ones for other content
  std::vector<WarningDocument> warnings;  // active trend warnings, newest raised first
};
struct ServiceDocument {
  std::string service;
  std::string instance;
  std::string machine_id;
  std::string state;
  std::string health;
  std::string health_detail;
  std::int64_t outbox_depth = 0;
  std::int64_t oldest_unacknowledged_ns = 0;                 // 0: nothing waits
  std::optional<std::int64_t> oldest_unacknowledged_age_ns;  // as of the heartbeat
  std::int64_t time_ns = 0;                                  // of the last heartbeat (wall clock)
  std::int64_t age_ns = 0;                                   // wall_now_ns - time_ns
  bool silent = false;  // no heartbeat for more than kSilentPeriods periods
};
struct StatusDocument {
  std::string plant;
  std::optional<std::int64_t> now_ns;  // of the last machine; null without machines
  std::vector<MachineDocument> machines;
  std::int64_t wall_now_ns = 0;  // what the services' ages are measured from
  std::int64_t heartbeat_period_ms = 0;
  std::vector<ServiceDocument> services;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CheckDocument, kind, last_pass_ns)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(PeriodDocument, name, every, checks, last_pass_ns, due, overdue,
                                   next_due_ns)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(WarningDocument, metric, check_kind, kind, side, started_ns,
                                   raised_by, raised_ns, expected_crossing_ns, earliest_crossing_ns,
                                   text)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(MachineDocument, machine_id, state, detail, status_time_ns,
                                   periods, conflicts, warnings)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ServiceDocument, service, instance, machine_id, state, health,
                                   health_detail, outbox_depth, oldest_unacknowledged_ns,
                                   oldest_unacknowledged_age_ns, time_ns, age_ns, silent)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(StatusDocument, plant, now_ns, machines, wall_now_ns,
                                   heartbeat_period_ms, services)

// A service is silent when its last heartbeat is older than this many heartbeat periods.
constexpr int kSilentPeriods = 3;

ServiceDocument service_document(const Heartbeat& beat, std::int64_t wall_now_ns,
                                 std::int64_t period_ns) {
  ServiceDocument d;
  d.service = beat.service;
  d.instance = beat.instance;
  d.machine_id = beat.machine_id;
  d.state = beat.state;
  d.health = beat.health;
  d.health_detail = beat.health_detail;
  d.outbox_depth = beat.outbox_depth;
  d.oldest_unacknowledged_ns = beat.oldest_unacknowledged_ns;
  if (beat.oldest_unacknowledged_ns > 0) {
    d.oldest_unacknowledged_age_ns = beat.time_ns - beat.oldest_unacknowledged_ns;
  }
  d.time_ns = beat.time_ns;
  d.age_ns = wall_now_ns - beat.time_ns;
  d.silent = d.age_ns > kSilentPeriods * period_ns;
  return d;
}

std::string upper(std::string text) {
  for (char& c : text) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return text;
}

// "42 s", "5 min", "3 h 20 min", "2 d 4 h": a duration for people.
std::string duration_text(std::int64_t ns) {
  const std::int64_t s = std::max<std::int64_t>(0, ns / 1'000'000'000);
  if (s < 120) return fmt::format("{} s", s);
  if (s < 7200) return fmt::format("{} min", s / 60);
  if (s < 172800) return fmt::format("{} h {} min", s / 3600, s % 3600 / 60);
  return fmt::format("{} d {} h", s / 86400, s % 86400 / 3600);
}

void print_services(const StatusDocument& out, const Calendar& calendar) {
  fmt::print("\nservices (the last heartbeat the historian stored of each; one every {} ms)\n",
             out.heartbeat_period_ms);
  if (out.services.empty()) {
    fmt::print("  none stored yet\n");
    return;
  }
  constexpr const char* kRow = "  {:<13}{:<28}{:<10}{:<10}{:<8}{:<16}{}\n";
  fmt::print(kRow, "service", "instance", "state", "health", "outbox", "oldest unacked",
             "last heartbeat");
  for (const auto& s : out.services) {
    const std::string instance = s.machine_id.empty() || s.service != "acquisition"
                                     ? s.instance
                                     : s.instance + " (" + s.machine_id + ")";
    const std::string last = !s.silent ? duration_text(s.age_ns) + " ago"
                             : s.state == "stopping"
                                 ? "stopped " + calendar.local_text(s.time_ns)
                                 : "silent since " + calendar.local_text(s.time_ns) + " (" +
                                       duration_text(s.age_ns) + ")";
    const std::string health = s.health == "ok" ? s.health : upper(s.health);
    fmt::print(kRow, s.service, instance, s.state, health, s.outbox_depth,
               s.oldest_unacknowledged_age_ns ? duration_text(*s.oldest_unacknowledged_age_ns)
                                              : std::string("-"),
               last);
    if (s.health != "ok" && !s.health_detail.empty()) fmt::print("    {}\n", s.health_detail);
  }
  for (const auto& s : out.services) {
    if (s.health != "failed") continue;
    fmt::print("\n!! SERVICE FAILED: {} {}{}: {}\n", s.service, s.instance,
               s.silent ? " (silent since " + calendar.local_text(s.time_ns) + ")" : "",
               s.health_detail.empty() ? "no detail given" : s.health_detail);
  }
}

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
  StatusDocument out;
  out.plant = plant.plant;
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
      PeriodDocument p;
      p.name = period.name;
      p.every = std::string(to_string(period.unit));
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
    machine.conflicts = static_cast<std::int64_t>(db.conflicts(m.machine_id).size());
    for (const auto& w : storage::trend_warnings(db, {m.machine_id, {}, true})) {
      machine.warnings.push_back({w.metric, w.check_kind, w.kind, w.side, w.started_ns, w.raised_by,
                                  w.raised_ns, w.expected_crossing_ns, w.earliest_crossing_ns,
                                  w.text});
    }
    out.now_ns = now;
  }
  // Heartbeats carry wall time, also on a simulated clock.
  const std::int64_t period_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(dds::ServiceOptions{}.heartbeat_period)
          .count();
  out.wall_now_ns = plant_now;
  out.heartbeat_period_ms = period_ns / 1'000'000;
  for (const Heartbeat& beat : db.services()) {
    out.services.push_back(service_document(beat, plant_now, period_ns));
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
    fmt::print("\n{}  {}  ({}){}\n  {}\n", machine.machine_id, to_string(machine.state),
               when(machine.status_time_ns),
               machine.conflicts > 0 ? fmt::format("  CONFLICT: {}", machine.conflicts) : "",
               machine.detail);
    fmt::print(kRow, "period", "every", "last passed", "next due", "");
    for (const auto& p : machine.periods) {
      fmt::print(kRow, p.name, p.every, when(p.last_pass_ns),
                 p.due ? std::string("now") : when(p.next_due_ns),
                 p.overdue ? "OVERDUE"
                 : p.due   ? "due"
                           : "");
    }
    if (!machine.warnings.empty()) {
      fmt::print(
          "  trend warnings ({}; `ncqual trend --machine {} --metric NAME` for the figures)\n",
          machine.warnings.size(), machine.machine_id);
      for (const auto& w : machine.warnings) {
        std::string dates;
        if (w.kind == "forecast") {
          dates = fmt::format("; earliest {}, expected {}", when(w.earliest_crossing_ns),
                              when(w.expected_crossing_ns));
        }
        fmt::print("    {} {} ({}) since {}{}\n      {}\n", w.metric, upper(w.kind), w.side,
                   calendar.local_text(w.started_ns), dates, w.text);
      }
    }
    if (machine.conflicts > 0) {
      fmt::print(
          "  {} sample{} kept beside stored one{} for other content: `ncqual history "
          "--machine {}` flags their checks\n",
          machine.conflicts, machine.conflicts == 1 ? "" : "s", machine.conflicts == 1 ? "" : "s",
          machine.machine_id);
    }
  }
  print_services(out, calendar);
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
