// SPDX-License-Identifier: Apache-2.0
// Thin RAII wrappers over the SQLite C API, private to ncqual_storage: a connection, prepared
// statements kept in a cache so that each is prepared once per connection, one use of a statement
// at a time (bind, step, read, reset), and transactions that roll back unless committed.
#pragma once

#include "ncqual/storage/database.hpp"

#include <sqlite3.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>
#include <string_view>
#include <unordered_map>

namespace ncqual::storage::sqlite {

// A named SQL text. The name says which operation failed when SQLite reports an error ("insert
// metric: UNIQUE constraint failed ..."). Defined as namespace-scope constants: the cache keys on
// their address.
struct Sql {
  const char* name;
  const char* text;
};

// Throws StorageError "<operation>: <sqlite3_errmsg> (code <extended code>)".
[[noreturn]] void throw_error(sqlite3* db, std::string_view operation);

struct ConnectionCloser {
  void operator()(sqlite3* db) const noexcept { sqlite3_close_v2(db); }
};
using Connection = std::unique_ptr<sqlite3, ConnectionCloser>;

// Opens `path` with `flags`; throws StorageError naming the path on failure.
Connection open_connection(const std::string& path, int flags);

// Runs SQL that returns no rows we need (pragmas that set, migration scripts). Not cached: used
// only while opening a connection.
void exec(sqlite3* db, std::string_view operation, const char* sql);

// Runs one statement that is not worth caching (used while opening) and returns the first
// column of its first row as text, "" when it returns no row.
std::string query_text(sqlite3* db, std::string_view operation, const char* sql);

class Statement {
 public:
  Statement(sqlite3* db, const Sql& sql);
  sqlite3_stmt* get() const { return stmt_.get(); }
  const char* name() const { return name_; }

  // A statement serves one Query at a time; a second, nested use would reset the first under
  // its feet. Checked, because the mistake would otherwise show up as rows silently missing.
  void acquire();
  void release() noexcept { in_use_ = false; }

 private:
  struct Finalizer {
    void operator()(sqlite3_stmt* stmt) const noexcept { sqlite3_finalize(stmt); }
  };
  std::unique_ptr<sqlite3_stmt, Finalizer> stmt_;
  const char* name_;
  bool in_use_ = false;
};

// Prepares each Sql the first time it is used on this connection and keeps it for the life of
// the connection. Must be destroyed before the connection.
class StatementCache {
 public:
  explicit StatementCache(sqlite3* db) : db_(db) {}
  Statement& get(const Sql& sql);
  sqlite3* db() const { return db_; }

 private:
  sqlite3* db_;
  std::unordered_map<const Sql*, Statement> statements_;
};

// One use of a cached statement: binds parameters, steps, reads columns. Resets the statement and
// clears its bindings when it goes out of scope, so the next use starts clean and no read snapshot
// outlives the use.
class Query {
 public:
  explicit Query(Statement& statement) : statement_(statement) { statement_.acquire(); }
  Query(StatementCache& cache, const Sql& sql) : Query(cache.get(sql)) {}
  ~Query();
  Query(const Query&) = delete;
  Query& operator=(const Query&) = delete;

  // Binds the arguments to parameters 1..N in order.
  template <typename... Args>
  Query& bind(const Args&... args) {
    int index = 0;
    (bind_at(++index, args), ...);
    return *this;
  }
  void bind_at(int index, std::int64_t value);
  void bind_at(int index, int value) { bind_at(index, static_cast<std::int64_t>(value)); }
  void bind_at(int index, bool value) { bind_at(index, static_cast<std::int64_t>(value)); }
  void bind_at(int index, double value);
  void bind_at(int index, std::string_view value);
  void bind_at(int index, const std::string& value) { bind_at(index, std::string_view(value)); }
  void bind_at(int index, const char* value) { bind_at(index, std::string_view(value)); }
  void bind_at(int index, std::nullopt_t);
  void bind_at(int index, const std::vector<std::uint8_t>& blob);
  template <typename T>
  void bind_at(int index, const std::optional<T>& value) {
    if (value) {
      bind_at(index, *value);
    } else {
      bind_at(index, std::nullopt);
    }
  }

  // True when a row is ready to read, false when the statement has finished.
  bool step();
  // Steps a statement that returns no rows to completion.
  void run();
  // Rows inserted, updated or deleted by this statement (0 after ON CONFLICT DO NOTHING).
  int changes() const;

  bool is_null(int column) const;
  std::int64_t int64(int column) const;
  int int32(int column) const { return static_cast<int>(int64(column)); }
  double real(int column) const;
  std::string text(int column) const;
  std::optional<std::string> optional_text(int column) const;
  std::optional<std::int64_t> optional_int64(int column) const;
  std::vector<std::uint8_t> blob(int column) const;

 private:
  sqlite3* db() const { return sqlite3_db_handle(statement_.get()); }
  Statement& statement_;
};

// BEGIN IMMEDIATE for writes: takes the write lock up front, so a writer waits (busy timeout) at
// BEGIN instead of failing with SQLITE_BUSY when it upgrades a read lock half way through.
// BEGIN DEFERRED for reads: one snapshot for every query of a joined read, while writers go on.
class Transaction {
 public:
  enum class Mode { Read, Write };
  Transaction(StatementCache& cache, Mode mode);
  ~Transaction();
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  void commit();

 private:
  StatementCache& cache_;
  bool open_ = true;
};

}  // namespace ncqual::storage::sqlite
