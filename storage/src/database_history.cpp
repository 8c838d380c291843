// SPDX-License-Identifier: Apache-2.0
// Database's queries: a check joined from its request, measurement set and result, the history
// of checks, and a machine's statuses, interventions, compensations, services and conflicts.
#include "ncqual/storage/database.hpp"

#include "database_impl.hpp"
#include "sqlite.hpp"

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ncqual::storage {
namespace {

using sqlite::Query;
using sqlite::Sql;

// Two statements: "?1 IS NULL OR machine_id = ?1" would keep SQLite from the machine's index.
constexpr Sql kSelectConflicts{
    "select conflicts",
    "SELECT topic, sample_id, machine_id, content_hash, stored_hash, writer, received_ns, document "
    "FROM conflicts ORDER BY received_ns DESC, id DESC"};
constexpr Sql kSelectMachineConflicts{
    "select conflicts of a machine",
    "SELECT topic, sample_id, machine_id, content_hash, stored_hash, writer, received_ns, document "
    "FROM conflicts WHERE machine_id = ?1 ORDER BY received_ns DESC, id DESC"};
constexpr Sql kSelectCheckWriters{"select the writers of a check",
                                  "SELECT (SELECT writer FROM requests WHERE request_id = ?1), "
                                  "(SELECT writer FROM measurement_sets WHERE request_id = ?1), "
                                  "(SELECT writer FROM results WHERE request_id = ?1)"};
constexpr Sql kCountCheckConflicts{
    "count conflicts of a check",
    "SELECT count(*) FROM conflicts WHERE sample_id = ?1 AND topic IN "
    "('ncqual/CheckRequest', 'ncqual/MeasurementSet', 'ncqual/CheckResult')"};

// Queries. history() has two forms so that each can walk its index newest first; a
// "?1 IS NULL OR machine_id = ?1" would keep SQLite from using the machine index.
constexpr Sql kHistoryAll{
    "select history",
    "SELECT request_id FROM checks WHERE sort_ns >= ?1 AND (?2 IS NULL OR kind = ?2) "
    "ORDER BY sort_ns DESC, request_id DESC LIMIT ?3"};
constexpr Sql kHistoryOfMachine{
    "select history of machine",
    "SELECT request_id FROM checks WHERE machine_id = ?4 AND sort_ns >= ?1 "
    "AND (?2 IS NULL OR kind = ?2) ORDER BY sort_ns DESC, request_id DESC LIMIT ?3"};

constexpr Sql kSelectRequest{
    "select request",
    "SELECT machine_id, kind, requested_by, time_ns, attempt, verifies_correction_of FROM requests "
    "WHERE request_id = ?1"};
// The counts are of the points measured: those stored and those retention deleted.
constexpr Sql kSelectMeasurementSet{
    "select measurement set",
    "SELECT machine_id, kind, instrument, frame, time_ns, error, "
    "thinned_touches + (SELECT count(*) FROM touches AS t WHERE t.request_id = m.request_id), "
    "thinned_tracker_points + "
    "(SELECT count(*) FROM tracker_points AS p WHERE p.request_id = m.request_id), "
    "points_thinned_ns, origin FROM measurement_sets AS m WHERE request_id = ?1"};
constexpr Sql kSelectRequestParameters{
    "select request parameters",
    "SELECT name, value, unit FROM request_parameters WHERE request_id = ?1 ORDER BY idx"};
constexpr Sql kSelectMeasurementParameters{
    "select measurement parameters",
    "SELECT name, value, unit FROM measurement_parameters WHERE request_id = ?1 ORDER BY idx"};
constexpr Sql kSelectTouches{
    "select touches",
    "SELECT feature, x_mm, y_mm, z_mm, w_mm, a_rad, c_rad, ux, uy, uz FROM touches "
    "WHERE request_id = ?1 ORDER BY idx"};
constexpr Sql kSelectTrackerPoints{
    "select tracker points",
    "SELECT label, x_mm, y_mm, z_mm, w_mm, a_rad, c_rad, measured_x_mm, measured_y_mm, "
    "measured_z_mm FROM tracker_points WHERE request_id = ?1 ORDER BY idx"};
constexpr Sql kSelectResult{
    "select result",
    "SELECT machine_id, kind, verdict, reason, time_ns, correction_target, produced_by, origin "
    "FROM results WHERE request_id = ?1"};
constexpr Sql kSelectMetrics{
    "select metrics",
    "SELECT name, value, unit, lower, upper, pass FROM metrics WHERE request_id = ?1 "
    "ORDER BY idx"};
constexpr Sql kSelectCauses{"select causes",
                            "SELECT cause FROM causes WHERE request_id = ?1 ORDER BY rank"};
constexpr Sql kSelectResultOffsets{
    "select result offsets",
    "SELECT name, value, unit FROM result_offsets WHERE request_id = ?1 ORDER BY idx"};

constexpr Sql kCountResults{"count results", "SELECT count(*) FROM results"};
constexpr Sql kCountResultsOfMachine{"count results of machine",
                                     "SELECT count(*) FROM results WHERE machine_id = ?1"};
constexpr Sql kLastPass{"last pass",
                        "SELECT max(time_ns) FROM results "
                        "WHERE machine_id = ?1 AND kind = ?2 AND verdict = 'PASS'"};
constexpr Sql kSelectMachines{"select machines",
                              "SELECT machine_id FROM machines ORDER BY machine_id"};
constexpr Sql kSelectMachine{
    "select machine", "SELECT first_seen_ns, last_seen_ns FROM machines WHERE machine_id = ?1"};
constexpr Sql kSelectLatestStatus{
    "select latest status",
    "SELECT request_id, state, last_kind, last_verdict, detail, time_ns FROM status_changes "
    "WHERE machine_id = ?1 ORDER BY time_ns DESC, id DESC LIMIT 1"};
constexpr Sql kSelectStatusHistory{
    "select status history",
    "SELECT request_id, state, last_kind, last_verdict, detail, time_ns FROM status_changes "
    "WHERE machine_id = ?1 ORDER BY time_ns, id"};
constexpr Sql kSelectInterventions{
    "select interventions",
    "SELECT intervention_id, kind, note, operator_name, time_ns FROM interventions "
    "WHERE machine_id = ?1 ORDER BY time_ns DESC, intervention_id DESC"};
constexpr Sql kSelectCompensations{
    "select compensations",
    "SELECT id, request_id, target, time_ns FROM compensations WHERE machine_id = ?1 "
    "ORDER BY time_ns DESC, id DESC"};
constexpr Sql kSelectCompensationOffsets{
    "select compensation offsets",
    "SELECT name, value, unit FROM compensation_offsets WHERE compensation_id = ?1 ORDER BY idx"};
constexpr Sql kSelectServices{
    "select services",
    "SELECT service, instance, machine_id, state, last_seen_ns, health, health_detail, "
    "outbox_depth, oldest_unacknowledged_ns FROM services "
    "ORDER BY service, instance"};

Verdict verdict_from(const std::string& name, const std::string& request_id) {
  if (auto verdict = parse_verdict(name)) return *verdict;
  throw StorageError("stored verdict '" + name + "' of request '" + request_id +
                     "' is not a verdict");
}

// The origin column (schema 11): NULL (stored before, or a sample that did not say) is Unknown.
DataOrigin origin_from(const std::optional<std::string>& name, const std::string& request_id) {
  if (!name) return DataOrigin::Unknown;
  if (auto origin = parse_data_origin(*name)) return *origin;
  throw StorageError("stored origin '" + *name + "' of request '" + request_id +
                     "' is not an origin");
}

MachineState state_from(const std::string& name, const std::string& machine_id) {
  if (auto state = parse_machine_state(name)) return *state;
  throw StorageError("stored state '" + name + "' of machine '" + machine_id +
                     "' is not a machine state");
}

}  // namespace

std::optional<CheckRequest> Database::Impl::load_request(const std::string& request_id) {
  Query q(statements, kSelectRequest);
  q.bind(request_id);
  if (!q.step()) return std::nullopt;
  CheckRequest request;
  request.request_id = request_id;
  request.machine_id = q.text(0);
  request.kind = kind_from(q.int64(1));
  request.requested_by = q.text(2);
  request.time_ns = q.int64(3);
  request.attempt = q.int32(4);
  request.verifies_correction_of = q.text(5);
  request.parameters = load_named_values(kSelectRequestParameters, request_id);
  return request;
}

std::vector<NamedValue> Database::Impl::load_named_values(const Sql& select,
                                                          const std::string& request_id) {
  std::vector<NamedValue> values;
  Query q(statements, select);
  q.bind(request_id);
  while (q.step()) values.push_back(NamedValue{q.text(0), q.real(1), q.text(2)});
  return values;
}

std::optional<MeasurementSet> Database::Impl::load_measurement_header(const std::string& request_id,
                                                                      MeasurementSummary* summary) {
  Query q(statements, kSelectMeasurementSet);
  q.bind(request_id);
  if (!q.step()) return std::nullopt;
  MeasurementSet set;
  set.request_id = request_id;
  set.machine_id = q.text(0);
  set.kind = kind_from(q.int64(1));
  set.instrument = q.text(2);
  set.frame = q.text(3);
  set.time_ns = q.int64(4);
  set.error = q.text(5);
  set.origin = origin_from(q.optional_text(9), request_id);
  set.parameters = load_named_values(kSelectMeasurementParameters, request_id);
  if (summary) {
    summary->instrument = set.instrument;
    summary->frame = set.frame;
    summary->time_ns = set.time_ns;
    summary->error = set.error;
    summary->touches = q.int64(6);
    summary->tracker_points = q.int64(7);
    summary->points_thinned_ns = q.optional_int64(8);
    summary->origin = set.origin;
  }
  return set;
}

std::optional<CheckResult> Database::Impl::load_result(const std::string& request_id) {
  CheckResult result;
  std::optional<std::string> correction_target;
  {
    Query q(statements, kSelectResult);
    q.bind(request_id);
    if (!q.step()) return std::nullopt;
    result.request_id = request_id;
    result.machine_id = q.text(0);
    result.kind = kind_from(q.int64(1));
    result.verdict = verdict_from(q.text(2), request_id);
    result.reason = q.text(3);
    result.time_ns = q.int64(4);
    correction_target = q.optional_text(5);
    result.produced_by = q.text(6);
    result.origin = origin_from(q.optional_text(7), request_id);
  }
  {
    Query q(statements, kSelectMetrics);
    q.bind(request_id);
    while (q.step()) {
      // NULL: a value that could not be evaluated (schema version 5), NaN as it was sent.
      const double value = q.is_null(1) ? std::nan("") : q.real(1);
      result.metrics.push_back(
          Metric{q.text(0), value, q.text(2), q.real(3), q.real(4), q.int64(5) != 0});
    }
  }
  {
    Query q(statements, kSelectCauses);
    q.bind(request_id);
    while (q.step()) result.likely_causes.push_back(q.text(0));
  }
  if (correction_target) {
    result.correction =
        Correction{*correction_target, load_named_values(kSelectResultOffsets, request_id)};
  }
  return result;
}

std::optional<CheckRecord> Database::Impl::load_record(const std::string& request_id) {
  CheckRecord record;
  record.request_id = request_id;
  record.request = load_request(request_id);
  MeasurementSummary summary;
  const auto measurement = load_measurement_header(request_id, &summary);
  if (measurement) record.measurement = summary;
  record.result = load_result(request_id);
  {
    Query q(statements, kCountCheckConflicts);
    q.bind(request_id);
    if (q.step()) record.conflicts = q.int64(0);
  }
  {
    Query q(statements, kSelectCheckWriters);
    q.bind(request_id);
    if (q.step()) {
      record.writers = {q.optional_text(0).value_or(""), q.optional_text(1).value_or(""),
                        q.optional_text(2).value_or("")};
    }
  }
  // Machine and kind from the result, else the request, else the measurement set; they agree
  // (note_check refuses a disagreement), the order only matters for which part is present.
  if (record.result) {
    record.machine_id = record.result->machine_id;
    record.kind = record.result->kind;
  } else if (record.request) {
    record.machine_id = record.request->machine_id;
    record.kind = record.request->kind;
  } else if (measurement) {
    record.machine_id = measurement->machine_id;
    record.kind = measurement->kind;
  } else {
    return std::nullopt;
  }
  return record;
}

DataOrigin origin_of(const CheckRecord& record) {
  if (record.result && record.result->origin != DataOrigin::Unknown) return record.result->origin;
  if (record.measurement) return record.measurement->origin;
  return DataOrigin::Unknown;
}

std::vector<CheckRecord> Database::history(const HistoryQuery& query) {
  return impl_->read([&] {
    std::vector<std::string> ids;
    {
      Query q(impl_->statements, query.machine_id ? kHistoryOfMachine : kHistoryAll);
      std::optional<std::int64_t> kind;
      if (query.kind) kind = code(*query.kind);
      // LIMIT -1 is SQLite's "no limit".
      const std::int64_t limit = query.limit > 0 ? query.limit : -1;
      q.bind(query.since_ns, kind, limit);
      if (query.machine_id) q.bind_at(4, *query.machine_id);
      while (q.step()) ids.push_back(q.text(0));
    }
    std::vector<CheckRecord> records;
    records.reserve(ids.size());
    for (const auto& id : ids) {
      if (auto record = impl_->load_record(id)) records.push_back(std::move(*record));
    }
    return records;
  });
}

std::optional<CheckRecord> Database::find_check(const std::string& request_id) {
  return impl_->read([&] { return impl_->load_record(request_id); });
}

std::optional<MeasurementSet> Database::load_measurement_set(const std::string& request_id) {
  return impl_->read([&]() -> std::optional<MeasurementSet> {
    auto set = impl_->load_measurement_header(request_id, nullptr);
    if (!set) return std::nullopt;
    {
      Query q(impl_->statements, kSelectTouches);
      q.bind(request_id);
      while (q.step()) {
        Touch touch;
        touch.feature = q.text(0);
        touch.axes = AxisPosition{q.real(1), q.real(2), q.real(3), q.real(4), q.real(5), q.real(6)};
        touch.approach = Eigen::Vector3d(q.real(7), q.real(8), q.real(9));
        set->touches.push_back(std::move(touch));
      }
    }
    {
      Query q(impl_->statements, kSelectTrackerPoints);
      q.bind(request_id);
      while (q.step()) {
        TrackerPoint point;
        point.label = q.text(0);
        point.commanded =
            AxisPosition{q.real(1), q.real(2), q.real(3), q.real(4), q.real(5), q.real(6)};
        point.measured_mm = Eigen::Vector3d(q.real(7), q.real(8), q.real(9));
        set->tracker_points.push_back(std::move(point));
      }
    }
    return set;
  });
}

std::int64_t Database::count_results(std::optional<std::string> machine_id) {
  Query q(impl_->statements, machine_id ? kCountResultsOfMachine : kCountResults);
  if (machine_id) q.bind(*machine_id);
  return q.step() ? q.int64(0) : 0;
}

std::vector<std::string> Database::machines() {
  std::vector<std::string> ids;
  Query q(impl_->statements, kSelectMachines);
  while (q.step()) ids.push_back(q.text(0));
  return ids;
}

std::optional<MachineRecord> Database::machine(const std::string& machine_id) {
  Query q(impl_->statements, kSelectMachine);
  q.bind(machine_id);
  if (!q.step()) return std::nullopt;
  return MachineRecord{machine_id, q.int64(0), q.int64(1)};
}

std::optional<std::int64_t> Database::last_pass_ns(const std::string& machine_id, CheckKind kind) {
  Query q(impl_->statements, kLastPass);
  q.bind(machine_id, static_cast<std::int64_t>(kind));
  if (!q.step() || q.is_null(0)) return std::nullopt;
  return q.int64(0);
}

namespace {
// A row of kSelectLatestStatus or kSelectStatusHistory.
MachineStatus status_row(Query& q, const std::string& machine_id) {
  MachineStatus status;
  status.machine_id = machine_id;
  status.request_id = q.text(0);
  status.state = state_from(q.text(1), machine_id);
  if (auto kind = q.optional_int64(2)) status.last_kind = kind_from(*kind);
  if (auto verdict = q.optional_text(3)) {
    status.last_verdict = verdict_from(*verdict, status.request_id);
  }
  status.detail = q.text(4);
  status.time_ns = q.int64(5);
  return status;
}
}  // namespace

std::optional<MachineStatus> Database::latest_status(const std::string& machine_id) {
  Query q(impl_->statements, kSelectLatestStatus);
  q.bind(machine_id);
  if (!q.step()) return std::nullopt;
  return status_row(q, machine_id);
}

std::vector<MachineStatus> Database::status_history(const std::string& machine_id) {
  Query q(impl_->statements, kSelectStatusHistory);
  q.bind(machine_id);
  std::vector<MachineStatus> list;
  while (q.step()) list.push_back(status_row(q, machine_id));
  return list;
}

std::vector<Intervention> Database::interventions(const std::string& machine_id) {
  std::vector<Intervention> list;
  Query q(impl_->statements, kSelectInterventions);
  q.bind(machine_id);
  while (q.step()) {
    Intervention intervention;
    intervention.machine_id = machine_id;
    intervention.intervention_id = q.text(0);
    intervention.kind = kind_from(q.int64(1));
    intervention.note = q.text(2);
    intervention.operator_name = q.text(3);
    intervention.time_ns = q.int64(4);
    list.push_back(std::move(intervention));
  }
  return list;
}

std::vector<Compensation> Database::compensations(const std::string& machine_id) {
  return impl_->read([&] {
    std::vector<std::pair<std::int64_t, Compensation>> rows;
    {
      Query q(impl_->statements, kSelectCompensations);
      q.bind(machine_id);
      while (q.step()) {
        Compensation compensation;
        compensation.machine_id = machine_id;
        compensation.request_id = q.text(1);
        compensation.correction.target = q.text(2);
        compensation.time_ns = q.int64(3);
        rows.emplace_back(q.int64(0), std::move(compensation));
      }
    }
    std::vector<Compensation> list;
    list.reserve(rows.size());
    for (auto& [id, compensation] : rows) {
      Query q(impl_->statements, kSelectCompensationOffsets);
      q.bind(id);
      while (q.step()) {
        compensation.correction.offsets.push_back(NamedValue{q.text(0), q.real(1), q.text(2)});
      }
      list.push_back(std::move(compensation));
    }
    return list;
  });
}

std::vector<ConflictRecord> Database::conflicts(const std::optional<std::string>& machine_id) {
  std::vector<ConflictRecord> list;
  Query q(impl_->statements, machine_id ? kSelectMachineConflicts : kSelectConflicts);
  if (machine_id) q.bind(*machine_id);
  while (q.step()) {
    list.push_back(ConflictRecord{q.text(0), q.text(1), q.text(2), q.text(3), q.text(4), q.text(5),
                                  q.int64(6), q.text(7)});
  }
  return list;
}

std::vector<Heartbeat> Database::services() {
  std::vector<Heartbeat> list;
  Query q(impl_->statements, kSelectServices);
  while (q.step()) {
    list.push_back(Heartbeat{q.text(0), q.text(1), q.text(2), q.text(3), q.int64(4), q.text(5),
                             q.text(6), q.int64(7), q.int64(8)});
  }
  return list;
}

}  // namespace ncqual::storage
