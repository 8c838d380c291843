// SPDX-License-Identifier: Apache-2.0
// The historian's database in trouble while a plant runs (two machines on a paced simulated
// calendar): a write lock held by another process's connection, writes failing as on a full disk
// (the historian's RLIMIT_FSIZE lowered from outside with prlimit(2), so every write past a few
// bytes fails with EFBIG; no root or tmpfs needed), and the file moved away while open and moved
// back. In each, the historian's heartbeat says so at once (health degraded or failed, with the
// backlog; its log may be on the same full disk), it stores and acknowledges nothing meanwhile,
// and the plant goes on; once it clears, everything is stored: every check complete, none
// retried, and every producer stops with its outbox empty.
#include "harness.hpp"
#include "test_participant.hpp"

#include "ncqual/dds/endpoint.hpp"
#include "ncqual/dds/topics.hpp"
#include "ncqual/common/text.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/resource.h>

#include <fstream>
#include <regex>
#include <set>

namespace ncqual::testing {
namespace {

const char* const kScheduler =
    "  calendar:\n"
    "    time_zone: Europe/Berlin\n"
    "    parts: {cycle_min: 120}\n";

std::string machine(const std::string& id) {
  return "extends: " + std::string(NCQUAL_SOURCE_DIR) + "/deploy/machines/pm1.yaml\n" +
         "machine_id: " + id + "\nglobal_check: null\n";
}

// Waits until `service`'s log holds `text` after offset `from`; the log is the event.
bool wait_for_log(const Plant& plant, const std::string& service, const std::string& text,
                  std::size_t from = 0, std::chrono::seconds timeout = std::chrono::seconds(30)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    const std::string log = plant.log(service);
    if (log.size() > from && log.find(text, from) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

// Waits for a heartbeat of the historian whose health is `health`; returns its detail and backlog
// ("" when none came).
std::string wait_for_health(dds::Reader<dds::HeartbeatTopic>& beats, const std::string& health) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < deadline) {
    for (const auto& in : beats.take()) {
      const Heartbeat& h = in.value;
      if (h.service == "historian" && h.health == health) {
        return h.health + ": " + h.health_detail + " (backlog " + std::to_string(h.outbox_depth) +
               ")";
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return "";
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Waits until the scheduler has issued `more` requests beyond those in its log now: the plant
// goes on while the historian cannot store.
bool plant_goes_on(const Plant& plant, std::size_t more) {
  const std::size_t now = count_of(plant.log("scheduler"), ": requesting ");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < deadline) {
    if (count_of(plant.log("scheduler"), ": requesting ") >= now + more) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

// "" when the outbox in `log` was empty at the stop, or held only samples awaiting roles in
// `stopped` (services stopped before it, which cannot acknowledge any more: the samples go out
// again at the next start); else what it still held.
std::string unacknowledged_at_stop(const std::string& log, const std::set<std::string>& stopped) {
  if (log.find("every sample acknowledged") != std::string::npos) return "";
  static const std::regex kLeft(R"(samples not yet acknowledged \(([^)]*)\))");
  std::smatch left;
  if (!std::regex_search(log, left, kLeft)) return "no outbox report at the stop";
  const std::string groups = left[1].str();
  static const std::regex kGroup(R"(\d+ \S+ awaiting ([a-z, ]+))");
  for (std::sregex_iterator it(groups.begin(), groups.end(), kGroup), end; it != end; ++it) {
    for (const std::string& role : split_at((*it)[1].str(), ',')) {
      const std::string r = role.substr(role.find_first_not_of(' '));
      if (!stopped.count(r)) return groups;
    }
  }
  return "";
}

// Stops the producers in order and checks that each did so with its outbox empty (the historian
// has all they sent; what awaits only a producer stopped before is sent again at its next start),
// and that the historian holds every check the scheduler requested, complete but for the last
// one or two the stop may have cut short, none a retry. Returns "N checks (C complete)".
std::string expect_everything_stored(Plant& plant, const std::vector<Process*>& producers) {
  for (Process* p : producers) {
    EXPECT_TRUE(p->running());
    p->terminate();
    EXPECT_EQ(p->wait(), 0);
  }
  // The order the producers were stopped in: scheduler, acquisition, solver.
  std::set<std::string> stopped;
  for (const char* service : {"scheduler", "acquisition", "solver"}) {
    const std::string log = plant.log(service);
    EXPECT_EQ(unacknowledged_at_stop(log, stopped), "")
        << service << ":\n"
        << log.substr(log.size() > 3000 ? log.size() - 3000 : 0);
    stopped.insert(service);
  }
  const std::size_t requested = count_of(plant.log("scheduler"), ": requesting ");
  auto db = storage::Database::open_readonly(plant.db_path());
  storage::HistoryQuery q;
  q.limit = 0;
  const auto records = db.history(q);
  EXPECT_EQ(records.size(), requested);
  std::size_t complete = 0;
  for (const auto& r : records) {
    // The last request or two may have been cut short by the stop: measured or not, not solved.
    if (r.request && r.measurement && r.result) ++complete;
    EXPECT_FALSE(std::regex_search(r.request_id, std::regex("-r[0-9]+$")))
        << r.request_id << ": a retry, so something waited too long";
  }
  EXPECT_GE(complete + 2, records.size());
  EXPECT_EQ(db.integrity_check(), "ok");
  return std::to_string(records.size()) + " checks (" + std::to_string(complete) + " complete)";
}

TEST(StorageFaults, LockedFullAndMovedAwayTheHistorianHoldsThenStoresEverything) {
  Plant plant("storage-faults", TestDomain::StorageFaults);
  plant.add_machine("sf1", machine("sf1"));
  plant.add_machine("sf2", machine("sf2"));
  plant.write_calendar_plant(kScheduler, "2026-03-02T00:00:00Z");
  Process& historian = plant.start("historian");
  Process& solver = plant.start("solver");
  Process& acquisition = plant.start("acquisition", {"--all"});
  // A month at a simulated hour in 0.18 s: longer than the faults take; stopped after them.
  Process& scheduler = plant.start("scheduler", {"--days", "30", "--speed", "20000"});
  dds::Participant participant(test_participant(plant));
  dds::Reader<dds::HeartbeatTopic> beats(participant);
  dds::Reader<dds::AlarmTopic> alarms(participant);
  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) { return db.count_results() >= 5; }))
      << plant.log("historian");

  // 1. Locked: another connection holds the write lock.
  {
    sqlite3* other = nullptr;
    ASSERT_EQ(sqlite3_open_v2(plant.db_path().c_str(), &other, SQLITE_OPEN_READWRITE, nullptr),
              SQLITE_OK);
    sqlite3_busy_timeout(other, 10000);  // the historian may be committing right now
    ASSERT_EQ(sqlite3_exec(other, "BEGIN EXCLUSIVE", nullptr, nullptr, nullptr), SQLITE_OK);
    beats.take();
    const std::string said = wait_for_health(beats, "degraded");
    EXPECT_NE(said.find("database locked"), std::string::npos) << said;
    EXPECT_TRUE(plant_goes_on(plant, 4));
    sqlite3_exec(other, "COMMIT", nullptr, nullptr, nullptr);
    sqlite3_close(other);
    EXPECT_NE(wait_for_health(beats, "ok"), "");
    // Raised as an alarm, and cleared: the latest of the historian's storage alarm is inactive.
    std::vector<Alarm> storage_alarms;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (std::chrono::steady_clock::now() < deadline &&
           (storage_alarms.empty() || storage_alarms.back().active)) {
      for (const auto& in : alarms.take()) {
        if (in.value.kind == AlarmKind::Storage) storage_alarms.push_back(in.value);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    ASSERT_GE(storage_alarms.size(), 2u);
    EXPECT_TRUE(storage_alarms.front().active);
    EXPECT_NE(storage_alarms.front().text.find("database locked"), std::string::npos)
        << storage_alarms.front().text;
    EXPECT_FALSE(storage_alarms.back().active);
  }

  // 2. Writes fail (the file size limit, as a full disk does).
  {
    rlimit tiny{};
    tiny.rlim_cur = 1024;
    tiny.rlim_max = RLIM_INFINITY;
    rlimit saved{};
    ASSERT_EQ(prlimit(historian.pid(), RLIMIT_FSIZE, &tiny, &saved), 0) << std::strerror(errno);
    beats.take();
    const std::string said = wait_for_health(beats, "failed");
    EXPECT_TRUE(said.find("I/O error") != std::string::npos ||
                said.find("disk full") != std::string::npos)
        << said;
    EXPECT_TRUE(plant_goes_on(plant, 4));
    ASSERT_EQ(prlimit(historian.pid(), RLIMIT_FSIZE, &saved, nullptr), 0);
    EXPECT_NE(wait_for_health(beats, "ok"), "");
    ASSERT_TRUE(historian.running()) << "a failed write must not end the historian";
  }

  // 3. The file moved away while open, and back.
  {
    const std::string moved = plant.db_path() + ".moved";
    const std::size_t from = plant.log("historian").size();
    beats.take();
    fs::rename(plant.db_path(), moved);
    const std::string said = wait_for_health(beats, "failed");
    EXPECT_NE(said.find("was removed while open"), std::string::npos) << said;
    EXPECT_TRUE(wait_for_log(plant, "historian", "everything stored until now is copied to", from))
        << plant.log("historian").substr(from);
    EXPECT_TRUE(plant_goes_on(plant, 4));
    fs::rename(moved, plant.db_path());
    EXPECT_NE(wait_for_health(beats, "ok"), "");
  }

  // Every producer stops with its outbox empty: the historian has all they sent.
  std::cerr << expect_everything_stored(plant, {&scheduler, &acquisition, &solver})
            << " stored through a lock, failing writes and a move\n";
}

// Damaged while the historian was stopped: it refuses the file at start, naming it and the first
// problem, while the plant goes on with every sample kept in the producers' outboxes; `ncqual db
// recover` salvages the file, the operator puts the salvaged one in place and starts the
// historian again, and the producers' resends fill in everything sent meanwhile. The page damaged
// is the `services` table's (the latest heartbeat per service, which the next heartbeats rewrite),
// so after the recovery nothing of the checks may be missing at all.
TEST(StorageFaults, ADamagedFileIsRefusedRecoveredAndRefilledByTheProducers) {
  Plant plant("storage-damaged", TestDomain::StorageDamaged);
  plant.add_machine("sd1", machine("sd1"));
  plant.write_calendar_plant(kScheduler, "2026-03-02T00:00:00Z");
  Process* historian = &plant.start("historian");
  Process& solver = plant.start("solver");
  Process& acquisition = plant.start("acquisition", {"--all"});
  Process& scheduler = plant.start("scheduler", {"--days", "30", "--speed", "20000"});
  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) { return db.count_results() >= 5; }))
      << plant.log("historian");
  historian->terminate();
  ASSERT_EQ(historian->wait(), 0) << plant.log("historian");

  // The services table's page overwritten with 0xFF, as a failing disk or a stray write leaves it.
  const std::string file = plant.db_path();
  const auto sql = [&](const std::string& statement) {
    const Outcome r = run(Launch({"sqlite3", "-readonly", file, statement}));
    EXPECT_EQ(r.exit_code, 0) << statement << ": " << r.err;
    return r.out;
  };
  const std::int64_t page_size = std::stoll(sql("PRAGMA page_size"));
  const std::int64_t page =
      std::stoll(sql("SELECT rootpage FROM sqlite_schema WHERE name = 'services'"));
  ASSERT_GT(page, 1);
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp((page - 1) * page_size);
    const std::string garbage(static_cast<std::size_t>(page_size), '\xff');
    f.write(garbage.data(), static_cast<std::streamsize>(garbage.size()));
  }

  // Refused at start, naming the file, the problem and the remedy; the plant goes on meanwhile.
  const std::size_t from = plant.log("historian").size();
  historian = &plant.start("historian");
  EXPECT_NE(historian->wait(), 0) << plant.log("historian").substr(from);
  const std::string refusal = plant.log("historian").substr(from);
  EXPECT_NE(refusal.find(file), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("ncqual db recover"), std::string::npos) << refusal;
  EXPECT_TRUE(plant_goes_on(plant, 4));

  // Recovered into a new file, put in place of the damaged one, the historian started again.
  const std::string salvaged = file + ".recovered";
  const Outcome recover =
      run(Launch({Plant::executable("ncqual"), "db", "recover", file, salvaged}));
  ASSERT_EQ(recover.exit_code, 0) << recover.out << recover.err;
  fs::rename(file, file + ".damaged");
  fs::remove(file + "-wal");
  fs::remove(file + "-shm");
  fs::rename(salvaged, file);
  historian = &plant.start("historian");
  EXPECT_TRUE(plant_goes_on(plant, 4));

  std::cerr << expect_everything_stored(plant, {&scheduler, &acquisition, &solver})
            << " stored through a damaged file and its recovery\n";
  historian->terminate();
  EXPECT_EQ(historian->wait(), 0);
}

}  // namespace
}  // namespace ncqual::testing
