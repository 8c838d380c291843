// SPDX-License-Identifier: Apache-2.0
// The historian's store: every request, measurement set, result, status change, intervention,
// compensation and heartbeat of every machine, in one SQLite file.
//
// Knows nothing of DDS. The historian writes through `Database::open`; the command-line tool reads
// through `Database::open_readonly` while the historian keeps writing (WAL mode lets both run).
// Every store is idempotent on the identity of its sample: DDS may deliver a sample again (a
// restarted historian, a durable writer replaying its history) and that must never become a
// second row.
#pragma once

#include "ncqual/common/error.hpp"
#include "ncqual/common/model.hpp"

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <chrono>
#include <string>
#include <vector>

namespace ncqual::storage {

// Everything the storage refuses or fails to do. Input is validated before anything is written,
// and every store runs in one transaction, so after a StorageError nothing of the sample is in the
// file.
class StorageError : public Error {
 public:
  explicit StorageError(const std::string& message, int sqlite_code = 0)
      : Error(message), sqlite_code_(sqlite_code) {}

  // The SQLite extended result code when SQLite failed (SQLITE_BUSY, SQLITE_FULL, ...), 0 when the
  // input itself was refused. Lets the historian tell "drop this sample and log it" from "the
  // database is in trouble, retry or alarm".
  int sqlite_code() const noexcept { return sqlite_code_; }

 private:
  int sqlite_code_;
};

// How well the historian can store: Ok; Degraded (the database is locked by someone else: samples
// wait and are retried); Failed (disk full, I/O error, corruption, the file removed: nothing is
// stored or acknowledged until it clears).
enum class StorageHealth { Ok, Degraded, Failed };
std::string_view to_string(StorageHealth health);
// What a failure with this SQLite (extended) result code means: busy or locked -> Degraded,
// anything else -> Failed.
StorageHealth health_after(int sqlite_code);
// The fault in a few words: "database locked", "disk full", "I/O error", "database corrupt", ...
std::string fault_name(int sqlite_code);

// Where a stored sample came from (acknowledged storage): the SHA-256 of its CDR serialization
// and the GUID of the DataWriter that wrote it, as the historian received it. Empty for samples
// stored by other means (tests, imports of old files): they are stored without a hash.
struct Origin {
  std::string content_hash;
  std::string writer;
  std::int64_t received_ns = 0;
  std::optional<std::string> hash() const {
    return content_hash.empty() ? std::nullopt : std::optional<std::string>(content_hash);
  }
  std::optional<std::string> writer_guid() const {
    return writer.empty() ? std::nullopt : std::optional<std::string>(writer);
  }
};

enum class StoreOutcome {
  Stored,     // newly stored
  Duplicate,  // the same sample was already stored (or one stored without a hash)
  Conflict,   // a sample with this identity and other content was stored first: this one is kept
              // in the conflicts table beside it, the first is never replaced
};

struct StoreResult {
  StoreOutcome outcome = StoreOutcome::Stored;
  std::string stored_hash;  // Duplicate/Conflict: the hash of the sample stored first ('' if none)
  // Conflict: false when this very content was already kept as a conflict (a resend): the
  // conflict is known, nothing new to raise.
  bool new_conflict = false;
  std::string stored_writer;  // Conflict: the GUID of the writer of the sample stored first
  explicit operator bool() const { return outcome == StoreOutcome::Stored; }
};

// A sample kept because its id was already stored with other content.
struct ConflictRecord {
  std::string topic;  // "ncqual/CheckResult"
  std::string sample_id;
  std::string machine_id;
  std::string content_hash;
  std::string stored_hash;
  std::string writer;
  std::int64_t received_ns = 0;
  std::string document;  // the sample, JSON
};

// What was measured for one check, without the raw points (load_measurement_set has those).
struct MeasurementSummary {
  std::string instrument;
  std::string frame;
  std::int64_t time_ns = 0;
  std::int64_t touches = 0;         // number of touches measured (also once thinned)
  std::int64_t tracker_points = 0;  // number of tracker points measured (also once thinned)
  std::string error;                // non-empty when the instrument could not perform the request
  // When retention deleted its touches and tracker points (Database::thin_points): the set,
  // its parameters and its check's result stay, its points are gone. Nothing while they are all
  // stored.
  std::optional<std::int64_t> points_thinned_ns;
  // Measured by a real instrument or simulated; Unknown for a set stored before schema 11 or
  // received in wire contract 1.
  DataOrigin origin = DataOrigin::Unknown;
};

// Retention (Database::thin_points): what was removed, or in a dry run what would be.
struct ThinReport {
  std::int64_t sets = 0;                             // measurement sets whose points were deleted
  std::int64_t touches = 0;                          // touches deleted
  std::int64_t tracker_points = 0;                   // tracker points deleted
  std::optional<std::int64_t> oldest_ns, newest_ns;  // the times of the oldest and newest such set
  int transactions = 0;                              // write transactions it took (0: dry run)
  bool dry_run = false;
};

struct ThinOptions {
  bool dry_run = false;                // count only: nothing is written
  std::optional<std::int64_t> now_ns;  // kept as each set's points_thinned_ns (default: wall clock)
  // One write transaction deletes the points of at most this many sets, and stops adding sets
  // once it holds this many points (a set is never split), then pauses: the historian's writers
  // wait for one short transaction at a time, never for the whole thinning.
  int sets_per_transaction = 100;
  std::int64_t points_per_transaction = 50'000;
  std::chrono::milliseconds pause{5};
};

// One check, joined by request id from whatever has arrived so far: a result can arrive before
// its request (different topics, different writers), so every part is optional.
struct CheckRecord {
  std::string request_id;
  std::string machine_id;
  CheckKind kind = CheckKind::MonumentPositioning;
  std::optional<CheckRequest> request;
  std::optional<MeasurementSummary> measurement;
  std::optional<CheckResult> result;  // metrics in order, causes in rank order, correction
  std::int64_t conflicts = 0;         // samples of this request kept beside these for other content
  // The DataWriters the request, set and result came from: their GUIDs as stored
  // ("a5.63.3b.ec.d4.04.66.67.64.02.6c.52|0.0.3.2"); empty when that part has not arrived, came
  // from a file (ncqual import) or was stored before schema version 4.
  struct Writers {
    std::string request, measurement, result;
  } writers;
};

// Whether a check's numbers were measured or simulated: its result's origin, else (no result yet,
// or one that did not say) its set's; Unknown when neither says.
DataOrigin origin_of(const CheckRecord& record);

struct HistoryQuery {
  std::optional<std::string> machine_id;  // all machines when empty
  std::optional<CheckKind> kind;          // all kinds when empty
  std::int64_t since_ns = std::numeric_limits<std::int64_t>::min();
  int limit = 100;  // at most this many records; <= 0 means no limit
};

struct MachineRecord {
  std::string machine_id;
  std::int64_t first_seen_ns = 0;  // sample times (not arrival times) of the oldest and newest
  std::int64_t last_seen_ns = 0;   // sample that named this machine
};

// Connection settings as SQLite reports them, for tests and `ncqual db info`.
struct ConnectionInfo {
  std::string path;
  bool read_only = false;
  std::string journal_mode;  // "wal"
  int synchronous = 0;       // 1 = NORMAL
  bool foreign_keys = false;
  int busy_timeout_ms = 0;
  int schema_version = 0;  // PRAGMA user_version
};

// One connection to the historian file. Movable, not copyable; a moved-from Database may only be
// destroyed or assigned to. Not safe to use from two threads at once: open one per thread (any
// number of connections, in any number of processes, may share the file).
struct DatabaseAccess;

class Database {
 public:
  // Opens read-write, creating the file and its parent directories if missing, and brings the
  // schema up to date. Refuses a file written by a newer ncqual (schema version above ours), one
  // that is not an ncqual database, and one that fails PRAGMA quick_check (the message names the
  // file and the first problem; `ncqual db recover` salvages it into a new file).
  static Database open(const std::string& path);
  // Opens an existing, up-to-date database read-only; never migrates, never writes.
  static Database open_readonly(const std::string& path);
  // Another read-write connection to the file this one opened, for another thread of the same
  // process: the same settings, without open()'s quick_check and migration (this connection did
  // both). Refused for ":memory:" (it would be another database) and after file_problem().
  Database open_another() const;

  // The schema version this build writes and reads (PRAGMA user_version after all migrations).
  static int latest_schema_version();

  Database(Database&&) noexcept;
  Database& operator=(Database&&) noexcept;
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;
  ~Database();

  ConnectionInfo info();
  // "ok", or SQLite's list of problems one per line.
  std::string integrity_check();
  // The same for PRAGMA quick_check (no index cross-checks: O(size), run at every open()).
  std::string quick_check();
  // "" while the path still names the file this connection opened; else what happened to it
  // ("... was removed", "... was replaced by another file"). A connection keeps writing to the
  // file it opened, so a historian must stop acknowledging as soon as this is not "".
  std::string file_problem() const;
  // How long a statement waits for another connection's lock before SQLITE_BUSY (default 5 s).
  void set_busy_timeout(std::chrono::milliseconds timeout);
  // A consistent copy of everything stored into the new file `path` (VACUUM INTO): e.g. to rescue
  // what a connection still holds after its file was removed. Throws StorageError.
  void copy_to(const std::string& path);

  // Each store says whether the sample was newly stored, a duplicate, or a conflict (its identity
  // was stored first with another content hash: it is kept in the conflicts table, the first row
  // stays). Identity: request_id for requests, measurement sets and results;
  // (machine_id, time_ns, state, request_id) for statuses; intervention_id for interventions;
  // (request_id, correction.target) for compensations; (service, instance) for heartbeats.
  // Each also records the machine as seen at the sample's time, and the origin's hash and writer.
  StoreResult store(const CheckRequest& request, const Origin& origin = {});
  StoreResult store(const MeasurementSet& measurement_set, const Origin& origin = {});
  StoreResult store(const CheckResult& result, const Origin& origin = {});
  StoreResult store(const MachineStatus& status, const Origin& origin = {});
  StoreResult store(const Intervention& intervention, const Origin& origin = {});
  StoreResult store(const Compensation& compensation, const Origin& origin = {});
  // Upserts the service's state and last seen time (a stale heartbeat never moves it back);
  // true when this (service, instance) was not known before.
  bool store(const Heartbeat& heartbeat);

  // Checks newest first by time (result time, else request time, else measurement time).
  std::vector<CheckRecord> history(const HistoryQuery& query);
  std::optional<CheckRecord> find_check(const std::string& request_id);
  // The measurement set with every touch and tracker point, exactly as stored.
  std::optional<MeasurementSet> load_measurement_set(const std::string& request_id);
  std::int64_t count_results(std::optional<std::string> machine_id = {});
  // Result time of the machine's newest PASS of `kind`, if any.
  std::optional<std::int64_t> last_pass_ns(const std::string& machine_id, CheckKind kind);
  // Every machine ever seen, sorted by id.
  std::vector<std::string> machines();
  std::optional<MachineRecord> machine(const std::string& machine_id);
  // The most recent status by time_ns (the last stored when several share a time).
  std::optional<MachineStatus> latest_status(const std::string& machine_id);
  // Every stored status change of the machine, oldest first.
  std::vector<MachineStatus> status_history(const std::string& machine_id);
  // Newest first.
  std::vector<Intervention> interventions(const std::string& machine_id);
  // Newest first.
  std::vector<Compensation> compensations(const std::string& machine_id);
  // The last heartbeat of every service instance, sorted by service then instance.
  std::vector<Heartbeat> services();
  // Samples kept for conflicting with a stored one, newest first; of one machine or of all.
  std::vector<ConflictRecord> conflicts(const std::optional<std::string>& machine_id = {});

  // Retention: deletes the touches and tracker points of every measurement set whose time is
  // before `before_ns` and whose points are still stored, and marks each such set thinned (its
  // points_thinned_ns and how many points it had). Requests, sets, parameters, results, metrics,
  // causes, corrections, compensations, status changes and everything else stay as they are.
  // Sets without any point are left unmarked. Idempotent: a second run finds nothing to do.
  // Runs in short write transactions (ThinOptions) so a running historian keeps storing; the
  // freed pages are reused by new rows (the file does not shrink). Read-write connections only.
  ThinReport thin_points(std::int64_t before_ns, const ThinOptions& options = {});

 private:
  struct Impl;
  friend struct DatabaseAccess;  // the library's other query files (storage/src/database_impl.hpp)
  explicit Database(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace ncqual::storage
