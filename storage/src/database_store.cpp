// SPDX-License-Identifier: Apache-2.0
// Database's stores: each sample in one write transaction, idempotent on its identity, one of
// other content kept beside the first as a conflict; and the machines and checks they note.
#include "ncqual/storage/database.hpp"

#include "database_impl.hpp"
#include "sqlite.hpp"
#include "validate.hpp"

#include "ncqual/common/json.hpp"

#include <cmath>
#include <optional>
#include <string>

namespace ncqual::storage {
namespace {

using sqlite::Query;
using sqlite::Sql;

// Inserts of a sample's identity row are ON CONFLICT DO NOTHING on exactly that identity, so only
// a duplicate is skipped; any other constraint still fails.
constexpr Sql kUpsertMachine{
    "upsert machine",
    "INSERT INTO machines (machine_id, first_seen_ns, last_seen_ns) VALUES (?1, ?2, ?2) "
    "ON CONFLICT (machine_id) DO UPDATE SET "
    "first_seen_ns = min(first_seen_ns, excluded.first_seen_ns), "
    "last_seen_ns = max(last_seen_ns, excluded.last_seen_ns)"};

constexpr Sql kSelectCheckIdentity{"select check identity",
                                   "SELECT machine_id, kind FROM checks WHERE request_id = ?1"};
constexpr Sql kUpsertCheckRequested{
    "upsert check (request)",
    "INSERT INTO checks (request_id, machine_id, kind, requested_at_ns) VALUES (?1, ?2, ?3, ?4) "
    "ON CONFLICT (request_id) DO UPDATE SET requested_at_ns = excluded.requested_at_ns"};
constexpr Sql kUpsertCheckMeasured{
    "upsert check (measurement)",
    "INSERT INTO checks (request_id, machine_id, kind, measured_at_ns) VALUES (?1, ?2, ?3, ?4) "
    "ON CONFLICT (request_id) DO UPDATE SET measured_at_ns = excluded.measured_at_ns"};
constexpr Sql kUpsertCheckResult{
    "upsert check (result)",
    "INSERT INTO checks (request_id, machine_id, kind, result_at_ns) VALUES (?1, ?2, ?3, ?4) "
    "ON CONFLICT (request_id) DO UPDATE SET result_at_ns = excluded.result_at_ns"};

constexpr Sql kInsertRequest{
    "insert request",
    "INSERT INTO requests (request_id, machine_id, kind, kind_name, requested_by, time_ns, attempt,"
    " verifies_correction_of, content_hash, writer) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, "
    "?10)"
    " ON CONFLICT (request_id) DO NOTHING"};

constexpr Sql kInsertMeasurementSet{
    "insert measurement set",
    "INSERT INTO measurement_sets (request_id, machine_id, kind, instrument, frame, time_ns, error,"
    " content_hash, writer, origin) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)"
    " ON CONFLICT (request_id) DO NOTHING"};
constexpr Sql kInsertRequestParameter{
    "insert request parameter",
    "INSERT INTO request_parameters (request_id, idx, name, value, unit) "
    "VALUES (?1, ?2, ?3, ?4, ?5)"};
constexpr Sql kInsertMeasurementParameter{
    "insert measurement parameter",
    "INSERT INTO measurement_parameters (request_id, idx, name, value, unit) "
    "VALUES (?1, ?2, ?3, ?4, ?5)"};
constexpr Sql kInsertTouch{
    "insert touch",
    "INSERT INTO touches (request_id, idx, feature, x_mm, y_mm, z_mm, w_mm, a_rad, c_rad, "
    "ux, uy, uz) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12)"};
constexpr Sql kInsertTrackerPoint{
    "insert tracker point",
    "INSERT INTO tracker_points (request_id, idx, label, x_mm, y_mm, z_mm, w_mm, a_rad, c_rad, "
    "measured_x_mm, measured_y_mm, measured_z_mm) "
    "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12)"};

constexpr Sql kInsertResult{
    "insert result",
    "INSERT INTO results (request_id, machine_id, kind, verdict, reason, time_ns, "
    "correction_target, produced_by, content_hash, writer, origin) "
    "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11) ON CONFLICT (request_id) DO NOTHING"};
constexpr Sql kInsertMetric{
    "insert metric",
    "INSERT INTO metrics (request_id, idx, name, value, unit, lower, upper, pass) "
    "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)"};
constexpr Sql kInsertCause{"insert cause",
                           "INSERT INTO causes (request_id, rank, cause) VALUES (?1, ?2, ?3)"};
constexpr Sql kInsertResultOffset{
    "insert result offset",
    "INSERT INTO result_offsets (request_id, idx, name, value, unit) VALUES (?1, ?2, ?3, ?4, ?5)"};

constexpr Sql kInsertStatus{
    "insert status change",
    "INSERT INTO status_changes (machine_id, request_id, state, last_kind, last_verdict, detail, "
    "time_ns, content_hash, writer) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9) "
    "ON CONFLICT (machine_id, time_ns, state, request_id) DO NOTHING"};

constexpr Sql kInsertIntervention{
    "insert intervention",
    "INSERT INTO interventions (intervention_id, machine_id, kind, note, operator_name, time_ns, "
    "content_hash, writer) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8) "
    "ON CONFLICT (intervention_id) DO NOTHING"};

constexpr Sql kInsertCompensation{
    "insert compensation",
    "INSERT INTO compensations (request_id, target, machine_id, time_ns, content_hash, writer) "
    "VALUES (?1, ?2, ?3, ?4, ?5, ?6) ON CONFLICT (request_id, target) DO NOTHING"};

// The content hash a sample was stored with, and its writer, by its identity (NULL: stored
// before version 4).
constexpr Sql kRequestHash{"read request hash",
                           "SELECT content_hash, writer FROM requests WHERE request_id = ?1"};
constexpr Sql kMeasurementSetHash{
    "read measurement set hash",
    "SELECT content_hash, writer FROM measurement_sets WHERE request_id = ?1"};
constexpr Sql kResultHash{"read result hash",
                          "SELECT content_hash, writer FROM results WHERE request_id = ?1"};
constexpr Sql kStatusHash{
    "read status change hash",
    "SELECT content_hash, writer FROM status_changes WHERE machine_id = ?1 AND "
    "time_ns = ?2 AND state = ?3 AND request_id = ?4"};
constexpr Sql kInterventionHash{
    "read intervention hash",
    "SELECT content_hash, writer FROM interventions WHERE intervention_id = ?1"};
constexpr Sql kCompensationHash{
    "read compensation hash",
    "SELECT content_hash, writer FROM compensations WHERE request_id = ?1 AND "
    "target = ?2"};
constexpr Sql kInsertConflict{
    "insert conflict",
    "INSERT INTO conflicts (topic, sample_id, machine_id, content_hash, stored_hash, writer, "
    "received_ns, document) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8) "
    "ON CONFLICT (topic, sample_id, content_hash) DO NOTHING"};
constexpr Sql kInsertCompensationOffset{
    "insert compensation offset",
    "INSERT INTO compensation_offsets (compensation_id, idx, name, value, unit) "
    "VALUES (?1, ?2, ?3, ?4, ?5)"};

// Heartbeats: insert when new, else move forward. Two statements rather than one upsert because
// the caller needs to know whether the instance is new, which an upsert does not tell.
constexpr Sql kInsertService{
    "insert service",
    "INSERT INTO services (service, instance, machine_id, state, first_seen_ns, last_seen_ns, "
    "health, health_detail, outbox_depth, oldest_unacknowledged_ns) "
    "VALUES (?1, ?2, ?3, ?4, ?5, ?5, ?6, ?7, ?8, ?9) ON CONFLICT (service, instance) DO NOTHING"};
constexpr Sql kUpdateService{"update service",
                             "UPDATE services SET machine_id = ?3, state = ?4, last_seen_ns = ?5, "
                             "health = ?6, health_detail = ?7, outbox_depth = ?8, "
                             "oldest_unacknowledged_ns = ?9 "
                             "WHERE service = ?1 AND instance = ?2 AND last_seen_ns <= ?5"};

std::string quoted(const std::string& text) { return "'" + text + "'"; }

// The origin column (schema 11): 'measured', 'simulated', or NULL when the sample does not say.
std::optional<std::string_view> origin_column(DataOrigin origin) {
  if (origin == DataOrigin::Unknown) return std::nullopt;
  return to_string(origin);
}

}  // namespace

template <typename Model, typename... Identity>
StoreResult Database::Impl::already_stored(const Sql& select_hash, const char* topic,
                                           const Model& sample, const Origin& origin,
                                           const Identity&... identity) {
  std::optional<std::string> stored_hash;
  std::string stored_writer;
  {
    Query q(statements, select_hash);
    q.bind(identity...);
    if (q.step()) {
      stored_hash = q.optional_text(0);
      stored_writer = q.optional_text(1).value_or("");
    }
  }
  if (!stored_hash || origin.content_hash.empty() || *stored_hash == origin.content_hash) {
    return StoreResult{StoreOutcome::Duplicate, stored_hash.value_or(""), false, stored_writer};
  }
  Query insert(statements, kInsertConflict);
  insert
      .bind(topic, sample_id_of(sample), sample.machine_id, origin.content_hash, *stored_hash,
            origin.writer, origin.received_ns, nlohmann::json(sample).dump())
      .run();
  return StoreResult{StoreOutcome::Conflict, *stored_hash, insert.changes() > 0, stored_writer};
}

void Database::Impl::touch_machine(const std::string& machine_id, std::int64_t time_ns) {
  Query(statements, kUpsertMachine).bind(machine_id, time_ns).run();
}

void Database::Impl::note_check(const Sql& upsert, const char* type, const std::string& request_id,
                                const std::string& machine_id, CheckKind kind,
                                std::int64_t time_ns) {
  {
    Query existing(statements, kSelectCheckIdentity);
    existing.bind(request_id);
    if (existing.step()) {
      const std::string stored_machine = existing.text(0);
      const CheckKind stored_kind = kind_from(existing.int64(1));
      if (stored_machine != machine_id) {
        throw StorageError(std::string(type) + ".machine_id " + quoted(machine_id) +
                           " differs from " + quoted(stored_machine) +
                           " already stored for request " + quoted(request_id));
      }
      if (stored_kind != kind) {
        throw StorageError(std::string(type) + ".kind " + std::string(to_string(kind)) +
                           " differs from " + std::string(to_string(stored_kind)) +
                           " already stored for request " + quoted(request_id));
      }
    }
  }
  Query(statements, upsert).bind(request_id, machine_id, code(kind), time_ns).run();
}

void Database::Impl::store_named_values(const Sql& insert, const std::string& request_id,
                                        const std::vector<NamedValue>& values) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    const NamedValue& p = values[i];
    Query(statements, insert)
        .bind(request_id, static_cast<std::int64_t>(i), p.name, p.value, p.unit)
        .run();
  }
}

StoreResult Database::store(const CheckRequest& request, const Origin& origin) {
  validate::check(request);
  return impl_->write("store CheckRequest " + quoted(request.request_id), [&] {
    {
      Query insert(impl_->statements, kInsertRequest);
      insert.bind(request.request_id, request.machine_id, code(request.kind),
                  to_string(request.kind), request.requested_by, request.time_ns, request.attempt,
                  request.verifies_correction_of, origin.hash(), origin.writer_guid());
      insert.run();
      if (insert.changes() == 0) {
        return impl_->already_stored(kRequestHash, "ncqual/CheckRequest", request, origin,
                                     request.request_id);
      }
    }
    impl_->store_named_values(kInsertRequestParameter, request.request_id, request.parameters);
    impl_->note_check(kUpsertCheckRequested, "CheckRequest", request.request_id, request.machine_id,
                      request.kind, request.time_ns);
    impl_->touch_machine(request.machine_id, request.time_ns);
    return StoreResult{};
  });
}

StoreResult Database::store(const MeasurementSet& set, const Origin& origin) {
  validate::check(set);
  return impl_->write("store MeasurementSet " + quoted(set.request_id), [&] {
    {
      Query insert(impl_->statements, kInsertMeasurementSet);
      insert.bind(set.request_id, set.machine_id, code(set.kind), set.instrument, set.frame,
                  set.time_ns, set.error, origin.hash(), origin.writer_guid(),
                  origin_column(set.origin));
      insert.run();
      if (insert.changes() == 0) {
        return impl_->already_stored(kMeasurementSetHash, "ncqual/MeasurementSet", set, origin,
                                     set.request_id);
      }
    }
    impl_->store_named_values(kInsertMeasurementParameter, set.request_id, set.parameters);
    for (std::size_t i = 0; i < set.touches.size(); ++i) {
      const Touch& t = set.touches[i];
      Query(impl_->statements, kInsertTouch)
          .bind(set.request_id, static_cast<std::int64_t>(i), t.feature, t.axes.x_mm, t.axes.y_mm,
                t.axes.z_mm, t.axes.w_mm, t.axes.a_rad, t.axes.c_rad, t.approach.x(),
                t.approach.y(), t.approach.z())
          .run();
    }
    for (std::size_t i = 0; i < set.tracker_points.size(); ++i) {
      const TrackerPoint& p = set.tracker_points[i];
      Query(impl_->statements, kInsertTrackerPoint)
          .bind(set.request_id, static_cast<std::int64_t>(i), p.label, p.commanded.x_mm,
                p.commanded.y_mm, p.commanded.z_mm, p.commanded.w_mm, p.commanded.a_rad,
                p.commanded.c_rad, p.measured_mm.x(), p.measured_mm.y(), p.measured_mm.z())
          .run();
    }
    impl_->note_check(kUpsertCheckMeasured, "MeasurementSet", set.request_id, set.machine_id,
                      set.kind, set.time_ns);
    impl_->touch_machine(set.machine_id, set.time_ns);
    return StoreResult{};
  });
}

StoreResult Database::store(const CheckResult& result, const Origin& origin) {
  validate::check(result);
  return impl_->write("store CheckResult " + quoted(result.request_id), [&] {
    {
      std::optional<std::string> target;
      if (result.correction) target = result.correction->target;
      Query insert(impl_->statements, kInsertResult);
      insert.bind(result.request_id, result.machine_id, code(result.kind),
                  to_string(result.verdict), result.reason, result.time_ns, target,
                  result.produced_by, origin.hash(), origin.writer_guid(),
                  origin_column(result.origin));
      insert.run();
      if (insert.changes() == 0) {
        return impl_->already_stored(kResultHash, "ncqual/CheckResult", result, origin,
                                     result.request_id);
      }
    }
    for (std::size_t i = 0; i < result.metrics.size(); ++i) {
      const Metric& m = result.metrics[i];
      Query(impl_->statements, kInsertMetric)
          .bind(result.request_id, static_cast<std::int64_t>(i), m.name,
                std::isfinite(m.value) ? std::optional<double>(m.value) : std::nullopt, m.unit,
                m.lower, m.upper, m.pass)
          .run();
    }
    for (std::size_t i = 0; i < result.likely_causes.size(); ++i) {
      Query(impl_->statements, kInsertCause)
          .bind(result.request_id, static_cast<std::int64_t>(i), result.likely_causes[i])
          .run();
    }
    if (result.correction) {
      impl_->store_named_values(kInsertResultOffset, result.request_id, result.correction->offsets);
    }
    impl_->note_check(kUpsertCheckResult, "CheckResult", result.request_id, result.machine_id,
                      result.kind, result.time_ns);
    impl_->touch_machine(result.machine_id, result.time_ns);
    return StoreResult{};
  });
}

StoreResult Database::store(const MachineStatus& status, const Origin& origin) {
  validate::check(status);
  return impl_->write("store MachineStatus of " + quoted(status.machine_id), [&] {
    std::optional<std::int64_t> last_kind;
    if (status.last_kind) last_kind = code(*status.last_kind);
    std::optional<std::string_view> last_verdict;
    if (status.last_verdict) last_verdict = to_string(*status.last_verdict);
    Query insert(impl_->statements, kInsertStatus);
    insert.bind(status.machine_id, status.request_id, to_string(status.state), last_kind,
                last_verdict, status.detail, status.time_ns, origin.hash(), origin.writer_guid());
    insert.run();
    if (insert.changes() == 0) {
      return impl_->already_stored(kStatusHash, "ncqual/MachineStatus", status, origin,
                                   status.machine_id, status.time_ns, to_string(status.state),
                                   status.request_id);
    }
    impl_->touch_machine(status.machine_id, status.time_ns);
    return StoreResult{};
  });
}

StoreResult Database::store(const Intervention& intervention, const Origin& origin) {
  validate::check(intervention);
  return impl_->write("store Intervention " + quoted(intervention.intervention_id), [&] {
    Query insert(impl_->statements, kInsertIntervention);
    insert.bind(intervention.intervention_id, intervention.machine_id, code(intervention.kind),
                intervention.note, intervention.operator_name, intervention.time_ns, origin.hash(),
                origin.writer_guid());
    insert.run();
    if (insert.changes() == 0) {
      return impl_->already_stored(kInterventionHash, "ncqual/Intervention", intervention, origin,
                                   intervention.intervention_id);
    }
    impl_->touch_machine(intervention.machine_id, intervention.time_ns);
    return StoreResult{};
  });
}

StoreResult Database::store(const Compensation& compensation, const Origin& origin) {
  validate::check(compensation);
  const Correction& correction = compensation.correction;
  return impl_->write(
      "store Compensation " + quoted(compensation.request_id) + " for " + quoted(correction.target),
      [&] {
        std::int64_t id = 0;
        {
          Query insert(impl_->statements, kInsertCompensation);
          insert.bind(compensation.request_id, correction.target, compensation.machine_id,
                      compensation.time_ns, origin.hash(), origin.writer_guid());
          insert.run();
          if (insert.changes() == 0) {
            return impl_->already_stored(kCompensationHash, "ncqual/Compensation", compensation,
                                         origin, compensation.request_id, correction.target);
          }
          id = sqlite3_last_insert_rowid(impl_->db.get());
        }
        for (std::size_t i = 0; i < correction.offsets.size(); ++i) {
          const NamedValue& offset = correction.offsets[i];
          Query(impl_->statements, kInsertCompensationOffset)
              .bind(id, static_cast<std::int64_t>(i), offset.name, offset.value, offset.unit)
              .run();
        }
        impl_->touch_machine(compensation.machine_id, compensation.time_ns);
        return StoreResult{};
      });
}

bool Database::store(const Heartbeat& heartbeat) {
  validate::check(heartbeat);
  return impl_->write(
      "store Heartbeat of " + quoted(heartbeat.service) + " " + quoted(heartbeat.instance), [&] {
        bool inserted = false;
        {
          Query insert(impl_->statements, kInsertService);
          insert.bind(heartbeat.service, heartbeat.instance, heartbeat.machine_id, heartbeat.state,
                      heartbeat.time_ns, heartbeat.health, heartbeat.health_detail,
                      heartbeat.outbox_depth, heartbeat.oldest_unacknowledged_ns);
          insert.run();
          inserted = insert.changes() == 1;
        }
        if (!inserted) {
          Query(impl_->statements, kUpdateService)
              .bind(heartbeat.service, heartbeat.instance, heartbeat.machine_id, heartbeat.state,
                    heartbeat.time_ns, heartbeat.health, heartbeat.health_detail,
                    heartbeat.outbox_depth, heartbeat.oldest_unacknowledged_ns)
              .run();
        }
        // Plant-wide services (scheduler, solver, historian) name no machine.
        if (!heartbeat.machine_id.empty()) {
          impl_->touch_machine(heartbeat.machine_id, heartbeat.time_ns);
        }
        return inserted;
      });
}

}  // namespace ncqual::storage
