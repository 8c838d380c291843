// SPDX-License-Identifier: Apache-2.0
#include "sqlite.hpp"

#include <stdexcept>

namespace ncqual::storage::sqlite {
namespace {

constexpr Sql kBeginRead{"begin read transaction", "BEGIN DEFERRED"};
constexpr Sql kBeginWrite{"begin write transaction", "BEGIN IMMEDIATE"};
constexpr Sql kCommit{"commit", "COMMIT"};
constexpr Sql kRollback{"rollback", "ROLLBACK"};

}  // namespace

void throw_error(sqlite3* db, std::string_view operation) {
  const int code = sqlite3_extended_errcode(db);
  throw StorageError(
      std::string(operation) + ": " + sqlite3_errmsg(db) + " (code " + std::to_string(code) + ")",
      code);
}

Connection open_connection(const std::string& path, int flags) {
  sqlite3* raw = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &raw, flags, nullptr);
  // sqlite3_open_v2 hands back a handle even on failure, to carry the message; own it either way.
  Connection db(raw);
  if (rc != SQLITE_OK) {
    const int code = db ? sqlite3_extended_errcode(db.get()) : rc;
    const std::string message = db ? sqlite3_errmsg(db.get()) : sqlite3_errstr(rc);
    throw StorageError("open '" + path + "': " + message + " (code " + std::to_string(code) + ")",
                       code);
  }
  // Errors carry the detailed code (SQLITE_BUSY_SNAPSHOT, SQLITE_IOERR_WRITE, ...).
  sqlite3_extended_result_codes(db.get(), 1);
  return db;
}

void exec(sqlite3* db, std::string_view operation, const char* sql) {
  if (sqlite3_exec(db, sql, nullptr, nullptr, nullptr) != SQLITE_OK) throw_error(db, operation);
}

std::string query_text(sqlite3* db, std::string_view operation, const char* sql) {
  sqlite3_stmt* raw = nullptr;
  if (sqlite3_prepare_v2(db, sql, -1, &raw, nullptr) != SQLITE_OK) throw_error(db, operation);
  std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)> stmt(raw, &sqlite3_finalize);
  const int rc = sqlite3_step(stmt.get());
  if (rc == SQLITE_DONE) return {};
  if (rc != SQLITE_ROW) throw_error(db, operation);
  const auto* text = sqlite3_column_text(stmt.get(), 0);
  return text ? reinterpret_cast<const char*>(text) : "";
}

Statement::Statement(sqlite3* db, const Sql& sql) : name_(sql.name) {
  sqlite3_stmt* raw = nullptr;
  // PERSISTENT: these statements live as long as the connection; SQLite allocates accordingly.
  if (sqlite3_prepare_v3(db, sql.text, -1, SQLITE_PREPARE_PERSISTENT, &raw, nullptr) != SQLITE_OK) {
    throw_error(db, std::string("prepare ") + sql.name);
  }
  stmt_.reset(raw);
}

void Statement::acquire() {
  if (in_use_) throw std::logic_error(std::string("statement in use twice: ") + name_);
  in_use_ = true;
}

Statement& StatementCache::get(const Sql& sql) {
  auto found = statements_.find(&sql);
  if (found != statements_.end()) return found->second;
  return statements_.try_emplace(&sql, db_, sql).first->second;
}

Query::~Query() {
  // sqlite3_reset repeats the last step's error code; the error was already thrown from step.
  sqlite3_reset(statement_.get());
  sqlite3_clear_bindings(statement_.get());
  statement_.release();
}

void Query::bind_at(int index, std::int64_t value) {
  if (sqlite3_bind_int64(statement_.get(), index, value) != SQLITE_OK) {
    throw_error(db(), std::string("bind ") + statement_.name());
  }
}

void Query::bind_at(int index, double value) {
  if (sqlite3_bind_double(statement_.get(), index, value) != SQLITE_OK) {
    throw_error(db(), std::string("bind ") + statement_.name());
  }
}

void Query::bind_at(int index, std::string_view value) {
  // TRANSIENT: SQLite copies, so temporaries (enum names, formatted ids) are safe to bind.
  if (sqlite3_bind_text64(statement_.get(), index, value.data(), value.size(), SQLITE_TRANSIENT,
                          SQLITE_UTF8) != SQLITE_OK) {
    throw_error(db(), std::string("bind ") + statement_.name());
  }
}

void Query::bind_at(int index, std::nullopt_t) {
  if (sqlite3_bind_null(statement_.get(), index) != SQLITE_OK) {
    throw_error(db(), std::string("bind ") + statement_.name());
  }
}

void Query::bind_at(int index, const std::vector<std::uint8_t>& blob) {
  // A zero-length blob is still a blob, not NULL: zeroblob keeps the column NOT NULL-safe.
  const int rc = blob.empty() ? sqlite3_bind_zeroblob(statement_.get(), index, 0)
                              : sqlite3_bind_blob64(statement_.get(), index, blob.data(),
                                                    blob.size(), SQLITE_TRANSIENT);
  if (rc != SQLITE_OK) throw_error(db(), std::string("bind ") + statement_.name());
}

bool Query::step() {
  const int rc = sqlite3_step(statement_.get());
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  throw_error(db(), statement_.name());
}

void Query::run() {
  while (step()) {}
}

int Query::changes() const { return sqlite3_changes(db()); }

bool Query::is_null(int column) const {
  return sqlite3_column_type(statement_.get(), column) == SQLITE_NULL;
}

std::int64_t Query::int64(int column) const {
  return sqlite3_column_int64(statement_.get(), column);
}

double Query::real(int column) const { return sqlite3_column_double(statement_.get(), column); }

std::string Query::text(int column) const {
  const auto* data = sqlite3_column_text(statement_.get(), column);
  // column_bytes after column_text: the length of the UTF-8 text, embedded NULs included.
  const int size = sqlite3_column_bytes(statement_.get(), column);
  if (data == nullptr) return {};
  return std::string(reinterpret_cast<const char*>(data), static_cast<std::size_t>(size));
}

std::optional<std::string> Query::optional_text(int column) const {
  if (is_null(column)) return std::nullopt;
  return text(column);
}

std::vector<std::uint8_t> Query::blob(int column) const {
  const auto* data =
      static_cast<const std::uint8_t*>(sqlite3_column_blob(statement_.get(), column));
  const int size = sqlite3_column_bytes(statement_.get(), column);
  if (data == nullptr || size <= 0) return {};
  return std::vector<std::uint8_t>(data, data + size);
}

std::optional<std::int64_t> Query::optional_int64(int column) const {
  if (is_null(column)) return std::nullopt;
  return int64(column);
}

Transaction::Transaction(StatementCache& cache, Mode mode) : cache_(cache) {
  Query(cache_, mode == Mode::Write ? kBeginWrite : kBeginRead).run();
}

Transaction::~Transaction() {
  // Some errors (SQLITE_FULL, SQLITE_IOERR, ...) roll back by themselves; autocommit tells.
  if (!open_ || sqlite3_get_autocommit(cache_.db())) return;
  try {
    Query(cache_, kRollback).run();
  } catch (...) {
    // Nothing useful to do in a destructor; SQLite rolls back when the connection closes.
  }
}

void Transaction::commit() {
  Query(cache_, kCommit).run();
  open_ = false;
}

}  // namespace ncqual::storage::sqlite
