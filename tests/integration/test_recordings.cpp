// SPDX-License-Identifier: Apache-2.0
// Recordings (docs/recordings.md) with the real executables: a simulated week of three machines
// recorded by `ncqual record` while the four services run it; the recording replayed by `ncqual
// replay` into another domain where only a historian and a second recorder listen. The replayed
// historian must hold exactly the live one's samples (the same content hashes, so the same ids
// and values, each once), the second recording exactly the first one's messages (the same bytes
// and source timestamps), `replay --resolve` must find nothing changed with the same plant and
// name what changes with a tighter tolerance, and Foxglove's reader must read the file.
#include "cli_runner.hpp"
#include "harness.hpp"

#include "ncqual/dds/convert.hpp"
#include "ncqual/dds/raw.hpp"
#include "ncqual/dds/serialized.hpp"
#include "ncqual/dds/topics.hpp"
#include "ncqual/mcap/mcap.hpp"
#include "ncqual/common/version.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sqlite3.h>

#include <fstream>
#include <algorithm>
#include <map>
#include <set>

namespace ncqual::testing {
namespace {

using testing_cli::run_cli;
using testing_cli::run_cli_stdout;

// The producers' topics a historian stores: what is compared between the live and the replayed
// plant (acknowledgements, heartbeats and commands are the services' own conversation).
const std::vector<std::string> kStored = {"ncqual/CheckRequest",  "ncqual/MeasurementSet",
                                          "ncqual/CheckResult",   "ncqual/Compensation",
                                          "ncqual/MachineStatus", "ncqual/Intervention"};
const std::map<std::string, std::string> kTableOf = {
    {"ncqual/CheckRequest", "requests"},        {"ncqual/MeasurementSet", "measurement_sets"},
    {"ncqual/CheckResult", "results"},          {"ncqual/Compensation", "compensations"},
    {"ncqual/MachineStatus", "status_changes"}, {"ncqual/Intervention", "interventions"}};

std::string machine_file(const std::string& id, int kind) {
  std::string yaml = "extends: " + std::string(NCQUAL_SOURCE_DIR) + "/deploy/machines/pm1.yaml\n" +
                     "machine_id: " + id + "\n";
  if (kind == 0) return yaml + "simulator: {seed: 41}\nfixture: {fixture_id: F-" + id + "}\n";
  if (kind == 1) {
    return yaml + "simulator: {seed: 42}\nfixture: {fixture_id: F-" + id +
           "}\nglobal_check: null\n";
  }
  return yaml + "simulator: {seed: 43, fixture: null}\nfixture: null\nglobal_check: null\n";
}

// One column of a table of the historian's file, sorted.
std::vector<std::string> column(const std::string& db, const std::string& sql) {
  sqlite3* handle = nullptr;
  std::vector<std::string> out;
  if (sqlite3_open_v2(db.c_str(), &handle, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    sqlite3_close(handle);
    return out;
  }
  sqlite3_busy_timeout(handle, 10000);
  sqlite3_stmt* stmt = nullptr;
  if (sqlite3_prepare_v2(handle, sql.c_str(), -1, &stmt, nullptr) == SQLITE_OK) {
    while (sqlite3_step(stmt) == SQLITE_ROW) {
      const auto* text = sqlite3_column_text(stmt, 0);
      out.emplace_back(text != nullptr ? reinterpret_cast<const char*>(text) : "(null)");
    }
  }
  sqlite3_finalize(stmt);
  sqlite3_close(handle);
  std::sort(out.begin(), out.end());
  return out;
}

std::size_t rows(const std::string& db, const std::string& table) {
  const auto c = column(db, "SELECT COUNT(*) FROM " + table);
  return c.empty() ? 0 : std::stoul(c.front());
}

// The messages of `file` per topic as (bytes, publish time), sorted; those of `topics` only.
using Messages =
    std::map<std::string, std::multiset<std::pair<std::vector<std::uint8_t>, std::uint64_t>>>;
Messages messages_of(const mcap::Recording& r, const std::vector<std::string>& topics) {
  Messages out;
  for (const auto& m : r.messages) {
    const std::string& topic = r.channels.at(m.channel_id).topic;
    if (std::find(topics.begin(), topics.end(), topic) == topics.end()) continue;
    out[topic].insert({m.data, m.publish_time});
  }
  return out;
}

// The distinct samples per topic (a sample sent again is recorded again).
std::map<std::string, std::size_t> distinct(const Messages& messages) {
  std::map<std::string, std::size_t> out;
  for (const auto& [topic, set] : messages) {
    std::set<std::vector<std::uint8_t>> bytes;
    for (const auto& m : set) bytes.insert(m.first);
    out[topic] = bytes.size();
  }
  return out;
}

std::vector<std::string> identity_flag(const Plant& plant) {
  if (plant.test_identity().empty()) return {};
  return {"--identity", plant.test_identity()};
}

TEST(Recordings, ASimulatedWeekRecordedReplayedAndRecordedAgainGivesTheSameHistorianAndMessages) {
  Plant live("rec-live", TestDomain::RecordingLive);
  const std::vector<std::string> machines = {"r01", "r02", "r03"};
  for (int i = 0; i < 3; ++i) live.add_machine(machines[i], machine_file(machines[i], i));
  live.write_calendar_plant("  calendar:\n    time_zone: UTC\n    parts: {cycle_min: 240}\n",
                            "2026-11-02T00:00:00Z");
  const std::string recording = (live.dir() / "live.mcap").string();
  Process recorder(
      Launch({NCQUAL_CLI_EXE, "record", "--plant", live.plant_file(), "--out", recording})
          .log_to((live.dir() / "record.log").string()));
  live.start("historian");
  live.start("solver");
  live.start("acquisition", {"--machine", "r01,r02,r03"});
  Process& scheduler = live.start("scheduler", {"--days", "5"});
  ASSERT_EQ(scheduler.wait(), 0) << live.log("scheduler");
  // Every machine's last cycle over in the historian, so that what it stored no longer grows
  // while the recording is compared with it (on a loaded machine a snapshot taken earlier missed
  // the last samples still in flight).
  for (const auto& m : machines) {
    const auto settled = run_cli(
        {"wait", "--plant", live.plant_file(), "--settled", "--machine", m, "--timeout", "120"});
    ASSERT_EQ(settled.exit_code, 0) << settled.out << live.log("historian");
  }

  // Until every stored sample is in the recording too (its chunks are flushed every second).
  const std::string live_db = live.db_path();
  std::map<std::string, std::size_t> stored;
  ASSERT_TRUE(live.wait_for_db(
      [&](storage::Database&) {
        for (const auto& topic : kStored) stored[topic] = rows(live_db, kTableOf.at(topic));
        return stored["ncqual/CheckResult"] != 0 &&
               stored["ncqual/CheckResult"] == stored["ncqual/CheckRequest"];
      },
      std::chrono::seconds(120)))
      << live.log("historian");
  ASSERT_TRUE(Plant::wait_for(
      [&] {
        try {
          return distinct(messages_of(mcap::read_file(recording), kStored)) ==
                 std::map<std::string, std::size_t>([&] {
                   std::map<std::string, std::size_t> nonzero;
                   for (const auto& [t, n] : stored) {
                     if (n != 0) nonzero[t] = n;
                   }
                   return nonzero;
                 }());
        } catch (const mcap::Error&) {
          return false;  // a chunk being written
        }
      },
      std::chrono::seconds(60)))
      << "the recording does not hold what the historian stored\n"
      << live.log("record");
  recorder.terminate();
  ASSERT_EQ(recorder.wait(), 0) << live.log("record");

  const mcap::Recording r = mcap::read_file(recording);
  EXPECT_TRUE(r.indexed);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  EXPECT_EQ(r.compression, (std::set<std::string>{"zstd"}));
  // Every topic has its channel, with its QoS; durable ones were read TRANSIENT_LOCAL.
  EXPECT_EQ(r.channels.size(), dds::ncqual_topics().size());
  for (const auto& [id, c] : r.channels) {
    EXPECT_EQ(c.message_encoding, "cdr") << c.topic;
    EXPECT_EQ(r.schemas.at(c.schema_id).encoding, "omgidl") << c.topic;
    if (c.topic == "ncqual/CheckResult") {
      EXPECT_EQ(r.schemas.at(c.schema_id).name, "ncqual::msg::v2::CheckResult");
      EXPECT_EQ(c.metadata.at("durability"), "TRANSIENT_LOCAL");
      EXPECT_EQ(c.metadata.at("reliability"), "RELIABLE");
      EXPECT_EQ(c.metadata.at("key"), "machine_id");
    }
    if (c.topic == "ncqual/Acknowledgement") {
      EXPECT_EQ(c.metadata.at("durability"), "VOLATILE");
    }
  }
  // A message is the payload as on the wire: the CDR encapsulation header (little-endian CDR).
  ASSERT_FALSE(r.messages.empty());
  EXPECT_EQ(r.messages.front().data[0], 0);
  EXPECT_EQ(r.messages.front().data[1], 1);

  // recording info: per topic and machine, the historian's counts.
  const auto info = run_cli_stdout({"recording", "info", "--json", recording});
  ASSERT_EQ(info.exit_code, 0) << info.out;
  const auto json = nlohmann::json::parse(info.out);
  EXPECT_TRUE(json["indexed"].get<bool>());
  std::map<std::string, std::uint64_t> results_per_machine;
  for (const auto& row : json["per_machine"]) {
    if (row["topic"] == "ncqual/CheckResult") results_per_machine[row["machine"]] = row["messages"];
  }
  {
    auto db = storage::Database::open_readonly(live_db);
    for (const auto& m : machines) {
      EXPECT_GE(results_per_machine[m], static_cast<std::uint64_t>(db.count_results(m))) << m;
      EXPECT_GT(results_per_machine[m], 0u) << m;
    }
  }

  // The replay: only a historian and a second recorder listen on the other domain.
  Plant replayed("rec-replay", TestDomain::RecordingReplay);
  for (int i = 0; i < 3; ++i) replayed.add_machine(machines[i], machine_file(machines[i], i));
  replayed.write_plant("[]");
  replayed.start("historian");
  const Messages live_messages = messages_of(r, kStored);
  std::size_t replayed_count = 0;
  for (const auto& [topic, set] : live_messages) replayed_count += set.size();
  const std::string again = (replayed.dir() / "again.mcap").string();
  std::string topics;
  for (const auto& t : kStored) topics += (topics.empty() ? "" : ",") + t.substr(7);
  Process second(Launch({NCQUAL_CLI_EXE, "record", "--plant", replayed.plant_file(), "--out", again,
                         "--topics", topics, "--compression", "lz4", "--stop-after",
                         std::to_string(replayed_count)})
                     .log_to((replayed.dir() / "record.log").string()));
  std::vector<std::string> replay = {
      "replay",   recording, "--fast",    "--plant", replayed.plant_file(),
      "--topics", topics,    "--readers", "2"};
  for (const auto& w : identity_flag(replayed)) replay.push_back(w);
  const auto replay_run = run_cli(replay);
  ASSERT_EQ(replay_run.exit_code, 0) << replay_run.out;
  EXPECT_NE(replay_run.out.find(std::to_string(replayed_count) + " samples written"),
            std::string::npos)
      << replay_run.out;

  // The replayed historian: exactly the live one's samples, by content hash, each once.
  const std::string replay_db = replayed.db_path();
  ASSERT_TRUE(replayed.wait_for_db(
      [&](storage::Database&) {
        for (const auto& topic : kStored) {
          if (rows(replay_db, kTableOf.at(topic)) != stored[topic]) return false;
        }
        return true;
      },
      std::chrono::seconds(120)))
      << replayed.log("historian");
  for (const auto& topic : kStored) {
    const std::string sql = "SELECT content_hash FROM " + kTableOf.at(topic);
    EXPECT_EQ(column(replay_db, sql), column(live_db, sql)) << topic;
  }
  for (const char* derived : {"touches", "tracker_points", "metrics_v5", "causes"}) {
    EXPECT_EQ(rows(replay_db, derived), rows(live_db, derived)) << derived;
  }
  EXPECT_EQ(rows(replay_db, "conflicts"), 0u);
  EXPECT_GT(stored["ncqual/MeasurementSet"], 0u);

  // The second recording: exactly the first one's messages of these topics.
  ASSERT_TRUE(second.wait_for(std::chrono::seconds(60))) << replayed.log("record");
  EXPECT_EQ(second.wait(), 0) << replayed.log("record");
  const mcap::Recording r2 = mcap::read_file(again);
  EXPECT_EQ(r2.compression, (std::set<std::string>{"lz4"}));
  EXPECT_TRUE(messages_of(r2, kStored) == live_messages)
      << "the recording of the replay differs from the recording replayed";

  // Judged again by this build with the same plant: nothing changed.
  const auto same =
      run_cli_stdout({"replay", recording, "--resolve", "--json", "--plant", live.plant_file()});
  ASSERT_EQ(same.exit_code, 0) << same.out;
  const auto resolved = nlohmann::json::parse(same.out);
  EXPECT_EQ(resolved["sets"].get<std::size_t>(), stored["ncqual/MeasurementSet"]);
  EXPECT_EQ(resolved["changed"], 0);
  EXPECT_EQ(resolved["without_recorded_result"], 0);

  // With r03's daily positioning tolerance cut to 0.1 µm every such check fails now: resolve
  // names each, with the verdict and the metric, and exits 3.
  std::ofstream(replayed.dir() / "r03.yaml")
      << machine_file("r03", 2) << "tolerances:\n  center_dx_mm: 0.0001\n";
  const auto tighter = run_cli_stdout({"replay", recording, "--resolve", "--json", "--plant",
                                       replayed.plant_file(), "--machine", "r03"});
  ASSERT_EQ(tighter.exit_code, 3) << tighter.out;
  const auto changed = nlohmann::json::parse(tighter.out);
  std::size_t positioning = 0;
  for (const auto& c : changed["checks"]) {
    EXPECT_EQ(c["machine"], "r03");
    if (c["kind"] != "monument_positioning") {
      EXPECT_FALSE(c["changed"].get<bool>()) << c.dump();
      continue;
    }
    ++positioning;
    EXPECT_EQ(c["recorded_verdict"], "PASS");
    EXPECT_EQ(c["verdict"], "FAIL");
    bool verdict = false;
    bool metric = false;
    for (const auto& d : c["differences"]) {
      verdict = verdict || d["kind"] == "verdict";
      metric = metric || (d["kind"] == "band" &&
                          d["text"].get<std::string>().find("center_dx_mm") != std::string::npos);
    }
    EXPECT_TRUE(verdict && metric) << c.dump();
  }
  EXPECT_EQ(positioning, 5u);  // one a working day
}

// The committed recordings (tests/data/recordings/README.md) replayed through the real solver and
// historian: their requests and measurement sets go in, and this build's solver must store a
// result for every set that judges it as the recorded result says (verdict, causes, every metric
// within 1e-9 of its recorded value: another CPU's libm may move the last digits).
struct Committed {
  const char* file;
  std::vector<const char*> machines;
  TestDomain domain;
  std::size_t at_least_results;
  std::size_t failed;  // recorded FAIL verdicts
};

void PrintTo(const Committed& c, std::ostream* os) { *os << c.file; }

class CommittedRecordings : public ::testing::TestWithParam<Committed> {};

TEST_P(CommittedRecordings, ReplayedThroughSolverAndHistorianStoreTheRecordedVerdicts) {
  const Committed& c = GetParam();
  const std::string file = std::string(NCQUAL_SOURCE_DIR) + "/tests/data/recordings/" + c.file;
  const mcap::Recording r = mcap::read_file(file);
  std::map<std::string, CheckResult> recorded;  // by request id
  for (const auto& m : r.messages) {
    if (r.channels.at(m.channel_id).topic != "ncqual/CheckResult") continue;
    // Recorded before wire contract 2: contract 1's layout, replayed in contract 2's.
    ASSERT_EQ(r.schemas.at(r.channels.at(m.channel_id).schema_id).name, "ncqual::msg::CheckResult");
    msg::CheckResult wire;
    ASSERT_TRUE(dds::deserialize<dds::CheckResultContract1Topic>(m.data, wire))
        << mcap::location(m);
    std::string error;
    CheckResult result = dds::from_wire(wire, error);
    ASSERT_TRUE(error.empty()) << error;
    recorded[result.request_id] = result;
  }
  ASSERT_GE(recorded.size(), c.at_least_results);
  EXPECT_EQ(std::count_if(recorded.begin(), recorded.end(),
                          [](const auto& r) { return r.second.verdict == Verdict::Fail; }),
            static_cast<std::ptrdiff_t>(c.failed));

  Plant plant("rec-committed", c.domain);
  const std::string machines = std::string(NCQUAL_SOURCE_DIR) + "/tests/data/recordings/machines/";
  for (const char* id : c.machines) {
    plant.add_machine(id, "extends: " + machines + id + ".yaml\n");
  }
  plant.write_plant("[]");
  plant.start("historian");
  plant.start("solver");
  std::vector<std::string> identity = identity_flag(plant);
  // Requests first (the historian reads them), then the sets (historian and solver).
  for (const auto& [topics, readers] : std::vector<std::pair<std::string, std::string>>{
           {"CheckRequest", "1"}, {"MeasurementSet", "2"}}) {
    std::vector<std::string> replay = {
        "replay",   file,   "--fast",    "--plant", plant.plant_file(),
        "--topics", topics, "--readers", readers};
    replay.insert(replay.end(), identity.begin(), identity.end());
    const auto run = run_cli(replay);
    ASSERT_EQ(run.exit_code, 0) << run.out;
  }
  ASSERT_TRUE(plant.wait_for_db(
      [&](storage::Database& db) {
        return db.count_results() >= static_cast<std::int64_t>(recorded.size());
      },
      std::chrono::seconds(120)))
      << plant.log("solver") << plant.log("historian");

  auto db = storage::Database::open_readonly(plant.db_path());
  storage::HistoryQuery q;
  q.limit = 0;
  std::size_t compared = 0;
  for (const auto& rec : db.history(q)) {
    ASSERT_TRUE(rec.result && rec.request && rec.measurement) << rec.request_id;
    const auto it = recorded.find(rec.request_id);
    ASSERT_NE(it, recorded.end()) << rec.request_id << " has no recorded result";
    const CheckResult& want = it->second;
    EXPECT_EQ(rec.result->verdict, want.verdict) << rec.request_id;
    EXPECT_EQ(rec.result->likely_causes, want.likely_causes) << rec.request_id;
    EXPECT_EQ(rec.result->produced_by, version_line("ncqual-solver"));
    ASSERT_EQ(rec.result->metrics.size(), want.metrics.size()) << rec.request_id;
    for (std::size_t i = 0; i < want.metrics.size(); ++i) {
      EXPECT_EQ(rec.result->metrics[i].name, want.metrics[i].name) << rec.request_id;
      EXPECT_NEAR(rec.result->metrics[i].value, want.metrics[i].value,
                  1e-9 * std::max(1.0, std::abs(want.metrics[i].value)))
          << rec.request_id << " " << want.metrics[i].name;
    }
    ++compared;
  }
  EXPECT_EQ(compared, recorded.size());

  // And judged again in process, against the same machines: nothing changed.
  const auto resolved =
      run_cli_stdout({"replay", file, "--resolve", "--plant", plant.plant_file()});
  EXPECT_EQ(resolved.exit_code, 0) << resolved.out;
  EXPECT_NE(resolved.out.find(" 0 changed, 0 without a recorded result"), std::string::npos)
      << resolved.out;
}

// week-3-machines.mcap: a working week of three machines, every check passing (zstd).
// drift-1-machine.mcap: one machine drifting along Y until its daily positioning check fails on
// the sixth working day (lz4).
INSTANTIATE_TEST_SUITE_P(
    Recordings, CommittedRecordings,
    ::testing::Values(
        Committed{
            "week-3-machines.mcap", {"r01", "r02", "r03"}, TestDomain::RecordingCommitted, 100, 0},
        Committed{"drift-1-machine.mcap", {"d01"}, TestDomain::RecordingCommittedDrift, 40, 1}),
    [](const auto& info) {
      std::string name = info.param.file;
      name = name.substr(0, name.find('.'));
      name.erase(std::remove(name.begin(), name.end(), '-'), name.end());
      return name;
    });

}  // namespace
}  // namespace ncqual::testing
