// SPDX-License-Identifier: Apache-2.0
// Opening: migrations, connection settings, refusing files that are not ours or are too new, and
// read-only handles that read while a writer writes.
#include "storage_test_support.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <thread>

namespace ncqual::storage {
namespace {

using namespace testing;  // storage_test_support.hpp

std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const StorageError& error) {
    return error.what();
  }
  return "(no StorageError)";
}

TEST(StorageSchema, MigratesAnEmptyFileToTheLatestVersion) {
  TempDir dir;
  const std::string path = dir.file("historian.db");
  std::ofstream(path).close();  // an existing, empty file, as a packager's touch would leave it
  ASSERT_EQ(std::filesystem::file_size(path), 0u);

  Database db = Database::open(path);
  EXPECT_GE(Database::latest_schema_version(), 1);
  EXPECT_EQ(db.info().schema_version, Database::latest_schema_version());

  RawDb raw(path);
  EXPECT_EQ(raw.text("PRAGMA user_version"), std::to_string(Database::latest_schema_version()));
  EXPECT_EQ(raw.text("PRAGMA application_id"), "1852010869");  // "ncqu"
  for (const char* table :
       {"machines", "requests", "measurement_sets", "touches", "tracker_points", "results",
        "metrics", "causes", "result_offsets", "checks", "status_changes", "interventions",
        "compensations", "compensation_offsets", "services"}) {
    EXPECT_EQ(raw.count("sqlite_schema", std::string("type = 'table' AND name = '") + table + "'"),
              1)
        << table;
  }
  EXPECT_EQ(db.integrity_check(), "ok");
}

TEST(StorageSchema, ReopenKeepsDataAndDoesNotMigrateAgain) {
  TempDir dir;
  const std::string path = dir.file("historian.db");
  {
    Database db = Database::open(path);
    ASSERT_TRUE(db.store(make_result("r1")));
  }
  std::string schema_before;
  {
    RawDb raw(path);
    schema_before = raw.text("SELECT group_concat(sql, ';') FROM sqlite_schema");
  }
  Database db = Database::open(path);
  EXPECT_EQ(db.info().schema_version, Database::latest_schema_version());
  EXPECT_EQ(db.count_results(), 1);
  EXPECT_FALSE(db.store(make_result("r1")));  // still known after the reopen
  RawDb raw(path);
  EXPECT_EQ(raw.text("SELECT group_concat(sql, ';') FROM sqlite_schema"), schema_before);
}

TEST(StorageSchema, OpenCreatesParentDirectories) {
  TempDir dir;
  const std::string path = dir.file("plant/line-2/historian.db");
  Database db = Database::open(path);
  EXPECT_TRUE(std::filesystem::exists(path));
}

TEST(StorageSchema, ConnectionUsesWalNormalSyncForeignKeysAndABusyTimeout) {
  TempDir dir;
  const std::string path = dir.file("historian.db");
  Database db = Database::open(path);
  ASSERT_TRUE(db.store(make_request("r1")));
  const ConnectionInfo info = db.info();
  EXPECT_EQ(info.path, path);
  EXPECT_FALSE(info.read_only);
  EXPECT_EQ(info.journal_mode, "wal");
  EXPECT_EQ(info.synchronous, 1);  // NORMAL
  EXPECT_TRUE(info.foreign_keys);
  EXPECT_EQ(info.busy_timeout_ms, 5000);

  // WAL is a property of the file: another connection sees it, and commits go to the -wal file.
  RawDb raw(path);
  EXPECT_EQ(raw.text("PRAGMA journal_mode"), "wal");
  EXPECT_TRUE(std::filesystem::exists(path + "-wal"));
}

TEST(StorageSchema, ChildRowsNeedTheirSample) {
  TempDir dir;
  const std::string path = dir.file("historian.db");
  Database db = Database::open(path);
  RawDb raw(path);
  raw.exec("PRAGMA foreign_keys = ON");
  EXPECT_THROW(raw.exec("INSERT INTO metrics VALUES ('orphan', 0, 'x', 1.0, 'mm', 0.0, 2.0, 1)"),
               std::runtime_error);
  // STRICT: a value of the wrong type is refused rather than stored as something else.
  EXPECT_THROW(raw.exec("INSERT INTO machines VALUES ('M1', 'yesterday', 0)"), std::runtime_error);
}

TEST(StorageSchema, RefusesADatabaseFromANewerBuild) {
  TempDir dir;
  const std::string path = dir.file("historian.db");
  { Database db = Database::open(path); }
  const int newer = Database::latest_schema_version() + 1;
  RawDb(path).exec("PRAGMA user_version = " + std::to_string(newer));

  EXPECT_NE(error_of([&] { Database::open(path); }).find("schema version " + std::to_string(newer)),
            std::string::npos);
  EXPECT_NE(error_of([&] { Database::open_readonly(path); }).find("upgrade ncqual"),
            std::string::npos);
  EXPECT_EQ(RawDb(path).text("PRAGMA user_version"), std::to_string(newer));
}

TEST(StorageSchema, RefusesSomeoneElsesSqliteFileWithoutTouchingIt) {
  TempDir dir;
  // One marked as another application's, one with tables and no mark at all.
  const std::string setups[] = {"PRAGMA application_id = 42; CREATE TABLE notes (text TEXT)",
                                "CREATE TABLE notes (text TEXT)"};
  for (std::size_t i = 0; i < std::size(setups); ++i) {
    const std::string& setup = setups[i];
    SCOPED_TRACE(setup);
    const std::string path = dir.file("other-" + std::to_string(i) + ".db");
    {
      RawDb raw(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
      raw.exec(setup);
    }
    EXPECT_NE(error_of([&] { Database::open(path); }).find("is not an ncqual historian database"),
              std::string::npos);
    EXPECT_NE(error_of([&] { Database::open_readonly(path); }).find(path), std::string::npos);
    RawDb raw(path);
    EXPECT_EQ(raw.count("sqlite_schema"), 1);  // still only `notes`
    EXPECT_EQ(raw.text("PRAGMA journal_mode"), "delete");
    EXPECT_EQ(raw.text("PRAGMA user_version"), "0");
  }
}

TEST(StorageSchema, InMemoryDatabaseWorksForTestsOfOtherParts) {
  Database db = Database::open(":memory:");
  EXPECT_TRUE(db.store(testing::make_result("r1")));
  EXPECT_FALSE(db.store(testing::make_result("r1")));
  EXPECT_EQ(db.info().schema_version, Database::latest_schema_version());
}

TEST(StorageSchema, RefusesAFileThatIsNotSqlite) {
  TempDir dir;
  const std::string path = dir.file("notes.txt");
  std::ofstream(path) << "this is not a database, just some text that is long enough to matter";
  const std::string message = error_of([&] { Database::open(path); });
  EXPECT_NE(message.find("not a database"), std::string::npos) << message;
}

// A historian cut short (a copy interrupted, a disk full while copying): refused naming the file
// and the way out, as a damaged page is, not with SQLite's bare message.
TEST(StorageSchema, AHistorianCutShortIsRefusedNamingTheFileAndTheWayOut) {
  TempDir dir;
  const std::string path = dir.file("historian.db");
  {
    auto db = Database::open(path);
    for (int i = 0; i < 50; ++i) db.store(testing::make_result("r" + std::to_string(i)));
  }
  std::filesystem::remove(path + "-wal");
  std::filesystem::remove(path + "-shm");
  std::filesystem::resize_file(path, 100);  // the header's first 100 bytes only
  const std::string message = error_of([&] { Database::open(path); });
  EXPECT_NE(message.find("'" + path + "' is corrupt"), std::string::npos) << message;
  EXPECT_NE(message.find("`ncqual db recover " + path + " NEW_FILE`"), std::string::npos)
      << message;
}

TEST(StorageSchema, ReadOnlyRefusesMissingAndUninitialisedFiles) {
  TempDir dir;
  const std::string missing = dir.file("missing.db");
  EXPECT_NE(error_of([&] { Database::open_readonly(missing); }).find(missing), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(missing));

  const std::string blank = dir.file("blank.db");
  { RawDb raw(blank, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE); }
  EXPECT_NE(error_of([&] { Database::open_readonly(blank); }).find("no ncqual schema"),
            std::string::npos);
}

TEST(StorageSchema, ReadOnlyHandleReadsWhatTheWriterWritesAndNeverWrites) {
  TempDir dir;
  const std::string path = dir.file("historian.db");
  Database writer = Database::open(path);
  ASSERT_TRUE(writer.store(make_result("r1")));

  Database reader = Database::open_readonly(path);
  EXPECT_TRUE(reader.info().read_only);
  EXPECT_EQ(reader.count_results(), 1);

  // The writer goes on while the reader stays open; the reader's next query sees it.
  ASSERT_TRUE(writer.store(make_request("r2")));
  ASSERT_TRUE(writer.store(make_measurement_set("r2")));
  ASSERT_TRUE(writer.store(make_result("r2")));
  EXPECT_EQ(reader.count_results(), 2);
  const auto loaded = reader.load_measurement_set("r2");
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(loaded->touches.size(), 4u);

  try {
    reader.store(make_result("r3"));
    FAIL() << "a read-only handle stored something";
  } catch (const StorageError& error) {
    EXPECT_EQ(error.sqlite_code(), SQLITE_READONLY);
    EXPECT_NE(std::string(error.what()).find("read-only"), std::string::npos) << error.what();
  }
  EXPECT_EQ(writer.count_results(), 2);
}

TEST(StorageSchema, ReadOnlyOpensAfterTheWriterClosed) {
  TempDir dir;
  const std::string path = dir.file("historian.db");
  { ASSERT_TRUE(Database::open(path).store(make_result("r1"))); }
  Database reader = Database::open_readonly(path);
  EXPECT_EQ(reader.count_results(), 1);
}

// A reader in another thread (its own connection) queries while the writer stores: it never
// fails with SQLITE_BUSY, never sees counts go backwards, and never sees half a result.
TEST(StorageSchema, ReaderSeesWholeSamplesWhileAWriterWrites) {
  TempDir dir;
  const std::string path = dir.file("historian.db");
  Database writer = Database::open(path);
  Database reader = Database::open_readonly(path);
  constexpr int kResults = 200;

  std::atomic<bool> done{false};
  std::thread writing([&] {
    for (int i = 0; i < kResults; ++i) {
      writer.store(make_result("r" + std::to_string(i), "M1", 1'000 + i));
    }
    done = true;
  });

  std::int64_t last = 0;
  int reads = 0;
  std::string failure;
  while (failure.empty()) {
    const bool finished = done;
    try {
      const std::int64_t count = reader.count_results("M1");
      if (count < last) failure = "count went back from " + std::to_string(last);
      last = count;
      for (const CheckRecord& record : reader.history(HistoryQuery{"M1", {}, INT64_MIN, 3})) {
        if (!record.result || record.result->metrics.size() != 3 ||
            record.result->likely_causes.size() != 3 || !record.result->correction ||
            record.result->correction->offsets.size() != 2) {
          failure = "partial result " + record.request_id;
        }
      }
    } catch (const StorageError& error) {
      failure = error.what();
    }
    ++reads;
    if (finished) break;
  }
  writing.join();
  EXPECT_EQ(failure, "");
  EXPECT_EQ(reader.count_results("M1"), kResults);
  EXPECT_GT(reads, 1);
}

TEST(StorageSchema, DatabaseMovesWithItsConnection) {
  TempDir dir;
  Database a = Database::open(dir.file("a.db"));
  ASSERT_TRUE(a.store(make_result("r1")));
  Database b = std::move(a);
  EXPECT_EQ(b.count_results(), 1);
  b = Database::open(dir.file("b.db"));
  EXPECT_EQ(b.count_results(), 0);
  EXPECT_TRUE(b.store(make_result("r1")));
}

}  // namespace
}  // namespace ncqual::storage
