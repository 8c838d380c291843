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
//       "last_pass_ns", "due", "overdue", "next_due_ns"}]}]}; times are ns since the Unix epoch
//       UTC or null; the text form prints them in the plant's time zone.
//
// Exit codes: 0, 2 bad usage (and a machine the plant does not configure), 6 no historian
// database at the path.
#include "commands.hpp"

#include "ncqual/check_kinds.hpp"

#include "ncqual/calendar.hpp"
#include "ncqual/clock.hpp"
#include "ncqual/storage.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>

namespace ncqual::cli {
namespace {

nlohmann::json time_or_null(std::optional<std::int64_t> t) {
  return t ? nlohmann::json(*t) : nlohmann::json(nullptr);
}

struct Options {
  std::string plant;
  std::optional<std::string> db, machine;
  bool json = false;
};

int run(const Options& o) {
  const PlantConfig plant = plant_from(o.plant);
  const std::string db_path = o.db.value_or(plant.historian_database);
  if (!std::filesystem::exists(db_path)) {
    std::cerr << "ncqual status: no historian database at " << db_path << "\n";
    return kExitNotFound;
  }
  auto db = storage::Database::open_readonly(db_path);
  const Calendar calendar(plant.calendar.value_or(default_calendar_config()));
  const auto& machine_filter = o.machine;
  if (machine_filter) (void)configured_machine(plant, *machine_filter);
  nlohmann::json out{{"plant", plant.plant}, {"machines", nlohmann::json::array()}};
  std::int64_t plant_now = WallClock().now_ns();
  for (const auto& m : plant.machines) {
    if (machine_filter && m.machine_id != *machine_filter) continue;
    const auto status = db.latest_status(m.machine_id);
    // On a simulated clock "now" is the scheduler's newest word on the machine (heartbeats carry
    // wall time, so the machine's last-seen time would not do).
    const std::int64_t now =
        plant.simulated_clock ? (status ? status->time_ns : plant.simulated_start_ns) : plant_now;
    nlohmann::json jm{{"machine_id", m.machine_id}};
    jm["state"] = status ? std::string(to_string(status->state))
                         : std::string(to_string(MachineState::Unknown));
    jm["detail"] = status ? status->detail : "no status stored yet";
    jm["status_time_ns"] = status ? nlohmann::json(status->time_ns) : nlohmann::json(nullptr);
    jm["periods"] = nlohmann::json::array();
    for (const auto& period : calendar.config().periods) {
      nlohmann::json jp{{"name", period.name},
                        {"every", std::string(to_string(period.unit))},
                        {"checks", nlohmann::json::array()}};
      std::optional<std::int64_t> oldest;
      bool all = true, any = false;
      for (CheckKind k : period.checks) {
        if (!has_sections_for(m, k)) continue;
        any = true;
        // The newest pass of the kind or of one that satisfies it (a fixture loop that ended in a
        // passed post-calibration completes the week too): the check-kind table says which.
        std::optional<std::int64_t> last;
        for (CheckKind passing : kinds_passing(k)) {
          const auto t = db.last_pass_ns(m.machine_id, passing);
          if (t && (!last || *t > *last)) last = t;
        }
        jp["checks"].push_back(
            {{"kind", std::string(to_string(k))}, {"last_pass_ns", time_or_null(last)}});
        if (!last) {
          all = false;
        } else if (!oldest || *last < *oldest) {
          oldest = last;
        }
      }
      if (!any) continue;
      const std::optional<std::int64_t> period_last = all ? oldest : std::nullopt;
      jp["last_pass_ns"] = time_or_null(period_last);
      jp["due"] = calendar.due(period, period_last, now);
      jp["overdue"] = calendar.overdue(period, period_last, now);
      jp["next_due_ns"] = calendar.next_due(period, period_last, now);
      jm["periods"].push_back(jp);
    }
    out["machines"].push_back(jm);
    out["now_ns"] = now;
  }
  if (o.json) {
    std::cout << out.dump(2) << "\n";
    return kExitOk;
  }
  const auto when = [&](const nlohmann::json& t) {
    return t.is_null() ? std::string("never") : calendar.local_text(t.get<std::int64_t>());
  };
  fmt::print("plant {} ({}{})\n", plant.plant, calendar.config().time_zone,
             plant.simulated_clock ? ", simulated clock" : "");
  constexpr const char* kRow = "  {:<10}{:<8}{:<24}{:<24}{}\n";
  for (const auto& jm : out["machines"]) {
    fmt::print("\n{}  {}  ({})\n  {}\n", jm["machine_id"].get<std::string>(),
               jm["state"].get<std::string>(), when(jm["status_time_ns"]),
               jm["detail"].get<std::string>());
    fmt::print(kRow, "period", "every", "last passed", "next due", "");
    for (const auto& jp : jm["periods"]) {
      const bool due = jp["due"].get<bool>();
      fmt::print(kRow, jp["name"].get<std::string>(), jp["every"].get<std::string>(),
                 when(jp["last_pass_ns"]), due ? std::string("now") : when(jp["next_due_ns"]),
                 jp["overdue"].get<bool>() ? "OVERDUE"
                 : due                     ? "due"
                                           : "");
    }
  }
  return kExitOk;
}

}  // namespace

void add_status(CLI::App& app, Commands& commands) {
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "status", "every machine's state, and per period its last pass and when it falls due next");
  add_plant_option(cmd, o->plant);
  add_db_option(cmd, o->db);
  add_machine_option(cmd, o->machine, "only this machine");
  add_json_flag(cmd, o->json);
  commands.push_back({cmd, [o] { return run(*o); }});
}

}  // namespace ncqual::cli
