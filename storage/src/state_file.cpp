// SPDX-License-Identifier: Apache-2.0
#include "ncqual/state_file.hpp"

#include "sqlite.hpp"

#include <filesystem>

namespace ncqual::storage {

namespace {

using sqlite::Query;
using sqlite::Sql;
using sqlite::Transaction;

// "ncqS": tells a state file from a historian database ("ncqH"-style id of schema.cpp) or any
// other SQLite file.
constexpr std::int32_t kStateApplicationId = 0x6e637153;

constexpr Sql kSelectAll{"load state documents", "SELECT key, json FROM documents ORDER BY key"};
constexpr Sql kUpsert{"save state document",
                      "INSERT INTO documents (key, json) VALUES (?1, ?2) "
                      "ON CONFLICT (key) DO UPDATE SET json = excluded.json"};
constexpr Sql kErase{"erase state document", "DELETE FROM documents WHERE key = ?1"};

}  // namespace

struct StateFile::Impl {
  Impl(sqlite::Connection connection, std::string p)
      : db(std::move(connection)), cache(db.get()), path(std::move(p)) {}
  sqlite::Connection db;
  sqlite::StatementCache cache;
  std::string path;
};

StateFile StateFile::open(const std::string& path) {
  if (path != ":memory:") {
    const auto parent = std::filesystem::path(path).parent_path();
    std::error_code error;
    if (!parent.empty()) std::filesystem::create_directories(parent, error);
    if (error) {
      throw StorageError("open state file '" + path + "': cannot create directory '" +
                         parent.string() + "': " + error.message());
    }
  }
  auto db = sqlite::open_connection(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  sqlite3_busy_timeout(db.get(), 5000);
  const std::string id =
      sqlite::query_text(db.get(), "read application id", "PRAGMA application_id");
  const std::string tables =
      sqlite::query_text(db.get(), "count tables", "SELECT count(*) FROM sqlite_schema");
  if (id != std::to_string(kStateApplicationId) && tables != "0") {
    throw StorageError("open state file '" + path + "': not an ncqual state file (application_id " +
                       id + ", " + tables + " schema objects); refusing to touch it");
  }
  // A process kill never loses a commit in WAL mode with synchronous=NORMAL.
  (void)sqlite::query_text(db.get(), "set journal mode", "PRAGMA journal_mode=WAL");
  sqlite::exec(db.get(), "set synchronous", "PRAGMA synchronous=NORMAL");
  sqlite::exec(db.get(), "create state schema",
               "CREATE TABLE IF NOT EXISTS documents ("
               "  key  TEXT NOT NULL PRIMARY KEY,"
               "  json TEXT NOT NULL"
               ") STRICT, WITHOUT ROWID;"
               "PRAGMA application_id = 1852010835;");
  static_assert(kStateApplicationId == 1852010835, "keep the pragma above in step");
  return StateFile(std::make_unique<Impl>(std::move(db), path));
}

StateFile::StateFile(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
StateFile::StateFile(StateFile&&) noexcept = default;
StateFile& StateFile::operator=(StateFile&&) noexcept = default;
StateFile::~StateFile() = default;

const std::string& StateFile::path() const { return impl_->path; }

std::map<std::string, std::string> StateFile::load() {
  std::map<std::string, std::string> out;
  Transaction tx(impl_->cache, Transaction::Mode::Read);
  Query q(impl_->cache, kSelectAll);
  while (q.step()) out[q.text(0)] = q.text(1);
  return out;
}

void StateFile::save(const std::map<std::string, std::string>& documents,
                     const std::vector<std::string>& erase) {
  Transaction tx(impl_->cache, Transaction::Mode::Write);
  for (const auto& [key, json] : documents) Query(impl_->cache, kUpsert).bind(key, json).run();
  for (const auto& key : erase) Query(impl_->cache, kErase).bind(key).run();
  tx.commit();
}

}  // namespace ncqual::storage
