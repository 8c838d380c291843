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
//     conflicting with stored ones (CONFLICT: n, when there are any), SIMULATED when its newest
//     check was produced by ncqual's simulator (with a line saying so; a line too when that
//     check does not say, stored before the historian recorded it), and its active trend
//     warnings (docs/trends.md, "Warnings": the metric, the kind, since when, and for a forecast
//     the earliest and expected dates it reaches its tolerance). Then the services: the last
//     heartbeat the historian stored of every service instance, with its state, health (and why,
//     when not ok), outbox depth and the age of its oldest unacknowledged sample, and how long ago
//     it was sent (wall clock). A service whose last heartbeat said "stopped" (an orderly stop)
//     is "stopped" then; one whose last heartbeat is older than 3 heartbeat periods on this
//     reader's wall clock (whatever clock the plant simulated) is "STALE since" then: it died,
//     hangs or cannot reach the historian. A machine without a live scheduler says so: `ncqual
//     check` and `ncqual intervene` need one. A service whose health is "failed" is printed
//     again at the end, prominently (the exit code stays 0). Read only; the scheduler need not
//     run.
//     --json names (stable): {"plant", "now_ns", "machines": [{"machine_id", "state", "detail",
//       "status_time_ns", "periods": [{"name", "every", "checks": [{"kind", "last_pass_ns"}],
//       "last_pass_ns", "due", "overdue", "next_due_ns"}], "conflicts", "warnings": [{"metric",
//       "check_kind", "kind", "side", "started_ns", "raised_by", "raised_ns",
//       "expected_crossing_ns", "earliest_crossing_ns", "text"}], "scheduler", "last_check",
//       "last_check_origin" ("measured", "simulated", "unknown"; null: no check)}], "wall_now_ns",
//       "heartbeat_period_ms", "services": [{"service", "instance", "machine_id", "state",
//       "health", "health_detail", "outbox_depth", "oldest_unacknowledged_ns",
//       "oldest_unacknowledged_age_ns", "time_ns", "age_ns", "silent", "liveness"}]}
//       (ncqual/status/plant_status.hpp, shared with the dashboard's /api/v1/plant); times are ns
//       since the Unix epoch UTC or null; the text form prints them in the plant's time zone.
//       oldest_unacknowledged_age_ns is as of the heartbeat (null: nothing waits).
//
// Exit codes: 0, 2 bad usage (and a machine the plant does not configure), 6 no historian
// database at the path.
#include "commands.hpp"

#include "ncqual/common/calendar.hpp"
#include "ncqual/common/clock.hpp"
#include "ncqual/common/json.hpp"
#include "ncqual/status/plant_status.hpp"
#include "ncqual/storage/database.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <iostream>

namespace ncqual::cli {
namespace {

// The --json document and its computation: ncqual/status/plant_status.hpp (the dashboard shows the
// same).
using plant_status::StatusDocument;

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
    const std::string last =
        s.liveness == "stopped" ? "stopped " + calendar.local_text(s.time_ns)
        : s.liveness == "stale"
            ? "stale since " + calendar.local_text(s.time_ns) + " (" + duration_text(s.age_ns) + ")"
            : duration_text(s.age_ns) + " ago";
    const std::string state = s.liveness == "live"    ? s.state
                              : s.liveness == "stale" ? "STALE"
                                                      : "stopped";
    const std::string health = s.health == "ok" ? s.health : upper(s.health);
    fmt::print(kRow, s.service, instance, state, health, s.outbox_depth,
               s.oldest_unacknowledged_age_ns ? duration_text(*s.oldest_unacknowledged_age_ns)
                                              : std::string("-"),
               last);
    if (s.health != "ok" && !s.health_detail.empty()) fmt::print("    {}\n", s.health_detail);
  }
  for (const auto& s : out.services) {
    if (s.health != "failed") continue;
    fmt::print("\n!! SERVICE FAILED: {} {}{}: {}\n", s.service, s.instance,
               s.liveness != "live"
                   ? " (" + s.liveness + " since " + calendar.local_text(s.time_ns) + ")"
                   : "",
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
  const auto& machine_filter = o.machine;
  if (machine_filter) (void)configured_machine(plant, *machine_filter);
  const std::string db_path = o.db.value_or(plant.historian_database);
  auto opened = open_historian(db_path, "status");
  if (!opened) return kExitNotFound;
  storage::Database& db = *opened;
  const Calendar calendar = plant_status::plant_calendar(plant);
  const StatusDocument out =
      plant_status::plant_status(db, plant, calendar, {machine_filter, WallClock().now_ns()});
  if (o.json) {
    std::cout << nlohmann::json(out).dump(2) << "\n";
    return kExitOk;
  }
  const auto when = [&](std::optional<std::int64_t> t) {
    return t ? calendar.local_text(*t) : std::string("never");
  };
  fmt::print("plant {} ({}{})\n", plant.plant, calendar.config().time_zone,
             plant.simulated_clock ? ", simulated clock" : "");
  constexpr const char* kRow = "  {:<10}{:<8}{:<30}{:<30}{}\n";
  for (const auto& machine : out.machines) {
    fmt::print("\n{}  {}  ({}){}{}\n  {}\n", machine.machine_id, to_string(machine.state),
               when(machine.status_time_ns),
               machine.last_check_origin == DataOrigin::Simulated ? "  SIMULATED" : "",
               machine.conflicts > 0 ? fmt::format("  CONFLICT: {}", machine.conflicts) : "",
               machine.detail);
    if (machine.last_check_origin == DataOrigin::Simulated) {
      fmt::print(
          "  SIMULATED DATA: its last check ({}) was produced by ncqual's simulator and says "
          "nothing about the machine\n",
          *machine.last_check);
    } else if (machine.last_check_origin == DataOrigin::Unknown) {
      fmt::print("  its last check ({}) does not say whether it was measured or simulated\n",
                 *machine.last_check);
    }
    fmt::print(kRow, "period", "every", "last passed", "next due", "");
    for (const auto& p : machine.periods) {
      fmt::print(kRow, p.name, p.every, when(p.last_pass_ns),
                 p.due ? std::string("now") : when(p.next_due_ns),
                 p.overdue ? "OVERDUE"
                 : p.due   ? "due"
                           : "");
    }
    if (machine.scheduler != "live") {
      fmt::print(
          "  no scheduler is running for it ({}): nothing is ordered, and `ncqual check` and "
          "`ncqual intervene` wait for one in vain; start ncqual-scheduler first\n",
          machine.scheduler == "none"    ? "none was heard"
          : machine.scheduler == "stale" ? "its heartbeats stopped"
                                         : "it stopped");
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
