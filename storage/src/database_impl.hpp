// SPDX-License-Identifier: Apache-2.0
// A Database's insides, private to ncqual_storage: its connection, statement cache and
// transactions (Database::Impl), and the kind of a check as stored. Its methods are defined
// beside their callers: database_open.cpp, database_store.cpp, database_history.cpp.
#pragma once

#include "sqlite.hpp"

#include "ncqual/common/model.hpp"
#include "ncqual/storage/database.hpp"

#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace ncqual::storage {

inline std::int64_t code(CheckKind kind) { return static_cast<std::int64_t>(kind); }

// Kinds are read back as numbers without a range check: a newer build may have appended kinds
// this one does not know (to_string names them "unknown"), and a reader should still list them.
inline CheckKind kind_from(std::int64_t number) { return static_cast<CheckKind>(number); }

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

  // Runs `body` in one write transaction and returns what it returns; SQLite failures get `what`
  // (e.g. "store CheckResult 'r-17'") in front so the historian's log says which sample failed.
  template <typename Body>
  auto write(const std::string& what, Body&& body) {
    if (read_only) {
      throw StorageError(what + ": the database '" + path + "' is open read-only", SQLITE_READONLY);
    }
    try {
      sqlite::Transaction transaction(statements, sqlite::Transaction::Mode::Write);
      // A duplicate changed nothing; committing it costs nothing either and keeps one path.
      return committed(transaction, body);
    } catch (const StorageError& error) {
      if (error.sqlite_code() == 0) throw;
      throw StorageError(what + ": " + error.what(), error.sqlite_code());
    }
  }

  // Runs `body` in one read transaction and returns what it returns: every query of a joined read
  // sees the same snapshot while the historian keeps writing.
  template <typename Body>
  auto read(Body&& body) {
    sqlite::Transaction transaction(statements, sqlite::Transaction::Mode::Read);
    return committed(transaction, body);
  }

  // What `body` returns (if anything), once it has run and `transaction` is committed.
  template <typename Body>
  static auto committed(sqlite::Transaction& transaction, Body& body) {
    if constexpr (std::is_void_v<std::invoke_result_t<Body&>>) {
      body();
      transaction.commit();
    } else {
      auto value = body();
      transaction.commit();
      return value;
    }
  }

  // --- for the stores (database_store.cpp) ---

  // A sample whose identity is already stored: the same content is a duplicate; other content is
  // a conflict, kept whole in `conflicts` beside the first (which stays as it is). A row stored
  // before version 4, or a caller without a hash, cannot be compared: a duplicate.
  template <typename Model, typename... Identity>
  StoreResult already_stored(const sqlite::Sql& select_hash, const char* topic, const Model& sample,
                             const Origin& origin, const Identity&... identity);

  void touch_machine(const std::string& machine_id, std::int64_t time_ns);

  // Records that a part of check `request_id` arrived. A request, its measurement set and its
  // result must agree on machine and kind: a disagreement is a producer's bug, refused loudly
  // rather than merged into one check with two machines.
  void note_check(const sqlite::Sql& upsert, const char* type, const std::string& request_id,
                  const std::string& machine_id, CheckKind kind, std::int64_t time_ns);

  // Named values of a request's row in a (request_id, idx, name, value, unit) table: request and
  // measurement parameters, result offsets.
  void store_named_values(const sqlite::Sql& insert, const std::string& request_id,
                          const std::vector<NamedValue>& values);

  // --- for the queries (database_history.cpp) ---

  std::vector<NamedValue> load_named_values(const sqlite::Sql& select,
                                            const std::string& request_id);
  std::optional<CheckRequest> load_request(const std::string& request_id);
  // The header of a measurement set (with its parameters); the counts go into `summary`.
  std::optional<MeasurementSet> load_measurement_header(const std::string& request_id,
                                                        MeasurementSummary* summary);
  std::optional<CheckResult> load_result(const std::string& request_id);
  std::optional<CheckRecord> load_record(const std::string& request_id);

  // --- for the connection's settings (database_open.cpp) ---

  std::string pragma_text(const sqlite::Sql& sql);
  std::int64_t pragma_int(const sqlite::Sql& sql);
};

// A Database's Impl, for the library's query files beside database_*.cpp (trend_store.cpp,
// changes.cpp): its statement cache and its read and write transactions.
struct DatabaseAccess {
  static Database::Impl& impl(Database& db) { return *db.impl_; }
};

}  // namespace ncqual::storage
