// SPDX-License-Identifier: Apache-2.0
#include "ncqual/storage/state_file.hpp"

#include "sqlite.hpp"

#include "ncqual/common/text.hpp"

#include <algorithm>
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

constexpr Sql kQueue{"queue outbox entry",
                     "INSERT INTO outbox (topic, sample_id, content_hash, machine_id, payload, "
                     "awaiting, queued_ns) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7) "
                     "ON CONFLICT (topic, sample_id, content_hash) DO NOTHING"};
constexpr Sql kIndex{"read outbox index",
                     "SELECT topic, sample_id, content_hash, machine_id, awaiting, queued_ns "
                     "FROM outbox ORDER BY queued_ns, rowid"};
constexpr Sql kPayload{"read outbox payload",
                       "SELECT payload FROM outbox "
                       "WHERE topic = ?1 AND sample_id = ?2 AND content_hash = ?3"};
constexpr Sql kAwaiting{"read outbox entry",
                        "SELECT awaiting FROM outbox "
                        "WHERE topic = ?1 AND sample_id = ?2 AND content_hash = ?3"};
constexpr Sql kSetAwaiting{"acknowledge outbox entry",
                           "UPDATE outbox SET awaiting = ?4 "
                           "WHERE topic = ?1 AND sample_id = ?2 AND content_hash = ?3"};
constexpr Sql kDiscard{"remove outbox entry",
                       "DELETE FROM outbox "
                       "WHERE topic = ?1 AND sample_id = ?2 AND content_hash = ?3"};
constexpr Sql kSummary{"summarize outbox",
                       "SELECT count(*), coalesce(min(queued_ns), 0) FROM outbox"};

// Roles are stored as one sorted, comma-separated text: few, short, and read whole.
std::string joined(std::vector<std::string> roles) {
  std::sort(roles.begin(), roles.end());
  roles.erase(std::unique(roles.begin(), roles.end()), roles.end());
  std::string out;
  for (const auto& r : roles) out += (out.empty() ? "" : ",") + r;
  return out;
}
std::vector<std::string> split(const std::string& text) {
  return text.empty() ? std::vector<std::string>{} : split_at(text, ',');
}

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
               "CREATE TABLE IF NOT EXISTS outbox ("
               "  topic        TEXT NOT NULL,"
               "  sample_id    TEXT NOT NULL,"
               "  content_hash TEXT NOT NULL,"
               "  machine_id   TEXT NOT NULL,"
               "  payload      BLOB NOT NULL,"
               "  awaiting     TEXT NOT NULL,"
               "  queued_ns    INTEGER NOT NULL,"
               "  PRIMARY KEY (topic, sample_id, content_hash)"
               ") STRICT;"
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
                     const std::vector<std::string>& erase, const std::vector<OutboxEntry>& queue) {
  Transaction tx(impl_->cache, Transaction::Mode::Write);
  for (const auto& [key, json] : documents) Query(impl_->cache, kUpsert).bind(key, json).run();
  for (const auto& key : erase) Query(impl_->cache, kErase).bind(key).run();
  for (const auto& e : queue) {
    Query(impl_->cache, kQueue)
        .bind(e.topic, e.sample_id, e.content_hash, e.machine_id, e.payload, joined(e.awaiting),
              e.queued_ns)
        .run();
  }
  tx.commit();
}

std::vector<OutboxEntry> StateFile::outbox_index() {
  std::vector<OutboxEntry> out;
  Transaction tx(impl_->cache, Transaction::Mode::Read);
  Query q(impl_->cache, kIndex);
  while (q.step()) {
    OutboxEntry e;
    e.topic = q.text(0);
    e.sample_id = q.text(1);
    e.content_hash = q.text(2);
    e.machine_id = q.text(3);
    e.awaiting = split(q.text(4));
    e.queued_ns = q.int64(5);
    out.push_back(std::move(e));
  }
  return out;
}

std::optional<std::vector<std::uint8_t>> StateFile::outbox_payload(
    const std::string& topic, const std::string& sample_id, const std::string& content_hash) {
  Query q(impl_->cache, kPayload);
  q.bind(topic, sample_id, content_hash);
  if (!q.step()) return std::nullopt;
  return q.blob(0);
}

std::optional<std::vector<std::string>> StateFile::acknowledge(const std::string& topic,
                                                               const std::string& sample_id,
                                                               const std::string& content_hash,
                                                               const std::string& role) {
  Transaction tx(impl_->cache, Transaction::Mode::Write);
  std::vector<std::string> awaiting;
  {
    Query q(impl_->cache, kAwaiting);
    q.bind(topic, sample_id, content_hash);
    if (!q.step()) return std::nullopt;
    awaiting = split(q.text(0));
  }
  const auto it = std::find(awaiting.begin(), awaiting.end(), role);
  if (it == awaiting.end()) return std::nullopt;
  awaiting.erase(it);
  if (awaiting.empty()) {
    Query(impl_->cache, kDiscard).bind(topic, sample_id, content_hash).run();
  } else {
    Query(impl_->cache, kSetAwaiting).bind(topic, sample_id, content_hash, joined(awaiting)).run();
  }
  tx.commit();
  return awaiting;
}

bool StateFile::discard(const std::string& topic, const std::string& sample_id,
                        const std::string& content_hash) {
  Query q(impl_->cache, kDiscard);
  q.bind(topic, sample_id, content_hash);
  q.run();
  return q.changes() > 0;
}

OutboxSummary StateFile::outbox_summary() {
  Query q(impl_->cache, kSummary);
  q.step();
  return OutboxSummary{q.int64(0), q.int64(1)};
}

}  // namespace ncqual::storage
