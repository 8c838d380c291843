// SPDX-License-Identifier: Apache-2.0
// The plant as the qualification process sees it: what `ncqual status` prints and what the
// dashboard's plant page (ncqual-web, docs/dashboard.md) shows, computed once here.
//
// Per configured machine: its newest status from the historian (state, detail, time), and per
// period of the plant calendar (scheduler.calendar, else the default process) its checks, when
// the period last passed (the oldest of its checks' newest PASS, or of a kind that satisfies it:
// a period is current only when all its checks are), whether it is due or overdue now, and when
// it falls due next. "Now" is the wall clock, or with a simulated clock the time of the machine's
// newest status (heartbeats carry wall time). Per machine also the samples the historian kept for
// conflicting with stored ones, its active trend warnings and whether its newest check was
// measured or simulated. Then the last heartbeat of every
// service instance, with its age and whether it is silent (older than kSilentPeriods periods).
//
// The documents' JSON names are stable (append, never rename): they are `ncqual status --json`
// and the dashboard's /api/v1/plant.
#pragma once

#include "ncqual/common/calendar.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/common/json.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/storage/database.hpp"

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::plant_status {

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
  // The scheduler serving the machine, as its heartbeats say (ServiceDocument::liveness): "live",
  // "stopped", "stale", or "none" when none was ever heard. `ncqual check` and `ncqual
  // intervene` need a live one.
  std::string scheduler = "none";
  // Its newest check (request id; null when none is stored) and whether its numbers were
  // "measured" on the machine, "simulated" by ncqual's simulator (its verdict says nothing about
  // the machine), or "unknown" (stored before the historian recorded it); null without a check.
  std::optional<std::string> last_check;
  std::optional<DataOrigin> last_check_origin;
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
  // What the reader makes of it, on its own wall clock (whatever clock the plant simulated):
  // "stopped" when the last heartbeat said so (an orderly stop), else "stale" when it is older
  // than kSilentPeriods periods (the service died, hangs or cannot reach the historian), else
  // "live".
  std::string liveness = "live";
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
                                   periods, conflicts, warnings, scheduler, last_check,
                                   last_check_origin)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ServiceDocument, service, instance, machine_id, state, health,
                                   health_detail, outbox_depth, oldest_unacknowledged_ns,
                                   oldest_unacknowledged_age_ns, time_ns, age_ns, silent, liveness)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(StatusDocument, plant, now_ns, machines, wall_now_ns,
                                   heartbeat_period_ms, services)

// A service is silent when its last heartbeat is older than this many heartbeat periods.
constexpr int kSilentPeriods = 3;

// The period at which every ncqual service sends its heartbeat (dds::ServiceOptions).
std::chrono::milliseconds service_heartbeat_period();

struct StatusQuery {
  std::optional<std::string> machine_id;  // only this configured machine; all when empty
  std::int64_t wall_now_ns = 0;           // the wall clock's now
};

// The calendar the status is computed with: the plant's, else the default process.
Calendar plant_calendar(const PlantConfig& plant);

// The plant's status from the historian `db` (read-only is enough), in one pass. Machines the
// plant configures, in its order (a machine_id it does not configure gives no machine: callers
// check it against the plant first).
StatusDocument plant_status(storage::Database& db, const PlantConfig& plant,
                            const Calendar& calendar, const StatusQuery& query);

}  // namespace ncqual::plant_status
