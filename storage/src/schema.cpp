// SPDX-License-Identifier: Apache-2.0
#include "schema.hpp"

#include "ncqual/storage/database.hpp"
#include "sqlite.hpp"

#include <string>

namespace ncqual::storage::schema {
namespace {

// ---------------------------------------------------------------------------------------------
// Version 1: the whole historian.
//
// Identity and ordering
//   Every sample type has a table keyed on the identity of the sample, and every store is
//   INSERT ... ON CONFLICT DO NOTHING on that key, so a resent DDS sample is never a second row.
//   Times are sample times in ns since the Unix epoch (UTC), never arrival times.
//
// Foreign keys only from a sample's children to the sample (touches -> measurement_sets, ...),
//   never between topics: a result can arrive before its request, a compensation before its
//   result. Children are numbered by `idx` in the order of the sample's vectors.
//
// Enums: `kind` columns hold the CheckKind numbers (stable, append-only, see model.hpp);
//   verdicts and machine states are stored by their stable names, readable in the sqlite3 shell.
//
// Tables
//   machines        every machine named by any sample: first and last sample time.
//   requests        CheckRequest, one per request_id (kind_name for people reading the file).
//   measurement_sets MeasurementSet header, one per request_id; error '' when it succeeded.
//     touches         its probe touches: axes at trigger, approach direction (ux, uy, uz).
//     tracker_points  its tracker points: commanded axes, measured position in `frame`.
//   results         CheckResult header, one per request_id; correction_target NULL when the
//                   result carries no correction (a correction may have zero offsets).
//     metrics         its metrics with tolerance band; an infinite bound is a one-sided band.
//     causes          its likely causes, rank 0 first (the order to investigate them).
//     result_offsets  its correction's offsets.
//   checks          one row per request_id seen in requests, measurement_sets or results, with
//                   the time each part arrived with; sort_ns is the check's time (result, else
//                   request, else measurement). Derived: written only in the same transaction as
//                   the sample it derives from. Lets history() page through checks by index.
//   status_changes  MachineStatus; request_id '' (not NULL) when no request caused it, so that
//                   the UNIQUE identity holds (NULLs are all distinct in SQL).
//   interventions   Intervention, one per intervention_id.
//   compensations   Compensation, one per (request_id, target).
//     compensation_offsets its offsets.
//   services        last Heartbeat per (service, instance); machine_id '' for plant-wide ones.
//
// STRICT tables: SQLite refuses a value of the wrong type instead of storing it anyway.
// ---------------------------------------------------------------------------------------------
constexpr const char* kVersion1 = R"sql(
CREATE TABLE machines (
  machine_id    TEXT NOT NULL PRIMARY KEY,
  first_seen_ns INTEGER NOT NULL,
  last_seen_ns  INTEGER NOT NULL
) STRICT, WITHOUT ROWID;

CREATE TABLE requests (
  request_id   TEXT NOT NULL PRIMARY KEY,
  machine_id   TEXT NOT NULL,
  kind         INTEGER NOT NULL,
  kind_name    TEXT NOT NULL,
  requested_by TEXT NOT NULL,
  time_ns      INTEGER NOT NULL,
  attempt      INTEGER NOT NULL
) STRICT;
CREATE INDEX requests_by_machine_time ON requests (machine_id, time_ns);

CREATE TABLE measurement_sets (
  request_id TEXT NOT NULL PRIMARY KEY,
  machine_id TEXT NOT NULL,
  kind       INTEGER NOT NULL,
  instrument TEXT NOT NULL,
  frame      TEXT NOT NULL,
  time_ns    INTEGER NOT NULL,
  error      TEXT NOT NULL
) STRICT;
CREATE INDEX measurement_sets_by_machine_time ON measurement_sets (machine_id, time_ns);

CREATE TABLE touches (
  request_id TEXT NOT NULL REFERENCES measurement_sets (request_id) ON DELETE CASCADE,
  idx        INTEGER NOT NULL,
  feature    TEXT NOT NULL,
  x_mm REAL NOT NULL, y_mm REAL NOT NULL, z_mm REAL NOT NULL,
  w_mm REAL NOT NULL, a_rad REAL NOT NULL, c_rad REAL NOT NULL,
  ux REAL NOT NULL, uy REAL NOT NULL, uz REAL NOT NULL,
  PRIMARY KEY (request_id, idx)
) STRICT, WITHOUT ROWID;

CREATE TABLE tracker_points (
  request_id TEXT NOT NULL REFERENCES measurement_sets (request_id) ON DELETE CASCADE,
  idx        INTEGER NOT NULL,
  label      TEXT NOT NULL,
  x_mm REAL NOT NULL, y_mm REAL NOT NULL, z_mm REAL NOT NULL,
  w_mm REAL NOT NULL, a_rad REAL NOT NULL, c_rad REAL NOT NULL,
  measured_x_mm REAL NOT NULL, measured_y_mm REAL NOT NULL, measured_z_mm REAL NOT NULL,
  PRIMARY KEY (request_id, idx)
) STRICT, WITHOUT ROWID;

CREATE TABLE results (
  request_id        TEXT NOT NULL PRIMARY KEY,
  machine_id        TEXT NOT NULL,
  kind              INTEGER NOT NULL,
  verdict           TEXT NOT NULL CHECK (verdict IN ('PASS', 'FAIL', 'INVALID')),
  reason            TEXT NOT NULL,
  time_ns           INTEGER NOT NULL,
  correction_target TEXT
) STRICT;
CREATE INDEX results_by_machine_time ON results (machine_id, time_ns);

CREATE TABLE metrics (
  request_id TEXT NOT NULL REFERENCES results (request_id) ON DELETE CASCADE,
  idx        INTEGER NOT NULL,
  name       TEXT NOT NULL,
  value      REAL NOT NULL,
  unit       TEXT NOT NULL,
  lower      REAL NOT NULL,
  upper      REAL NOT NULL,
  pass       INTEGER NOT NULL CHECK (pass IN (0, 1)),
  PRIMARY KEY (request_id, idx)
) STRICT, WITHOUT ROWID;

CREATE TABLE causes (
  request_id TEXT NOT NULL REFERENCES results (request_id) ON DELETE CASCADE,
  rank       INTEGER NOT NULL,
  cause      TEXT NOT NULL,
  PRIMARY KEY (request_id, rank)
) STRICT, WITHOUT ROWID;

CREATE TABLE result_offsets (
  request_id TEXT NOT NULL REFERENCES results (request_id) ON DELETE CASCADE,
  idx        INTEGER NOT NULL,
  name       TEXT NOT NULL,
  value      REAL NOT NULL,
  unit       TEXT NOT NULL,
  PRIMARY KEY (request_id, idx)
) STRICT, WITHOUT ROWID;

CREATE TABLE checks (
  request_id      TEXT NOT NULL PRIMARY KEY,
  machine_id      TEXT NOT NULL,
  kind            INTEGER NOT NULL,
  requested_at_ns INTEGER,
  measured_at_ns  INTEGER,
  result_at_ns    INTEGER,
  sort_ns         INTEGER NOT NULL
                  GENERATED ALWAYS AS (coalesce(result_at_ns, requested_at_ns, measured_at_ns))
) STRICT, WITHOUT ROWID;
CREATE INDEX checks_by_machine_time ON checks (machine_id, sort_ns);
CREATE INDEX checks_by_time ON checks (sort_ns);

CREATE TABLE status_changes (
  id           INTEGER PRIMARY KEY,
  machine_id   TEXT NOT NULL,
  request_id   TEXT NOT NULL,
  state        TEXT NOT NULL,
  last_kind    INTEGER,
  last_verdict TEXT,
  detail       TEXT NOT NULL,
  time_ns      INTEGER NOT NULL,
  UNIQUE (machine_id, time_ns, state, request_id)
) STRICT;

CREATE TABLE interventions (
  intervention_id TEXT NOT NULL PRIMARY KEY,
  machine_id      TEXT NOT NULL,
  kind            INTEGER NOT NULL,
  note            TEXT NOT NULL,
  operator_name   TEXT NOT NULL,
  time_ns         INTEGER NOT NULL
) STRICT;
CREATE INDEX interventions_by_machine_time ON interventions (machine_id, time_ns);

CREATE TABLE compensations (
  id         INTEGER PRIMARY KEY,
  request_id TEXT NOT NULL,
  target     TEXT NOT NULL,
  machine_id TEXT NOT NULL,
  time_ns    INTEGER NOT NULL,
  UNIQUE (request_id, target)
) STRICT;
CREATE INDEX compensations_by_machine_time ON compensations (machine_id, time_ns);

CREATE TABLE compensation_offsets (
  compensation_id INTEGER NOT NULL REFERENCES compensations (id) ON DELETE CASCADE,
  idx             INTEGER NOT NULL,
  name            TEXT NOT NULL,
  value           REAL NOT NULL,
  unit            TEXT NOT NULL,
  PRIMARY KEY (compensation_id, idx)
) STRICT, WITHOUT ROWID;

CREATE TABLE services (
  service       TEXT NOT NULL,
  instance      TEXT NOT NULL,
  machine_id    TEXT NOT NULL,
  state         TEXT NOT NULL,
  first_seen_ns INTEGER NOT NULL,
  last_seen_ns  INTEGER NOT NULL,
  PRIMARY KEY (service, instance)
) STRICT, WITHOUT ROWID;

PRAGMA application_id = 1852010869;
)sql";

// Version 2: the parameters of a request (e.g. the weekly fixture configuration) and the ones
// the instrument echoed with its measurement set; the correction a request verifies.
constexpr const char* kVersion2 = R"sql(
ALTER TABLE requests ADD COLUMN verifies_correction_of TEXT NOT NULL DEFAULT '';

CREATE TABLE request_parameters (
  request_id TEXT NOT NULL REFERENCES requests (request_id) ON DELETE CASCADE,
  idx        INTEGER NOT NULL,
  name       TEXT NOT NULL,
  value      REAL NOT NULL,
  unit       TEXT NOT NULL,
  PRIMARY KEY (request_id, idx)
) STRICT, WITHOUT ROWID;

CREATE TABLE measurement_parameters (
  request_id TEXT NOT NULL REFERENCES measurement_sets (request_id) ON DELETE CASCADE,
  idx        INTEGER NOT NULL,
  name       TEXT NOT NULL,
  value      REAL NOT NULL,
  unit       TEXT NOT NULL,
  PRIMARY KEY (request_id, idx)
) STRICT, WITHOUT ROWID;
)sql";

// Version 3: the software that judged each result (CheckResult.produced_by); '' for results
// stored before.
constexpr const char* kVersion3 = R"sql(
ALTER TABLE results ADD COLUMN produced_by TEXT NOT NULL DEFAULT '';
)sql";

// Version 4: acknowledged storage and conflicts (docs/architecture.md, "Acknowledged storage").
//   content_hash, writer on every sample table: the SHA-256 of the sample's CDR serialization and
//     the GUID of the DataWriter it came from; NULL for rows stored before version 4.
//   conflicts: a sample whose id was already stored with other content, kept whole (document,
//     JSON) beside the first, never replacing it; stored_hash is the first one's.
//   services: the health and outbox fields of the newest heartbeat.
constexpr const char* kVersion4 = R"sql(
ALTER TABLE requests ADD COLUMN content_hash TEXT;
ALTER TABLE requests ADD COLUMN writer TEXT;
ALTER TABLE measurement_sets ADD COLUMN content_hash TEXT;
ALTER TABLE measurement_sets ADD COLUMN writer TEXT;
ALTER TABLE results ADD COLUMN content_hash TEXT;
ALTER TABLE results ADD COLUMN writer TEXT;
ALTER TABLE status_changes ADD COLUMN content_hash TEXT;
ALTER TABLE status_changes ADD COLUMN writer TEXT;
ALTER TABLE interventions ADD COLUMN content_hash TEXT;
ALTER TABLE interventions ADD COLUMN writer TEXT;
ALTER TABLE compensations ADD COLUMN content_hash TEXT;
ALTER TABLE compensations ADD COLUMN writer TEXT;

CREATE TABLE conflicts (
  id           INTEGER PRIMARY KEY,
  topic        TEXT NOT NULL,
  sample_id    TEXT NOT NULL,
  machine_id   TEXT NOT NULL,
  content_hash TEXT NOT NULL,
  stored_hash  TEXT NOT NULL,
  writer       TEXT NOT NULL,
  received_ns  INTEGER NOT NULL,
  document     TEXT NOT NULL,
  UNIQUE (topic, sample_id, content_hash)
) STRICT;
CREATE INDEX conflicts_by_machine_time ON conflicts (machine_id, received_ns);

ALTER TABLE services ADD COLUMN health TEXT NOT NULL DEFAULT 'ok';
ALTER TABLE services ADD COLUMN health_detail TEXT NOT NULL DEFAULT '';
ALTER TABLE services ADD COLUMN outbox_depth INTEGER NOT NULL DEFAULT 0;
ALTER TABLE services ADD COLUMN oldest_unacknowledged_ns INTEGER NOT NULL DEFAULT 0;
)sql";

// Version 5: a metric that could not be evaluated (NaN or infinite) is kept with its value NULL,
// so every result the historian receives is stored (read back as NaN). SQLite cannot drop a NOT
// NULL constraint: the table is rebuilt, its rows copied.
constexpr const char* kVersion5 = R"sql(
CREATE TABLE metrics_v5 (
  request_id TEXT NOT NULL REFERENCES results (request_id) ON DELETE CASCADE,
  idx        INTEGER NOT NULL,
  name       TEXT NOT NULL,
  value      REAL,
  unit       TEXT NOT NULL,
  lower      REAL NOT NULL,
  upper      REAL NOT NULL,
  pass       INTEGER NOT NULL CHECK (pass IN (0, 1)),
  PRIMARY KEY (request_id, idx)
) STRICT, WITHOUT ROWID;
INSERT INTO metrics_v5 (request_id, idx, name, value, unit, lower, upper, pass)
  SELECT request_id, idx, name, value, unit, lower, upper, pass FROM metrics;
DROP TABLE metrics;
ALTER TABLE metrics_v5 RENAME TO metrics;
)sql";

// Version 6: trend warnings (trend/, docs/trends.md), raised and ended by the historian as it
// assesses each metric's series after a stored result. One row per warning: its machine, metric
// (and the check kind the metric belongs to), kind ("forecast", "ewma", "cusum_up", ...), the time
// of the check where it first fired, the result that raised it and the one that ended it (NULL
// while active), and for a forecast the dates the fitted line and its 95 % prediction bound cross
// the tolerance (kept up to date while active).
constexpr const char* kVersion6 = R"sql(
CREATE TABLE trend_warnings (
  machine_id           TEXT NOT NULL,
  metric               TEXT NOT NULL,
  check_kind           INTEGER NOT NULL,
  kind                 TEXT NOT NULL,
  started_ns           INTEGER NOT NULL,
  raised_by            TEXT NOT NULL,
  raised_ns            INTEGER NOT NULL,
  ended_by             TEXT,
  ended_ns             INTEGER,
  expected_crossing_ns INTEGER,
  earliest_crossing_ns INTEGER,
  text                 TEXT NOT NULL,
  PRIMARY KEY (machine_id, metric, kind, started_ns)
) STRICT, WITHOUT ROWID;
CREATE INDEX trend_warnings_by_machine_end ON trend_warnings (machine_id, ended_ns);
)sql";

// Version 7: retention (docs/export.md, "Retention"). Database::thin_points deletes the raw points
// (touches, tracker_points) of old measurement sets and keeps everything else; the set row says
// when (points_thinned_ns, NULL while its points are all there) and how many there were
// (thinned_touches, thinned_tracker_points), so a check's summary still counts what was measured.
// The index walks the sets in time order across machines (thinning, export).
constexpr const char* kVersion7 = R"sql(
ALTER TABLE measurement_sets ADD COLUMN points_thinned_ns INTEGER;
ALTER TABLE measurement_sets ADD COLUMN thinned_touches INTEGER NOT NULL DEFAULT 0;
ALTER TABLE measurement_sets ADD COLUMN thinned_tracker_points INTEGER NOT NULL DEFAULT 0;
CREATE INDEX measurement_sets_by_time ON measurement_sets (time_ns, request_id);
)sql";

// Version 8: the historian for people (docs/trends.md). A metric's series is read by machine,
// check kind and time (the results index then holds every row the trend of a metric walks);
// a trend warning keeps its side (above or below; for a forecast the limit it heads to); the
// warnings are listed by the time they started.
constexpr const char* kVersion8 = R"sql(
CREATE INDEX results_by_machine_kind_time ON results (machine_id, kind, time_ns);
ALTER TABLE trend_warnings ADD COLUMN side TEXT NOT NULL DEFAULT '';
CREATE INDEX trend_warnings_by_started ON trend_warnings (started_ns);
)sql";

// Version 9: the pages of a plant with a year of checks (docs/history-bench.md). A machine's
// newest failed checks (storage::recent_failures: the plant and machine pages) and its newest pass
// of a kind (Database::last_pass_ns: every period of `ncqual status`) each walked every result of
// the machine (of the kind) to test its verdict; partial indexes of the results that did not pass
// and of those that passed make each a search of the rows it returns (plant page of 50 machines x
// 365 days: 50 ms to 9 ms).
constexpr const char* kVersion9 = R"sql(
CREATE INDEX results_not_passed_by_machine_time ON results (machine_id, time_ns, request_id)
  WHERE verdict <> 'PASS';
CREATE INDEX results_passed_by_machine_kind_time ON results (machine_id, kind, time_ns)
  WHERE verdict = 'PASS';
)sql";

// Version 10: which metrics a machine's checks of each kind have ever reported (docs/trends.md,
// "The series and its segment"). A metric's series (storage::metric_series) and a machine's list
// of metrics (storage::machine_metrics) found them through the machine's newest result of each
// kind, so a newest result that reported fewer metrics (an INVALID check, a fixture check of
// another pogo rotation) hid the others' history. Kept by a trigger as metrics are stored (a
// result's row is stored before its metrics), filled once from the metrics already stored.
constexpr const char* kVersion10 = R"sql(
CREATE TABLE reported_metrics (
  machine_id TEXT NOT NULL,
  name       TEXT NOT NULL,
  kind       INTEGER NOT NULL,
  PRIMARY KEY (machine_id, name, kind)
) STRICT, WITHOUT ROWID;
INSERT OR IGNORE INTO reported_metrics (machine_id, name, kind)
  SELECT DISTINCT r.machine_id, m.name, r.kind FROM metrics AS m JOIN results AS r USING (request_id);
CREATE TRIGGER metrics_reported AFTER INSERT ON metrics BEGIN
  INSERT OR IGNORE INTO reported_metrics (machine_id, name, kind)
    SELECT machine_id, NEW.name, kind FROM results WHERE request_id = NEW.request_id;
END;
)sql";

// Version 11: whether a set and its result were measured by a real instrument or simulated
// (MeasurementSet.origin, CheckResult.origin; wire contract 2). 'measured' or 'simulated'; NULL for
// rows stored before, and for samples of contract 1, which do not say: read back as "unknown",
// never assumed measured.
constexpr const char* kVersion11 = R"sql(
ALTER TABLE measurement_sets ADD COLUMN origin TEXT CHECK (origin IN ('measured', 'simulated'));
ALTER TABLE results ADD COLUMN origin TEXT CHECK (origin IN ('measured', 'simulated'));
)sql";

// Append new steps here, never edit an applied one: files in the field are at its version.
const std::vector<Migration> kMigrations = {
    {1, "create the historian tables", kVersion1},
    {2, "store request and measurement parameters", kVersion2},
    {3, "store the software that judged each result", kVersion3},
    {4, "content hashes, writers, conflicts and service health", kVersion4},
    {5, "keep a metric that could not be evaluated, its value NULL", kVersion5},
    {6, "trend warnings", kVersion6},
    {7, "thinned points of old measurement sets", kVersion7},
    {8, "trend series index and warning sides", kVersion8},
    {9, "indexes of failed and passed results by machine", kVersion9},
    {10, "the metrics each machine's checks of a kind reported", kVersion10},
    {11, "whether each set and result was measured or simulated", kVersion11},
};

std::int64_t pragma_int(sqlite3* db, const char* sql) {
  return std::stoll(sqlite::query_text(db, sql, sql));
}

}  // namespace

const std::vector<Migration>& migrations() { return kMigrations; }
int latest_version() { return kMigrations.back().version; }

int user_version(sqlite3* db) { return static_cast<int>(pragma_int(db, "PRAGMA user_version")); }

std::int32_t application_id(sqlite3* db) {
  return static_cast<std::int32_t>(pragma_int(db, "PRAGMA application_id"));
}

void migrate(sqlite3* db, const char* path) {
  for (;;) {
    sqlite::exec(db, "begin migration", "BEGIN IMMEDIATE");
    try {
      // Read under the write lock: another process may have migrated while we waited for it.
      const int version = user_version(db);
      if (version > latest_version()) {
        throw StorageError(std::string("database '") + path + "' has schema version " +
                           std::to_string(version) + ", newer than this build's " +
                           std::to_string(latest_version()) + ": upgrade ncqual");
      }
      if (version == latest_version()) {
        sqlite::exec(db, "end migration", "COMMIT");
        return;
      }
      const Migration& step = kMigrations.at(static_cast<std::size_t>(version));
      const std::string operation = "migration to schema version " + std::to_string(step.version) +
                                    " (" + step.description + ")";
      sqlite::exec(db, operation, step.sql);
      sqlite::exec(db, operation,
                   ("PRAGMA user_version = " + std::to_string(step.version)).c_str());
      sqlite::exec(db, operation, "COMMIT");
    } catch (...) {
      if (!sqlite3_get_autocommit(db)) sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
      throw;
    }
  }
}

}  // namespace ncqual::storage::schema
