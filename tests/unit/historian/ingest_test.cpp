// SPDX-License-Identifier: Apache-2.0
// The historian's ingest (services/historian/core/include/ncqual/historian/ingest.hpp) through real
// database faults on real SQLite files: a write lock held by another connection, writes failing
// beyond a file size limit (RLIMIT_FSIZE: what a full disk does to the writes, without root), the
// file removed or replaced while open, and a file damaged before it is opened. In each, nothing is
// acknowledged that is not committed, health says what is wrong, and once the fault clears every
// sample that arrived is stored, in arrival order.
#include "ncqual/historian/ingest.hpp"

#include "storage_test_support.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <fstream>
#include <vector>

namespace ncqual::historian {
namespace {

using storage::StorageHealth;
using storage::testing::make_request;
using storage::testing::RawDb;
using storage::testing::TempDir;
using namespace std::chrono_literals;

// A historian in miniature: the database, the ingest, and what was acknowledged, in order.
struct Historian {
  explicit Historian(const std::string& path) : db(storage::Database::open(path)) {
    db.set_busy_timeout(20ms);
  }
  void receive(const std::string& request_id, Steady now) {
    ingest.submit(
        received_ns++,
        [this, request_id] {
          db.store(make_request(request_id));
          acknowledged.push_back(request_id);  // only once committed
        },
        now);
  }

  storage::Database db;
  std::vector<std::string> acknowledged;
  std::vector<std::pair<StorageHealth, std::string>> changes;
  std::int64_t received_ns = 1000;
  Ingest ingest{IngestOptions{}, [this](StorageHealth h, const std::string& detail) {
                  changes.emplace_back(h, detail);
                }};
};

std::vector<std::string> ids(const std::string& prefix, int n) {
  std::vector<std::string> out;
  for (int i = 0; i < n; ++i) out.push_back(prefix + std::to_string(i));
  return out;
}

TEST(Ingest, ALockedDatabaseKeepsSamplesInOrderAndAcknowledgesOnlyWhatIsCommitted) {
  TempDir dir;
  Historian h(dir.file("h.db"));
  Steady t{};
  h.receive("before", t);
  EXPECT_EQ(h.acknowledged, (std::vector<std::string>{"before"}));

  RawDb other(dir.file("h.db"));
  other.exec("BEGIN EXCLUSIVE");  // e.g. a backup tool holding the write lock
  for (const auto& id : ids("r", 5)) h.receive(id, t);
  EXPECT_EQ(h.acknowledged.size(), 1u);
  EXPECT_EQ(h.ingest.health(), StorageHealth::Degraded);
  EXPECT_EQ(h.ingest.backlog(), 5u);
  EXPECT_EQ(h.ingest.oldest_received_ns(), 1001);
  EXPECT_NE(h.ingest.detail().find("database locked"), std::string::npos) << h.ingest.detail();
  EXPECT_NE(h.ingest.detail().find("5 sample(s) waiting"), std::string::npos);

  // Retries wait for their back-off, and fail while the lock is held.
  h.ingest.retry(t + 100ms);
  EXPECT_EQ(h.ingest.backlog(), 5u);
  h.ingest.retry(t + 300ms);
  EXPECT_EQ(h.ingest.backlog(), 5u);
  ASSERT_EQ(h.changes.size(), 1u) << "the same fault again is not news";

  other.exec("COMMIT");
  h.ingest.retry(t + 10s);
  EXPECT_EQ(h.ingest.backlog(), 0u);
  EXPECT_EQ(h.ingest.health(), StorageHealth::Ok);
  EXPECT_EQ(h.ingest.oldest_received_ns(), 0);
  std::vector<std::string> want{"before"};
  for (const auto& id : ids("r", 5)) want.push_back(id);
  EXPECT_EQ(h.acknowledged, want);
  EXPECT_EQ(RawDb(dir.file("h.db")).count("requests"), 6);
  ASSERT_EQ(h.changes.size(), 2u);
  EXPECT_EQ(h.changes[1].first, StorageHealth::Ok);
}

// A full disk (storage::testing::FullDisk: writes past a file size limit fail).
TEST(Ingest, WritesThatFailStopAcknowledgingAndResumeWhenTheyWorkAgain) {
  TempDir dir;
  Historian h(dir.file("h.db"));
  Steady t{};
  h.receive("before", t);
  StorageHealth during{};
  std::string detail;
  std::size_t waiting = 0;
  {
    const storage::testing::FullDisk full;
    for (const auto& id : ids("r", 3)) h.receive(id, t);
    h.ingest.retry(t + 1s);
    during = h.ingest.health();
    detail = h.ingest.detail();
    waiting = h.ingest.backlog();
  }

  EXPECT_EQ(during, StorageHealth::Failed) << detail;
  EXPECT_TRUE(detail.find("I/O error") != std::string::npos ||
              detail.find("disk full") != std::string::npos)
      << detail;
  EXPECT_EQ(waiting, 3u);
  EXPECT_EQ(h.acknowledged, (std::vector<std::string>{"before"}));

  h.ingest.retry(t + 1h);
  EXPECT_EQ(h.ingest.health(), StorageHealth::Ok) << h.ingest.detail();
  EXPECT_EQ(h.acknowledged, (std::vector<std::string>{"before", "r0", "r1", "r2"}));
  EXPECT_EQ(h.db.quick_check(), "ok");
}

TEST(Ingest, AFileRemovedOrReplacedWhileOpenIsSeenAndHoldsEveryAttempt) {
  TempDir dir;
  const std::string path = dir.file("h.db");
  Historian h(path);
  Steady t{};
  h.receive("before", t);
  EXPECT_EQ(h.db.file_problem(), "");

  // Moved away: the connection would go on writing to a file nobody reads.
  std::filesystem::rename(path, dir.file("moved.db"));
  const std::string removed = h.db.file_problem();
  EXPECT_NE(removed.find("was removed while open"), std::string::npos) << removed;
  EXPECT_NE(removed.find(path), std::string::npos) << removed;
  h.ingest.hold(removed, t);
  EXPECT_EQ(h.ingest.health(), StorageHealth::Failed);
  h.receive("while-held", t);
  h.ingest.retry(t + 1h);
  EXPECT_EQ(h.acknowledged, (std::vector<std::string>{"before"}));
  EXPECT_EQ(h.ingest.backlog(), 1u);

  // What the connection holds can be rescued into a new file.
  h.db.copy_to(dir.file("rescued.db"));
  EXPECT_EQ(RawDb(dir.file("rescued.db")).count("requests"), 1);
  EXPECT_THROW(h.db.copy_to(dir.file("rescued.db")), storage::StorageError);  // never overwrites

  // Another file in its place is not ours either.
  { std::ofstream(path) << "not the historian"; }
  EXPECT_NE(h.db.file_problem().find("replaced by another file"), std::string::npos);
  std::filesystem::remove(path);

  // Moved back: released, what waited is stored at once.
  std::filesystem::rename(dir.file("moved.db"), path);
  EXPECT_EQ(h.db.file_problem(), "");
  h.ingest.hold("", t + 1h);
  EXPECT_EQ(h.ingest.health(), StorageHealth::Ok);
  EXPECT_EQ(h.acknowledged, (std::vector<std::string>{"before", "while-held"}));
}

TEST(Ingest, BeyondItsBoundTheBacklogKeepsNothingMoreAndCountsIt) {
  TempDir dir;
  Historian h(dir.file("h.db"));
  IngestOptions small;
  small.max_backlog = 2;
  Ingest ingest(small, {});
  ingest.hold("held for the test", Steady{});
  for (int i = 0; i < 5; ++i)
    ingest.submit(
        i, [] {}, Steady{});
  EXPECT_EQ(ingest.backlog(), 2u);
  EXPECT_EQ(ingest.dropped(), 3u);
  EXPECT_NE(ingest.detail().find("3 not kept"), std::string::npos) << ingest.detail();
}

// A file whose pages were overwritten in the middle is refused at open, naming it and the first
// problem, and nothing is written to it.
TEST(Ingest, ADamagedFileIsRefusedAtOpenWithItsNameAndFirstProblem) {
  TempDir dir;
  const std::string path = dir.file("h.db");
  {
    auto db = storage::Database::open(path);
    for (int i = 0; i < 400; ++i) db.store(make_request("r" + std::to_string(i)));
  }  // closing the last connection checkpoints the WAL into the file
  const auto size = std::filesystem::file_size(path);
  ASSERT_GT(size, 16u * 4096u);
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size / 2 / 4096 * 4096));
    const std::string garbage(2 * 4096, '\x5a');
    f.write(garbage.data(), static_cast<std::streamsize>(garbage.size()));
  }
  const auto before = std::filesystem::last_write_time(path);
  try {
    storage::Database::open(path);
    ADD_FAILURE() << "a damaged file was opened";
  } catch (const storage::StorageError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find("is corrupt"), std::string::npos) << message;
    EXPECT_NE(message.find("ncqual db recover"), std::string::npos) << message;
  }
  EXPECT_EQ(std::filesystem::last_write_time(path), before);
}

}  // namespace
}  // namespace ncqual::historian
