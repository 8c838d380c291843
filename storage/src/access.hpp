// SPDX-License-Identifier: Apache-2.0
// A Database's connection for the query files of ncqual_storage beside database.cpp
// (trend_store.cpp): its statement cache and its read and write transactions. Private to the
// library.
#pragma once

#include "sqlite.hpp"

#include "ncqual/storage/database.hpp"

#include <functional>
#include <string>

namespace ncqual::storage {

struct DatabaseAccess {
  static sqlite::StatementCache& statements(Database& db);
  // `body` in one read transaction (one snapshot while the historian writes).
  static void read(Database& db, const std::function<void()>& body);
  // `body` in one write transaction; SQLite's failures get `what` in front. Read-only
  // connections throw StorageError (SQLITE_READONLY).
  static void write(Database& db, const std::string& what, const std::function<void()>& body);
};

}  // namespace ncqual::storage
