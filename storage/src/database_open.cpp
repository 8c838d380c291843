// SPDX-License-Identifier: Apache-2.0
// Opening a Database (read-write, read-only, another connection to the same file), its
// connection settings, checks and copy, and what SQLite's failure codes mean to the historian.
#include "ncqual/storage/database.hpp"

#include "database_impl.hpp"
#include "open.hpp"
#include "schema.hpp"
#include "sqlite.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>

namespace ncqual::storage {
namespace {

using sqlite::Query;
using sqlite::Sql;

// A writer waits this long for another writer's transaction before giving up with SQLITE_BUSY.
// Transactions here last milliseconds; 5 s only runs out when something is badly stuck.
constexpr int kBusyTimeoutMs = 5000;

// STRICT tables and the generated sort column need SQLite 3.37 (Debian 12 has 3.40).
constexpr int kMinimumSqliteVersion = 3037000;

constexpr Sql kIntegrityCheck{"integrity check", "PRAGMA integrity_check"};
constexpr Sql kQuickCheck{"quick check", "PRAGMA quick_check"};
constexpr Sql kCopyTo{"copy the database", "VACUUM INTO ?1"};
constexpr Sql kJournalMode{"read journal mode", "PRAGMA journal_mode"};
constexpr Sql kSynchronous{"read synchronous", "PRAGMA synchronous"};
constexpr Sql kForeignKeys{"read foreign keys", "PRAGMA foreign_keys"};
constexpr Sql kBusyTimeout{"read busy timeout", "PRAGMA busy_timeout"};
constexpr Sql kUserVersion{"read user version", "PRAGMA user_version"};

}  // namespace

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

  // A damaged file, found by its first read or by the check: not opened, and the way out named.
  const auto corrupt = [&](const std::string& found_by, const std::string& problem) {
    return StorageError("'" + path + "' is corrupt (" + found_by + "): " + problem +
                            "; it is not opened. `ncqual db recover " + path +
                            " NEW_FILE` salvages what can be read into a new file",
                        SQLITE_CORRUPT);
  };
  try {
    refuse_foreign_file(db.get(), path);
  } catch (const StorageError& e) {
    const int primary = e.sqlite_code() & 0xff;
    if (primary == SQLITE_CORRUPT) throw corrupt("reading its header", e.what());
    throw;
  }
  if (path != ":memory:") {
    // The first row: "ok", or the first problem (a page too damaged to check is one, too).
    std::string problem;
    try {
      problem = sqlite::query_text(db.get(), "quick check", "PRAGMA quick_check");
    } catch (const StorageError& e) {
      problem = e.what();
    }
    if (problem != "ok") throw corrupt("PRAGMA quick_check", problem);
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

std::string Database::Impl::pragma_text(const Sql& sql) {
  Query q(statements, sql);
  if (!q.step()) return {};
  return q.text(0);
}

std::int64_t Database::Impl::pragma_int(const Sql& sql) {
  Query q(statements, sql);
  if (!q.step()) return 0;
  return q.int64(0);
}

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

}  // namespace ncqual::storage
