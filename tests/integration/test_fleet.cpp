// SPDX-License-Identifier: Apache-2.0
// Twenty machines of three kinds against one scheduler, one solver and one historian, for three
// simulated weeks that cross the change to summer time (29 March 2026 in Europe/Berlin) and a
// month end (1 April). Two acquisition processes serve ten machines each (the "cell computer"
// deployment; docs/running.md, "Many machines"). Every check the calendar makes due must be stored
// exactly once, at the time the process defines, and nothing else:
//   - m01..m04 extend pm1 (monument, fixture, laser tracker): the monthly global check on the
//     first shift of the run and again on Wednesday 1 April, before that day's daily checks;
//   - m05..m12 have no global_check: section: the weekly fixture pre-calibration on each Monday;
//   - m13..m20 have no fixture either: the daily monument checks 1-4 only;
//   - every machine: parts (set-point checks) from the end of the period checks to the end of
//     each shift, one every cycle.
// The expected times are worked out here from hand-known facts (the working days, the UTC offset
// before and after the DST change, shift times) and the simulated instruments' durations; the
// scheduler's calendar code is not used to compute them.
#include "cli_runner.hpp"
#include "harness.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/common/check_kinds.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <map>
#include <regex>
#include <set>

namespace ncqual::testing {
namespace {

using testing_cli::run_cli_stdout;

constexpr int kMachines = 20;
constexpr int kDays = 21;
constexpr double kCycleMin = 200;
constexpr std::int64_t kNsPerMin = 60'000'000'000LL;

std::string machine_id(int i) {
  char id[8];
  std::snprintf(id, sizeof id, "m%02d", i);
  return id;
}

enum class Type { Full, Fixture, MonumentOnly };
Type type_of(int i) { return i <= 4 ? Type::Full : i <= 12 ? Type::Fixture : Type::MonumentOnly; }

std::string machine_file(int i) {
  const std::string id = machine_id(i);
  std::string yaml = "extends: " + std::string(NCQUAL_SOURCE_DIR) + "/deploy/machines/pm1.yaml\n" +
                     "machine_id: " + id + "\nsimulator: {seed: " + std::to_string(100 + i) +
                     (type_of(i) == Type::MonumentOnly ? ", fixture: null" : "") + "}\n";
  // Each machine holds its own fixture, so each has its own rotation of configurations.
  if (type_of(i) != Type::MonumentOnly) yaml += "fixture: {fixture_id: F-" + id + "}\n";
  if (type_of(i) != Type::Full) yaml += "global_check: null\n";
  if (type_of(i) == Type::MonumentOnly) yaml += "fixture: null\n";
  return yaml;
}

const char* const kScheduler =
    "  calendar:\n"
    "    time_zone: Europe/Berlin\n"
    "    parts: {cycle_min: 200}\n";

const std::vector<std::string> kMonthly = {
    "global_master_frame", "global_grid", "rotary_w",  "rotary_a",       "rotary_c",
    "circle_xy",           "circle_yz",   "circle_xz", "linear_axis_run"};
const std::vector<std::string> kDaily = {"monument_c_alignment", "monument_tool_length",
                                         "monument_positioning", "monument_c_rotation"};

std::int64_t utc(const std::string& iso) { return parse_iso8601(iso).value(); }

double duration_min(const std::string& kind) {
  return check_kind_info(parse_check_kind(kind).value()).duration_min;
}

// One expected request: kind and request time.
struct Expected {
  std::string kind;
  std::int64_t time_ns;
};

// The requests the process defines for machine i over a run of `days` days, in order.
std::vector<Expected> expected_requests(int i, int days = kDays) {
  std::vector<Expected> out;
  // The run starts Monday 23 March 2026 00:00 UTC. Working days are Monday to Friday; Berlin is
  // UTC+1 until Sunday 29 March 01:00 UTC and UTC+2 from then on.
  const std::int64_t day0 = utc("2026-03-23T00:00:00Z");
  const std::int64_t day_ns = 24 * 60 * kNsPerMin;
  for (int d = 0; d < days; ++d) {
    if (d % 7 >= 5) continue;  // Saturday, Sunday: no shift
    const int offset_h = d < 6 ? 1 : 2;
    const std::int64_t midnight_local = day0 + d * day_ns - offset_h * 60 * kNsPerMin;
    const std::int64_t early = midnight_local + 6 * 60 * kNsPerMin;  // 06:00-14:00
    const std::int64_t late = midnight_local + 14 * 60 * kNsPerMin;  // 14:00-22:00
    const std::int64_t late_end = midnight_local + 22 * 60 * kNsPerMin;
    std::int64_t t = early;
    auto run = [&](const std::string& kind) {
      out.push_back({kind, t});
      t += static_cast<std::int64_t>(duration_min(kind) * kNsPerMin);
    };
    // 0 = Monday 23 March (first ever), 9 = Wednesday 1 April (new month).
    if (type_of(i) == Type::Full && (d == 0 || d == 9)) {
      for (const auto& k : kMonthly) run(k);
    }
    if (type_of(i) != Type::MonumentOnly && d % 7 == 0) run("fixture_precal");
    for (const auto& k : kDaily) run(k);
    // Parts: the first when the period checks end; the next a cycle after each one ends; none
    // starts at or after the shift's end. A new shift starts its parts at its start, or when the
    // part still running from the previous shift ends.
    for (const auto& [start, end] : {std::pair{early, late}, std::pair{late, late_end}}) {
      for (t = std::max(t, start); t < end;) {
        run("part_setpoints");
        const std::int64_t next = t + static_cast<std::int64_t>(kCycleMin * kNsPerMin);
        if (next >= end) break;
        t = next;
      }
    }
  }
  return out;
}

std::string utc_text(std::int64_t ns) {
  char buffer[32];
  return std::string(format_iso8601(ns, buffer));
}

// The stored requests of one machine (any order) are exactly `want`: same kinds at the same
// times, none missing, none extra.
void expect_requests(const std::string& id, std::vector<Expected> got,
                     const std::vector<Expected>& want) {
  std::sort(got.begin(), got.end(),
            [](const Expected& a, const Expected& b) { return a.time_ns < b.time_ns; });
  EXPECT_EQ(got.size(), want.size()) << id;
  for (std::size_t k = 0; k < std::min(got.size(), want.size()); ++k) {
    if (got[k].kind != want[k].kind || got[k].time_ns != want[k].time_ns) {
      ADD_FAILURE() << id << " request " << k << ": stored " << got[k].kind << " at "
                    << utc_text(got[k].time_ns) << ", expected " << want[k].kind << " at "
                    << utc_text(want[k].time_ns);
      return;  // the rest is shifted; one message per machine says enough
    }
  }
}

TEST(Fleet, TwentyMachinesThreeWeeksEveryDueCheckStoredExactlyOnce) {
  Plant plant("fleet", TestDomain::Fleet);
  std::string first_ten, last_ten;
  for (int i = 1; i <= kMachines; ++i) {
    plant.add_machine(machine_id(i), machine_file(i));
    (i <= 10 ? first_ten : last_ten) += (i == 1 || i == 11 ? "" : ",") + machine_id(i);
  }
  plant.write_calendar_plant(kScheduler, "2026-03-23T00:00:00Z");
  plant.start("historian");
  plant.start("solver");
  plant.start("acquisition", {"--machine", first_ten});
  plant.start("acquisition", {"--machine", last_ten});
  Process& scheduler = plant.start("scheduler", {"--days", std::to_string(kDays)});
  // The run takes 15-30 s; one that has not ended in 200 s hangs: say where each service was
  // (the end of its log) rather than leave it to ctest's timeout, which shows nothing.
  if (!scheduler.wait_for(std::chrono::seconds(200))) {
    const auto tail = [&](const std::string& service) {
      const std::string log = plant.log(service);
      return "\n--- end of " + service + ".log ---\n" +
             log.substr(log.size() > 6000 ? log.size() - 6000 : 0);
    };
    FAIL() << "the scheduler's three weeks did not end within 200 s" << tail("scheduler")
           << tail("solver") << tail("historian") << tail("acquisition");
  }
  ASSERT_EQ(scheduler.wait(), 0) << plant.log("scheduler");

  std::size_t expected_total = 0;
  std::map<std::string, std::vector<Expected>> expected;
  for (int i = 1; i <= kMachines; ++i) {
    expected[machine_id(i)] = expected_requests(i);
    expected_total += expected[machine_id(i)].size();
  }
  auto all_stored = [&](storage::Database& db) {
    return db.count_results() >= static_cast<std::int64_t>(expected_total);
  };
  ASSERT_TRUE(plant.wait_for_db(all_stored, std::chrono::seconds(120)))
      << "expected " << expected_total << " results\n"
      << plant.log("historian");

  auto db = storage::Database::open_readonly(plant.db_path());
  storage::HistoryQuery q;
  q.limit = 0;
  const auto records = db.history(q);
  std::map<std::string, std::vector<Expected>> stored;  // by machine, in request-time order
  std::map<std::string, std::map<std::int64_t, double>>
      rotation;  // machine -> time -> configuration
  std::size_t incomplete = 0, not_passed = 0;
  for (const auto& r : records) {
    ASSERT_TRUE(r.request) << r.request_id << " has a result but no request";
    stored[r.machine_id].push_back({std::string(to_string(r.kind)), r.request->time_ns});
    if (r.kind == CheckKind::FixturePreCalibration) {
      for (const auto& p : r.request->parameters) {
        if (p.name == "fixture_configuration") rotation[r.machine_id][r.request->time_ns] = p.value;
      }
    }
    if (!r.measurement || !r.result) ++incomplete;
    if (r.result && r.result->verdict != Verdict::Pass) {
      ++not_passed;
      ADD_FAILURE() << r.request_id << " " << to_string(r.result->verdict) << ": "
                    << r.result->reason;
    }
    // Retries are "<id>-r2", "-r3": none may be needed on a healthy plant.
    EXPECT_FALSE(std::regex_search(r.request_id, std::regex("-r[0-9]+$")))
        << r.request_id << ": a retry, so a request or result was lost";
  }
  std::cerr << records.size() << " checks stored for " << stored.size() << " machines\n";
  EXPECT_EQ(incomplete, 0u);
  EXPECT_EQ(not_passed, 0u);
  EXPECT_EQ(records.size(), expected_total);
  EXPECT_EQ(db.count_results(), static_cast<std::int64_t>(expected_total));

  for (int i = 1; i <= kMachines; ++i) {
    expect_requests(machine_id(i), stored[machine_id(i)], expected[machine_id(i)]);
  }

  // Each machine holds its own fixture: each starts the rotation at configuration 0 and takes
  // the next one each week, whatever the other machines do.
  for (int i = 1; i <= 12; ++i) {
    std::vector<double> got;
    for (const auto& [t, k] : rotation[machine_id(i)]) got.push_back(k);
    EXPECT_EQ(got, (std::vector<double>{0, 1, 2})) << machine_id(i);
  }

  // `ncqual status` shows all twenty, each QUALIFIED, with the last pass and next due of each
  // period its sections allow.
  const auto status = run_cli_stdout({"status", "--json", "--plant", plant.plant_file()});
  ASSERT_EQ(status.exit_code, 0) << status.out;
  const auto json = nlohmann::json::parse(status.out);
  ASSERT_EQ(json["machines"].size(), static_cast<std::size_t>(kMachines));
  for (const auto& m : json["machines"]) {
    const std::string id = m["machine_id"];
    EXPECT_EQ(m["state"], "QUALIFIED") << id << ": " << m["detail"];
    for (const auto& p : m["periods"]) {
      if (p["checks"].empty()) continue;  // e.g. monthly for a machine without a tracker set-up
      EXPECT_FALSE(p["overdue"].get<bool>()) << id << " " << p["name"];
      EXPECT_FALSE(p["last_pass_ns"].is_null()) << id << " " << p["name"];
    }
  }
}

// The machine list is checked before anything joins the domain: a bad list names the bad entry
// and the process exits 2 (usage), so a plant's service manager shows why it did not start.
TEST(Fleet, AcquisitionRefusesABadMachineListNamingTheEntry) {
  Plant plant("fleet-args", TestDomain::FleetArguments);
  plant.add_machine("m01", machine_file(1));
  plant.add_machine("m13", machine_file(13));
  plant.write_calendar_plant(kScheduler, "2026-03-23T00:00:00Z");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--machine", "m01,nope"}, "--machine 'nope' is not configured"},
      {{"--machine", "m01,,m13"}, "--machine 'm01,,m13': an empty machine id"},
      {{"--machine", "m13,m13"}, "--machine 'm13' is named twice"},
      {{"--all", "--machine", "m01"}, "exactly one of --machine"},
      {{}, "exactly one of --machine"},
  };
  for (const auto& [args, message] : cases) {
    const std::size_t before = plant.log("acquisition").size();  // the log is appended to
    Process& acquisition = plant.start("acquisition", args);
    EXPECT_EQ(acquisition.wait(), 2) << message;
    const std::string said = plant.log("acquisition").substr(before);
    EXPECT_NE(said.find(message), std::string::npos) << "expected \"" << message << "\" in:\n"
                                                     << said;
  }
}

// "One scheduler per machine": three schedulers, each serving one machine (--machine) with its
// own state file and its own simulated clock, and one acquisition serving all (--all). Each
// machine gets exactly the checks of the process over eight days (across the DST change), as with
// the shared scheduler, and no scheduler refuses the others' traffic.
TEST(Fleet, OneSchedulerPerMachineGivesEachMachineItsProcess) {
  constexpr int kShortDays = 8;
  const std::vector<int> machines = {5, 13, 14};
  Plant plant("fleet-per-machine", TestDomain::FleetSchedulerPerMachine);
  for (int i : machines) plant.add_machine(machine_id(i), machine_file(i));
  plant.write_calendar_plant(kScheduler, "2026-03-23T00:00:00Z");
  plant.start("historian");
  plant.start("solver");
  plant.start("acquisition", {"--all"});
  std::vector<Process*> schedulers;
  for (int i : machines) {
    schedulers.push_back(&plant.start(
        "scheduler", {"--machine", machine_id(i), "--days", std::to_string(kShortDays)}));
  }
  for (auto* s : schedulers) ASSERT_EQ(s->wait(), 0) << plant.log("scheduler");
  std::size_t total = 0;
  for (int i : machines) total += expected_requests(i, kShortDays).size();
  ASSERT_TRUE(plant.wait_for_db([&](storage::Database& db) {
    return db.count_results() >= static_cast<std::int64_t>(total);
  })) << plant.log("historian");

  auto db = storage::Database::open_readonly(plant.db_path());
  storage::HistoryQuery q;
  q.limit = 0;
  std::map<std::string, std::vector<Expected>> stored;
  for (const auto& r : db.history(q)) {
    ASSERT_TRUE(r.request && r.result) << r.request_id;
    EXPECT_EQ(r.result->verdict, Verdict::Pass) << r.request_id << ": " << r.result->reason;
    stored[r.machine_id].push_back({std::string(to_string(r.kind)), r.request->time_ns});
  }
  EXPECT_EQ(stored.size(), machines.size());
  for (int i : machines) {
    expect_requests(machine_id(i), stored[machine_id(i)], expected_requests(i, kShortDays));
    EXPECT_TRUE(fs::exists(plant.dir() / ("scheduler-" + machine_id(i) + ".db"))) << machine_id(i);
  }
  EXPECT_EQ(plant.log("scheduler").find("refused"), std::string::npos) << plant.log("scheduler");
}

}  // namespace
}  // namespace ncqual::testing
