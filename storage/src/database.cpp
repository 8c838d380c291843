// SPDX-License-Identifier: Apache-2.0
#include "ncqual/storage/database.hpp"

#include "access.hpp"
#include "open.hpp"
#include "schema.hpp"
#include "sqlite.hpp"
#include "validate.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/common/json.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <algorithm>
#include <filesystem>
#include <limits>
#include <thread>
#include <utility>

namespace ncqual::storage {
namespace {

using sqlite::Query;
using sqlite::Sql;
using sqlite::Transaction;

// A writer waits this long for another writer's transaction before giving up with SQLITE_BUSY.
// Transactions here last milliseconds; 5 s only runs out when something is badly stuck.
constexpr int kBusyTimeoutMs = 5000;

// STRICT tables and the generated sort column need SQLite 3.37 (Debian 12 has 3.40).
constexpr int kMinimumSqliteVersion = 3037000;

// --- statements --------------------------------------------------------------------------------
// Every statement the library runs after opening, each prepared once per connection (the cache
// keys on these constants). Inserts of a sample's identity row are ON CONFLICT DO NOTHING on
// exactly that identity, so only a duplicate is skipped; any other constraint still fails.

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
    " content_hash, writer) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)"
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
    "correction_target, produced_by, content_hash, writer) "
    "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10) ON CONFLICT (request_id) DO NOTHING"};
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
    "points_thinned_ns FROM measurement_sets AS m WHERE request_id = ?1"};
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
    "SELECT machine_id, kind, verdict, reason, time_ns, correction_target, produced_by "
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

// Retention (thin_points). The sets before a time whose points are still all stored, in time
// order from a cursor (time_ns, request_id), with the points each holds; a set without points is
// passed over (and never marked), so the cursor moves on through them.
constexpr Sql kSetsToThin{
    "select measurement sets to thin",
    "SELECT request_id, time_ns, "
    "(SELECT count(*) FROM touches AS t WHERE t.request_id = m.request_id), "
    "(SELECT count(*) FROM tracker_points AS p WHERE p.request_id = m.request_id) "
    "FROM measurement_sets AS m WHERE time_ns < ?1 AND points_thinned_ns IS NULL "
    "AND (time_ns, request_id) > (?2, ?3) ORDER BY time_ns, request_id LIMIT ?4"};
constexpr Sql kCountToThin{
    "count points to thin",
    "SELECT count(*), coalesce(sum(t), 0), coalesce(sum(p), 0), min(time_ns), max(time_ns) FROM "
    "(SELECT time_ns, "
    "(SELECT count(*) FROM touches AS t WHERE t.request_id = m.request_id) AS t, "
    "(SELECT count(*) FROM tracker_points AS p WHERE p.request_id = m.request_id) AS p "
    "FROM measurement_sets AS m WHERE time_ns < ?1 AND points_thinned_ns IS NULL) "
    "WHERE t + p > 0"};
constexpr Sql kDeleteTouches{"delete touches", "DELETE FROM touches WHERE request_id = ?1"};
constexpr Sql kDeleteTrackerPoints{"delete tracker points",
                                   "DELETE FROM tracker_points WHERE request_id = ?1"};
constexpr Sql kMarkThinned{
    "mark a measurement set thinned",
    "UPDATE measurement_sets SET points_thinned_ns = ?2, thinned_touches = thinned_touches + ?3, "
    "thinned_tracker_points = thinned_tracker_points + ?4 WHERE request_id = ?1"};

constexpr Sql kIntegrityCheck{"integrity check", "PRAGMA integrity_check"};
constexpr Sql kQuickCheck{"quick check", "PRAGMA quick_check"};
constexpr Sql kCopyTo{"copy the database", "VACUUM INTO ?1"};
constexpr Sql kJournalMode{"read journal mode", "PRAGMA journal_mode"};
constexpr Sql kSynchronous{"read synchronous", "PRAGMA synchronous"};
constexpr Sql kForeignKeys{"read foreign keys", "PRAGMA foreign_keys"};
constexpr Sql kBusyTimeout{"read busy timeout", "PRAGMA busy_timeout"};
constexpr Sql kUserVersion{"read user version", "PRAGMA user_version"};

// --- conversions -------------------------------------------------------------------------------

std::int64_t code(CheckKind kind) { return static_cast<std::int64_t>(kind); }

// Kinds are read back as numbers without a range check: a newer build may have appended kinds
// this one does not know (to_string names them "unknown"), and a reader should still list them.
CheckKind kind_from(std::int64_t number) { return static_cast<CheckKind>(number); }

Verdict verdict_from(const std::string& name, const std::string& request_id) {
  if (auto verdict = parse_verdict(name)) return *verdict;
  throw StorageError("stored verdict '" + name + "' of request '" + request_id +
                     "' is not a verdict");
}

MachineState state_from(const std::string& name, const std::string& machine_id) {
  if (auto state = parse_machine_state(name)) return *state;
  throw StorageError("stored state '" + name + "' of machine '" + machine_id +
                     "' is not a machine state");
}

std::string quoted(const std::string& text) { return "'" + text + "'"; }

}  // namespace

// --- Impl --------------------------------------------------------------------------------------

struct Database::Impl {
  Impl(sqlite::Connection connection, std::string path, bool read_only)
      : db(std::move(connection)),
        statements(db.get()),
        path(std::move(path)),
        read_only(read_only) {}

  // Declared first, destroyed last: the cached statements must be finalized before it closes.
  sqlite::Connection db;
  sqlite::StatementCache statements;
  std::string path;
  bool read_only;
  // The file opened (st_dev, st_ino), to tell when the path no longer names it.
  std::optional<std::pair<dev_t, ino_t>> identity;

  // Runs `body` in one write transaction; SQLite failures get `what` (e.g. "store CheckResult
  // 'r-17'") in front so the historian's log says which sample failed.
  template <typename Body>
  auto write(const std::string& what, Body&& body) {
    if (read_only) {
      throw StorageError(what + ": the database '" + path + "' is open read-only", SQLITE_READONLY);
    }
    try {
      Transaction transaction(statements, Transaction::Mode::Write);
      auto stored = body();
      // A duplicate changed nothing; committing it costs nothing either and keeps one path.
      transaction.commit();
      return stored;
    } catch (const StorageError& error) {
      if (error.sqlite_code() == 0) throw;
      throw StorageError(what + ": " + error.what(), error.sqlite_code());
    }
  }

  // Runs `body` in one read transaction: every query of a joined read sees the same snapshot
  // while the historian keeps writing.
  template <typename Body>
  auto read(Body&& body) {
    Transaction transaction(statements, Transaction::Mode::Read);
    auto value = body();
    transaction.commit();
    return value;
  }

  // A sample whose identity is already stored: the same content is a duplicate; other content is
  // a conflict, kept whole in `conflicts` beside the first (which stays as it is). A row stored
  // before version 4, or a caller without a hash, cannot be compared: a duplicate.
  template <typename Model, typename... Identity>
  StoreResult already_stored(const Sql& select_hash, const char* topic, const Model& sample,
                             const Origin& origin, const Identity&... identity) {
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

  void touch_machine(const std::string& machine_id, std::int64_t time_ns) {
    Query(statements, kUpsertMachine).bind(machine_id, time_ns).run();
  }

  // Records that a part of check `request_id` arrived. A request, its measurement set and its
  // result must agree on machine and kind: a disagreement is a producer's bug, refused loudly
  // rather than merged into one check with two machines.
  void note_check(const Sql& upsert, const char* type, const std::string& request_id,
                  const std::string& machine_id, CheckKind kind, std::int64_t time_ns) {
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

  std::optional<CheckRequest> load_request(const std::string& request_id) {
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

  // Named values of a request's row in a (request_id, idx, name, value, unit) table: request and
  // measurement parameters, result offsets.
  void store_named_values(const Sql& insert, const std::string& request_id,
                          const std::vector<NamedValue>& values) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      const NamedValue& p = values[i];
      Query(statements, insert)
          .bind(request_id, static_cast<std::int64_t>(i), p.name, p.value, p.unit)
          .run();
    }
  }

  std::vector<NamedValue> load_named_values(const Sql& select, const std::string& request_id) {
    std::vector<NamedValue> values;
    Query q(statements, select);
    q.bind(request_id);
    while (q.step()) values.push_back(NamedValue{q.text(0), q.real(1), q.text(2)});
    return values;
  }

  // The header of a measurement set (with its parameters); the counts go into `summary`.
  std::optional<MeasurementSet> load_measurement_header(const std::string& request_id,
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
    set.parameters = load_named_values(kSelectMeasurementParameters, request_id);
    if (summary) {
      summary->instrument = set.instrument;
      summary->frame = set.frame;
      summary->time_ns = set.time_ns;
      summary->error = set.error;
      summary->touches = q.int64(6);
      summary->tracker_points = q.int64(7);
      summary->points_thinned_ns = q.optional_int64(8);
    }
    return set;
  }

  std::optional<CheckResult> load_result(const std::string& request_id) {
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

  std::optional<CheckRecord> load_record(const std::string& request_id) {
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

  std::string pragma_text(const Sql& sql) {
    Query q(statements, sql);
    if (!q.step()) return {};
    return q.text(0);
  }

  std::int64_t pragma_int(const Sql& sql) {
    Query q(statements, sql);
    if (!q.step()) return 0;
    return q.int64(0);
  }
};

// --- opening -----------------------------------------------------------------------------------

namespace {

void check_sqlite_version() {
  if (sqlite3_libversion_number() < kMinimumSqliteVersion) {
    throw StorageError(std::string("SQLite ") + sqlite3_libversion() +
                       " is too old: ncqual needs 3.37 or newer");
  }
}

// Before anything is changed: a file marked as someone else's, or holding tables without any mark
// of ours, is not adopted (migration 1 would otherwise add our tables to it and mark it ours).
void refuse_foreign_file(sqlite3* db, const std::string& path) {
  const std::int32_t id = schema::application_id(db);
  if (id == schema::kApplicationId) return;
  if (id == 0 && schema::user_version(db) == 0 &&
      sqlite::query_text(db, "count schema objects", "SELECT count(*) FROM sqlite_schema") == "0") {
    return;  // a new or empty file: ours to create
  }
  throw StorageError("'" + path + "' is not an ncqual historian database (application_id " +
                     std::to_string(id) + ")");
}

void check_application_id(sqlite3* db, const std::string& path) {
  const std::int32_t id = schema::application_id(db);
  if (id != schema::kApplicationId) {
    throw StorageError("'" + path + "' is not an ncqual historian database (application_id " +
                       std::to_string(id) + ")");
  }
}

}  // namespace

namespace {
// WAL: the command-line tool reads while the historian writes, and a commit is one append.
// synchronous=NORMAL: in WAL mode a commit survives a crash of the process (what the crash test
// checks); a power cut may lose the last commits but never corrupts the file.
// foreign_keys is per connection and off by default in SQLite.
void set_write_pragmas(sqlite3* db, const std::string& path) {
  const std::string mode = sqlite::query_text(db, "set journal mode", "PRAGMA journal_mode=WAL");
  if (mode != "wal" && path != ":memory:") {
    throw StorageError("open '" + path + "': cannot switch to WAL journal mode (still " + mode +
                       ")");
  }
  sqlite::exec(db, "set synchronous", "PRAGMA synchronous=NORMAL");
  sqlite::exec(db, "enable foreign keys", "PRAGMA foreign_keys=ON");
}
}  // namespace

Database Database::open(const std::string& path) {
  check_sqlite_version();
  if (path != ":memory:") {
    const auto parent = std::filesystem::path(path).parent_path();
    std::error_code error;
    if (!parent.empty()) std::filesystem::create_directories(parent, error);
    if (error) {
      throw StorageError("open '" + path + "': cannot create directory '" + parent.string() +
                         "': " + error.message());
    }
  }
  auto db = sqlite::open_connection(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  sqlite3_busy_timeout(db.get(), kBusyTimeoutMs);

  refuse_foreign_file(db.get(), path);
  if (path != ":memory:") {
    // The first row: "ok", or the first problem (a page too damaged to check is one, too).
    std::string problem;
    try {
      problem = sqlite::query_text(db.get(), "quick check", "PRAGMA quick_check");
    } catch (const StorageError& e) {
      problem = e.what();
    }
    if (problem != "ok") {
      throw StorageError("'" + path + "' is corrupt (PRAGMA quick_check): " + problem +
                             "; it is not opened. `ncqual db recover " + path +
                             " NEW_FILE` salvages what can be read into a new file",
                         SQLITE_CORRUPT);
    }
  }

  set_write_pragmas(db.get(), path);
  schema::migrate(db.get(), path.c_str());
  check_application_id(db.get(), path);
  auto impl = std::make_unique<Impl>(std::move(db), path, false);
  struct stat st {};
  if (path != ":memory:" && ::stat(path.c_str(), &st) == 0) {
    impl->identity = {st.st_dev, st.st_ino};
  }
  return Database(std::move(impl));
}

Database Database::open_another() const {
  const std::string& path = impl_->path;
  if (path == ":memory:") {
    throw StorageError("open another connection: ':memory:' has none (it would be a new database)");
  }
  const std::string problem = file_problem();
  if (!problem.empty()) throw StorageError("open another connection: " + problem);
  auto db = sqlite::open_connection(
      path, impl_->read_only ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE);
  sqlite3_busy_timeout(db.get(), kBusyTimeoutMs);
  if (impl_->read_only) {
    sqlite::exec(db.get(), "enable foreign keys", "PRAGMA foreign_keys=ON");
  } else {
    set_write_pragmas(db.get(), path);
  }
  auto impl = std::make_unique<Impl>(std::move(db), path, impl_->read_only);
  impl->identity = impl_->identity;
  return Database(std::move(impl));
}

sqlite::Connection open_readonly_connection(const std::string& path) {
  check_sqlite_version();
  // No SQLITE_OPEN_CREATE: a missing file is an error, not a new empty database.
  auto db = sqlite::open_connection(path, SQLITE_OPEN_READONLY);
  // A reader can meet SQLITE_BUSY too, e.g. while a writer recovers the WAL after a crash.
  sqlite3_busy_timeout(db.get(), kBusyTimeoutMs);
  sqlite::exec(db.get(), "enable foreign keys", "PRAGMA foreign_keys=ON");

  const int version = schema::user_version(db.get());
  if (version == 0) {
    throw StorageError("open_readonly '" + path +
                       "': no ncqual schema in it (user_version 0); the historian creates it");
  }
  check_application_id(db.get(), path);
  if (version != schema::latest_version()) {
    throw StorageError("open_readonly '" + path + "': schema version " + std::to_string(version) +
                       ", this build reads version " + std::to_string(schema::latest_version()) +
                       (version < schema::latest_version()
                            ? ": start the historian of this build once to migrate it"
                            : ": upgrade ncqual"));
  }
  return db;
}

Database Database::open_readonly(const std::string& path) {
  return Database(std::make_unique<Impl>(open_readonly_connection(path), path, true));
}

int Database::latest_schema_version() { return schema::latest_version(); }

Database::Database(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Database::Database(Database&&) noexcept = default;
Database& Database::operator=(Database&&) noexcept = default;
Database::~Database() = default;

ConnectionInfo Database::info() {
  ConnectionInfo info;
  info.path = impl_->path;
  info.read_only = impl_->read_only;
  info.journal_mode = impl_->pragma_text(kJournalMode);
  info.synchronous = static_cast<int>(impl_->pragma_int(kSynchronous));
  info.foreign_keys = impl_->pragma_int(kForeignKeys) != 0;
  info.busy_timeout_ms = static_cast<int>(impl_->pragma_int(kBusyTimeout));
  info.schema_version = static_cast<int>(impl_->pragma_int(kUserVersion));
  return info;
}

namespace {
std::string check_report(Query& q) {
  std::string report;
  while (q.step()) {
    if (!report.empty()) report += '\n';
    report += q.text(0);
  }
  return report;
}
}  // namespace

std::string Database::integrity_check() {
  Query q(impl_->statements, kIntegrityCheck);
  return check_report(q);
}

std::string Database::quick_check() {
  Query q(impl_->statements, kQuickCheck);
  return check_report(q);
}

std::string Database::file_problem() const {
  if (!impl_->identity) return "";
  struct stat st {};
  if (::stat(impl_->path.c_str(), &st) != 0) {
    const int error = errno;
    return error == ENOENT ? "'" + impl_->path + "' was removed while open"
                           : "'" + impl_->path + "' cannot be looked at: " + std::strerror(error);
  }
  if (st.st_dev != impl_->identity->first || st.st_ino != impl_->identity->second) {
    return "'" + impl_->path + "' was replaced by another file while open";
  }
  return "";
}

void Database::set_busy_timeout(std::chrono::milliseconds timeout) {
  sqlite3_busy_timeout(impl_->db.get(), static_cast<int>(timeout.count()));
}

void Database::copy_to(const std::string& path) {
  if (std::filesystem::exists(path)) {
    throw StorageError("copy to '" + path + "': the file exists; not overwritten");
  }
  Query q(impl_->statements, kCopyTo);
  q.bind(path);
  while (q.step()) {}
}

std::string_view to_string(StorageHealth health) {
  switch (health) {
    case StorageHealth::Ok: return "ok";
    case StorageHealth::Degraded: return "degraded";
    case StorageHealth::Failed: return "failed";
  }
  return "failed";
}

StorageHealth health_after(int sqlite_code) {
  const int primary = sqlite_code & 0xff;
  return primary == SQLITE_BUSY || primary == SQLITE_LOCKED ? StorageHealth::Degraded
                                                            : StorageHealth::Failed;
}

std::string fault_name(int sqlite_code) {
  switch (sqlite_code & 0xff) {
    case SQLITE_BUSY:
    case SQLITE_LOCKED: return "database locked";
    case SQLITE_FULL: return "disk full";
    case SQLITE_IOERR: return "I/O error";
    case SQLITE_CORRUPT:
    case SQLITE_NOTADB: return "database corrupt";
    case SQLITE_READONLY: return "database read-only";
    case SQLITE_CANTOPEN: return "database file cannot be opened";
    default: return sqlite3_errstr(sqlite_code);
  }
}

// --- stores ------------------------------------------------------------------------------------

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
                  set.time_ns, set.error, origin.hash(), origin.writer_guid());
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
                  result.produced_by, origin.hash(), origin.writer_guid());
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

// --- queries -----------------------------------------------------------------------------------

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

sqlite::StatementCache& DatabaseAccess::statements(Database& db) { return db.impl_->statements; }

void DatabaseAccess::read(Database& db, const std::function<void()>& body) {
  db.impl_->read([&] {
    body();
    return 0;
  });
}

void DatabaseAccess::write(Database& db, const std::string& what,
                           const std::function<void()>& body) {
  db.impl_->write(what, [&] {
    body();
    return 0;
  });
}

ThinReport Database::thin_points(std::int64_t before_ns, const ThinOptions& options) {
  ThinReport report;
  report.dry_run = options.dry_run;
  if (options.dry_run) {
    return impl_->read([&] {
      Query q(impl_->statements, kCountToThin);
      q.bind(before_ns);
      if (q.step()) {
        report.sets = q.int64(0);
        report.touches = q.int64(1);
        report.tracker_points = q.int64(2);
        report.oldest_ns = q.optional_int64(3);
        report.newest_ns = q.optional_int64(4);
      }
      return report;
    });
  }
  const std::int64_t now_ns = options.now_ns.value_or(WallClock().now_ns());
  const int batch = std::max(1, options.sets_per_transaction);
  // Where the previous transaction stopped: every set up to it is thinned or has no points.
  std::int64_t cursor_ns = std::numeric_limits<std::int64_t>::min();
  std::string cursor_id;
  struct Candidate {
    std::string request_id;
    std::int64_t time_ns, touches, points;
  };
  // One transaction: the next sets after the cursor, selected under the write lock; true while
  // there may be more.
  const auto thin_some = [&] {
    std::vector<Candidate> candidates;
    {
      Query q(impl_->statements, kSetsToThin);
      q.bind(before_ns, cursor_ns, cursor_id, std::int64_t{batch});
      while (q.step()) candidates.push_back({q.text(0), q.int64(1), q.int64(2), q.int64(3)});
    }
    std::int64_t points = 0;
    for (const Candidate& c : candidates) {
      if (points >= options.points_per_transaction) return true;
      cursor_ns = c.time_ns;
      cursor_id = c.request_id;
      if (c.touches + c.points == 0) continue;
      Query(impl_->statements, kDeleteTouches).bind(c.request_id).run();
      Query(impl_->statements, kDeleteTrackerPoints).bind(c.request_id).run();
      Query(impl_->statements, kMarkThinned).bind(c.request_id, now_ns, c.touches, c.points).run();
      points += c.touches + c.points;
      ++report.sets;
      report.touches += c.touches;
      report.tracker_points += c.points;
      if (!report.oldest_ns) report.oldest_ns = c.time_ns;
      report.newest_ns = c.time_ns;
    }
    return static_cast<int>(candidates.size()) == batch;
  };
  const std::string what =
      "thin the points of measurement sets before " + std::to_string(before_ns);
  for (bool more = true; more; ++report.transactions) {
    if (report.transactions > 0 && options.pause.count() > 0) {
      std::this_thread::sleep_for(options.pause);  // the historian's writers get their turn
    }
    more = impl_->write(what, thin_some);
  }
  return report;
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
