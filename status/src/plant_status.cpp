// SPDX-License-Identifier: Apache-2.0
// The plant's status (ncqual/status/plant_status.hpp): `ncqual status` and the dashboard's plant
// page.
#include "ncqual/status/plant_status.hpp"

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/storage/trend.hpp"

#include <string_view>
#include <utility>

namespace ncqual::plant_status {
namespace {

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
  d.liveness = beat.state == "stopped" ? "stopped" : d.silent ? "stale" : "live";
  return d;
}

// Whether `service` (a scheduler's heartbeat) serves `machine_id`: a plant-wide one (no machine
// named) or one whose machines, joined by commas, include it.
bool serves(const ServiceDocument& service, const std::string& machine_id) {
  if (service.machine_id.empty()) return true;
  std::string_view rest = service.machine_id;
  while (true) {
    const std::size_t comma = rest.find(',');
    if (rest.substr(0, comma) == machine_id) return true;
    if (comma == std::string_view::npos) return false;
    rest.remove_prefix(comma + 1);
  }
}

// The best word of the schedulers serving `machine_id`: live over stale over stopped over none.
std::string scheduler_liveness(const std::vector<ServiceDocument>& services,
                               const std::string& machine_id) {
  const auto rank = [](const std::string& l) {
    return l == "live" ? 3 : l == "stale" ? 2 : l == "stopped" ? 1 : 0;
  };
  std::string best = "none";
  for (const auto& s : services) {
    if (s.service == "scheduler" && serves(s, machine_id) && rank(s.liveness) > rank(best)) {
      best = s.liveness;
    }
  }
  return best;
}

}  // namespace

std::chrono::milliseconds service_heartbeat_period() { return kHeartbeatPeriod; }

Calendar plant_calendar(const PlantConfig& plant) {
  return Calendar(plant.calendar.value_or(default_calendar_config()));
}

StatusDocument plant_status(storage::Database& db, const PlantConfig& plant,
                            const Calendar& calendar, const StatusQuery& query) {
  StatusDocument out;
  out.plant = plant.plant;
  const std::int64_t plant_now = query.wall_now_ns;
  for (const auto& m : plant.machines) {
    if (query.machine_id && m.machine_id != *query.machine_id) continue;
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
    // The newest check: were its numbers measured on the machine or simulated?
    storage::HistoryQuery newest;
    newest.machine_id = m.machine_id;
    newest.limit = 1;
    if (const auto checks = db.history(newest); !checks.empty()) {
      machine.last_check = checks.front().request_id;
      machine.last_check_origin = storage::origin_of(checks.front());
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
      std::chrono::duration_cast<std::chrono::nanoseconds>(service_heartbeat_period()).count();
  out.wall_now_ns = plant_now;
  out.heartbeat_period_ms = period_ns / 1'000'000;
  for (const Heartbeat& beat : db.services()) {
    out.services.push_back(service_document(beat, plant_now, period_ns));
  }
  for (auto& machine : out.machines) {
    machine.scheduler = scheduler_liveness(out.services, machine.machine_id);
  }
  return out;
}

}  // namespace ncqual::plant_status
