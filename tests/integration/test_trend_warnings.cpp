// SPDX-License-Identifier: Apache-2.0
// The historian's trend watch with the real processes (docs/trends.md, "Warnings"): the four
// services on the simulated clock run the machine of the committed drift recording
// (tests/data/recordings/machines/d01.yaml: check 3, monument_positioning, measures center_dy_mm
// = -4 um a day from 5 January 2026 against +-0.025 mm and fails on Monday 12 January, the sixth
// working day). The historian must raise a forecast warning on center_dy_mm at a check before
// the one that fails, store it, publish it on ncqual/TrendWarning (a monitor that joins late
// still receives it: durable), and `ncqual status` must show it. The forecast's dates are checked
// against the drift's truth: it reaches -0.025 mm 0.025 / 0.004 = 6.25 days after 5 January
// 2026 00:00 UTC. (A replay of the recording would not do: the replayed sets are judged by a
// solver on the wall clock, so every result carries the replay's time.)
#include "cli_runner.hpp"
#include "harness.hpp"
#include "test_participant.hpp"

#include "ncqual/dds/endpoint.hpp"
#include "ncqual/dds/participant.hpp"
#include "ncqual/dds/topics.hpp"
#include "ncqual/storage/trend.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <thread>

namespace ncqual::testing {
namespace {

using testing_cli::run_cli_stdout;

constexpr std::int64_t kDay = 86'400'000'000'000;
constexpr std::int64_t kDriftSince = 1'767'571'200'000'000'000;  // 2026-01-05T00:00:00Z

TEST(TrendWarnings, ADriftingMachineRaisesAForecastBeforeCheck3FailsAndPublishesIt) {
  Plant plant("trend-warnings", TestDomain::TrendWarnings);
  plant.add_machine("d01", "extends: " + std::string(NCQUAL_SOURCE_DIR) +
                               "/tests/data/recordings/machines/d01.yaml\n");
  plant.write_calendar_plant("  calendar:\n    time_zone: UTC\n", "2026-01-05T00:00:00Z");
  plant.start("historian");
  plant.start("solver");
  plant.start("acquisition", {"--machine", "d01"});
  Process& scheduler = plant.start("scheduler", {"--days", "8"});
  ASSERT_EQ(scheduler.wait(), 0) << plant.log("scheduler");

  // Every result stored, the failing check among them, and a forecast warning on check 3.
  std::optional<storage::MetricValue> failed;
  ASSERT_TRUE(plant.wait_for_db(
      [&](storage::Database& db) {
        failed.reset();
        for (const auto& v : storage::metric_series(db, {"d01", "center_dy_mm"})) {
          if (!v.pass) {
            failed = v;
            break;
          }
        }
        storage::TrendWarningQuery q;
        q.machine_id = "d01";
        q.metric = "center_dy_mm";
        const auto warnings = storage::trend_warnings(db, q);
        return failed && std::any_of(warnings.begin(), warnings.end(),
                                     [](const auto& w) { return w.kind == "forecast"; });
      },
      std::chrono::seconds(120)))
      << plant.log("solver") << plant.log("historian");
  ASSERT_TRUE(failed.has_value());

  auto db = storage::Database::open_readonly(plant.db_path());
  storage::TrendWarningQuery q;
  q.machine_id = "d01";
  q.metric = "center_dy_mm";
  const auto warnings = storage::trend_warnings(db, q);
  const storage::TrendWarningRecord* forecast = nullptr;
  for (const auto& w : warnings) {
    if (w.kind == "forecast") forecast = &w;
  }
  ASSERT_NE(forecast, nullptr) << plant.log("historian");
  EXPECT_EQ(forecast->check_kind, CheckKind::MonumentPositioning);
  EXPECT_EQ(forecast->side, "below");
  // Raised by a check that passed, before the first one that failed.
  EXPECT_LT(forecast->raised_ns, failed->time_ns) << forecast->raised_by;
  EXPECT_NE(forecast->raised_by, failed->request_id);
  const auto raised = db.find_check(forecast->raised_by);
  ASSERT_TRUE(raised && raised->result) << forecast->raised_by;
  EXPECT_EQ(raised->result->verdict, Verdict::Pass);
  // The truth crosses -0.025 mm at day 6.25; the noise moves the fitted line's date by hours.
  ASSERT_TRUE(forecast->expected_crossing_ns && forecast->earliest_crossing_ns);
  const auto day_of = [](std::int64_t ns) {
    return static_cast<double>(ns - kDriftSince) / static_cast<double>(kDay);
  };
  EXPECT_NEAR(day_of(*forecast->expected_crossing_ns), 6.25, 0.5);
  std::cerr << "forecast raised by " << forecast->raised_by << " on day "
            << day_of(forecast->raised_ns) << ", "
            << day_of(failed->time_ns) - day_of(forecast->raised_ns)
            << " days before check 3 failed (day " << day_of(failed->time_ns)
            << "); expected crossing day " << day_of(*forecast->expected_crossing_ns)
            << ", earliest day " << day_of(*forecast->earliest_crossing_ns) << "\n";

  // Published: a monitor that joins now still receives the raise (TRANSIENT_LOCAL).
  ncqual::dds::Participant participant(test_participant(plant));
  ncqual::dds::Reader<ncqual::dds::TrendWarningTopic> monitor(participant);
  std::vector<TrendWarning> received;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  const auto has_raise = [&] {
    return std::any_of(received.begin(), received.end(), [&](const TrendWarning& w) {
      return w.active && w.kind == "forecast" && w.metric == "center_dy_mm" &&
             w.started_ns == forecast->started_ns;
    });
  };
  while (!has_raise() && std::chrono::steady_clock::now() < deadline) {
    for (const auto& in : monitor.take()) {
      EXPECT_TRUE(in.error.empty()) << in.error;
      received.push_back(in.value);
    }
    if (!has_raise()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(has_raise()) << received.size() << " trend warnings received\n"
                           << plant.log("historian");
  for (const auto& w : received) {
    if (w.kind != "forecast" || !w.active || w.metric != "center_dy_mm") continue;
    EXPECT_EQ(w.machine_id, "d01");
    EXPECT_EQ(w.check_kind, CheckKind::MonumentPositioning);
    EXPECT_EQ(w.raised_by, forecast->raised_by);
    EXPECT_EQ(w.time_ns, forecast->raised_ns);
    EXPECT_FALSE(w.text.empty());
    // As of the check that raised it (the stored dates move with every check after it): the
    // near prediction bound reaches the limit first, before the check that fails.
    ASSERT_TRUE(w.expected_crossing_ns && w.earliest_crossing_ns);
    EXPECT_LE(*w.earliest_crossing_ns, *w.expected_crossing_ns);
    EXPECT_LT(*w.earliest_crossing_ns, failed->time_ns);
    EXPECT_NEAR(day_of(*w.expected_crossing_ns), 6.25, 0.5);
    std::cerr << "as raised: expected crossing day " << day_of(*w.expected_crossing_ns)
              << ", earliest day " << day_of(*w.earliest_crossing_ns) << "\n";
  }
  // Said once in the historian's log, at level warning.
  EXPECT_NE(plant.log("historian").find("[warning] trend warning raised: "), std::string::npos);

  // `ncqual status` lists it while it is active (the failing check keeps it so: the line is
  // beyond the limit already).
  const auto status = run_cli_stdout({"status", "--plant", plant.plant_file(), "--json"});
  ASSERT_EQ(status.exit_code, 0) << status.out;
  const auto doc = nlohmann::json::parse(status.out);
  bool listed = false;
  for (const auto& m : doc.at("machines")) {
    if (m.at("machine_id") != "d01") continue;
    for (const auto& w : m.at("warnings")) {
      listed |= w.at("metric") == "center_dy_mm" && w.at("kind") == "forecast";
    }
  }
  EXPECT_EQ(listed, forecast->active()) << status.out;
}

}  // namespace
}  // namespace ncqual::testing
