// SPDX-License-Identifier: Apache-2.0
// The machine report (report/machine_report.hpp) from a historian built here
// (report_historian.hpp): the document is read back by an XML parser of its own
// (inspect_report.py, Debian's python3) and its sections, charts, table and data values are
// compared with the stored data and the deviations worked by hand.
#include "ncqual/report/machine_report.hpp"

#include "report_historian.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

namespace ncqual::report {
namespace {

using nlohmann::json;
using testing::kDay;
using testing::kT0;

class MachineReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> counter{0};
    dir_ = std::filesystem::temp_directory_path() /
           ("ncqual-report-" + std::to_string(getpid()) + "-" + std::to_string(counter++));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }

  // The historian of `machine_id` (built once per test).
  storage::Database historian(const MachineConfig& m) {
    const std::string path = (dir_ / "historian.db").string();
    testing::build_report_historian(path, m);
    return storage::Database::open_readonly(path);
  }

  // The document as inspect_report.py reads it.
  json inspect(const std::string& document) {
    const std::string file = (dir_ / "report.html").string();
    std::ofstream(file, std::ios::binary) << document;
    const std::string command =
        "/usr/bin/python3 " NCQUAL_REPORT_TEST_DIR "/inspect_report.py '" + file + "'";
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
    std::string out;
    char buffer[4096];
    while (pipe && fgets(buffer, sizeof buffer, pipe.get())) out += buffer;
    return json::parse(out);
  }

  static const json* section(const json& doc, const std::string& cls) {
    for (const auto& s : doc["sections"]) {
      if (s["class"] == cls) return &s;
    }
    return nullptr;
  }

  std::filesystem::path dir_;
};

int count(const json& charts, const std::string& kind) {
  int n = 0;
  for (const auto& c : charts) n += c == kind;
  return n;
}

TEST_F(MachineReportTest, EverySectionWithItsChartsAndTheStoredFigures) {
  const MachineConfig m = testing::report_machine("PM1");
  storage::Database db = historian(m);
  MachineReportQuery q;
  q.machine_id = "PM1";
  q.since_ns = kT0;
  q.now_ns = kT0 + 14 * kDay;
  q.machine = &m;
  const MachineReport r = gather_machine_report(db, q);

  // The gathered data, against what was stored.
  ASSERT_TRUE(r.status);
  EXPECT_EQ(r.status->state, MachineState::NeedsIntervention);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.checks.size(), 15u);  // 12 daily + grid + circle + linear run
  ASSERT_TRUE(r.grid);
  EXPECT_EQ(r.grid->check.request_id, "monthly-grid");
  EXPECT_EQ(r.grid->check.error, "");
  EXPECT_EQ(r.grid->check.verdict, Verdict::Fail);  // grid:20 is 0.16 mm off, limit 0.15
  ASSERT_EQ(r.grid->planes.size(), 4u);             // pm1: Z 600, 800, 1000, 1200
  EXPECT_EQ(r.grid->planes[0].points.size(), 54u);  // 9 x 6
  ASSERT_TRUE(r.grid->tolerance_mm);
  EXPECT_DOUBLE_EQ(*r.grid->tolerance_mm, 0.15);
  ASSERT_EQ(r.circles.size(), 1u);
  ASSERT_TRUE(r.circles[0].evaluation) << r.circles[0].check.error;
  ASSERT_TRUE(r.linear_run && r.linear_run->evaluation) << r.linear_run->check.error;
  // ISO 230-2 by hand: every cycle reads +2 µm going up and -2 µm going down, so B = 4 µm,
  // s = 0 and A = 4 µm.
  EXPECT_NEAR(*r.linear_run->evaluation->result.B_mm, 2 * testing::kBacklashHalfMm, 1e-9);
  EXPECT_NEAR(*r.linear_run->evaluation->result.A_mm, 2 * testing::kBacklashHalfMm, 1e-9);
  EXPECT_TRUE(r.budget.evaluation) << r.budget.error;
  EXPECT_FALSE(r.trends.empty());
  EXPECT_EQ(r.markers.size(), 1u);

  const json doc = inspect(machine_report_document(r));
  ASSERT_TRUE(doc["ok"].get<bool>()) << doc["error"];
  EXPECT_TRUE(doc["forbidden"].empty()) << doc["forbidden"].dump();
  EXPECT_EQ(doc["h1"], "Qualification report: PM1");

  const json* state = section(doc, "ncqual-report-state");
  ASSERT_TRUE(state);
  const json* grid = section(doc, "ncqual-report-grid");
  ASSERT_TRUE(grid);
  EXPECT_EQ(count((*grid)["charts"], "deviation-vectors"), 4);
  EXPECT_EQ(count((*grid)["charts"], "point-deviation"), 4);
  const json* linear = section(doc, "ncqual-report-linear");
  ASSERT_TRUE(linear);
  EXPECT_EQ((*linear)["charts"], json::array({"positioning"}));
  const json* circles = section(doc, "ncqual-report-circles");
  ASSERT_TRUE(circles);
  EXPECT_EQ((*circles)["charts"], json::array({"polar"}));
  EXPECT_EQ(doc["traces"], json::array({"CCW", "CW"}));
  // The circle by hand: about the nominal circle, F = 4 µm cos 2θ (+2 µm clockwise), so
  // F max = 6 µm, F min = -4 µm, and H = 2 µm.
  const solver::CircularTestResult& circle = r.circles[0].evaluation->result;
  EXPECT_NEAR(circle.F_max_mm, testing::kCircleOvalMm + testing::kCircleCwOffsetMm, 1e-7);
  EXPECT_NEAR(circle.F_min_mm, -testing::kCircleOvalMm, 1e-7);
  EXPECT_NEAR(*circle.H_mm, testing::kCircleCwOffsetMm, 1e-6);
  const json* trends = section(doc, "ncqual-report-trends");
  ASSERT_TRUE(trends);
  // A chart per metric with two checks or more (center_dx_mm alone); the monthly metrics (one
  // check each) in the table below it.
  EXPECT_EQ((*trends)["charts"], json::array({"trend"}));
  EXPECT_GT(r.trends.size(), 10u);
  const json* budget = section(doc, "ncqual-report-budget");
  ASSERT_TRUE(budget);
  EXPECT_EQ((*budget)["charts"], json::array({"budget"}));
  ASSERT_TRUE(section(doc, "ncqual-report-checks"));
  for (const auto& s : doc["sections"]) EXPECT_TRUE(s["none"].empty()) << s.dump();

  // The hand-worked vectors: stored point minus nominal.
  bool seen7 = false, seen20 = false;
  int fails = 0;
  for (const auto& v : doc["vectors"]) {
    fails += v["class"] == "vector fail";
    if (v["label"] == "grid:7:t0") {
      seen7 = true;
      EXPECT_NEAR(v["dx"].get<double>(), 0.012, 1e-9);
      EXPECT_NEAR(v["dy"].get<double>(), -0.005, 1e-9);
      EXPECT_NEAR(v["value"].get<double>(), 0.013, 1e-9);  // 5-12-13
      EXPECT_EQ(v["class"], "vector pass");
    } else if (v["label"] == "grid:20:t0") {
      seen20 = true;
      EXPECT_NEAR(v["value"].get<double>(), 0.160, 1e-9);
      EXPECT_EQ(v["class"], "vector fail");
    } else {
      EXPECT_NEAR(v["value"].get<double>(), 0, 1e-9) << v["label"];
    }
  }
  EXPECT_TRUE(seen7 && seen20);
  EXPECT_EQ(fails, 1);
  EXPECT_EQ(doc["vectors"].size(), 216u);

  // The ISO 230-2 means: +2 µm up, -2 µm down at every target.
  ASSERT_EQ(doc["means"].size(), 2 * m.global_check->linear_run.targets_mm.size());
  for (const auto& mean : doc["means"]) {
    EXPECT_NEAR(mean["value"].get<double>(),
                mean["class"] == "mean up" ? testing::kBacklashHalfMm : -testing::kBacklashHalfMm,
                1e-9);
  }

  // The table: newest first, the stored verdicts, the ranked causes, the correction.
  const json& rows = doc["checks"];
  ASSERT_EQ(rows.size(), 15u);
  EXPECT_EQ(rows[0][2], "monthly-linear");
  EXPECT_EQ(rows[0][1], "linear_axis_run");
  int pass = 0, fail = 0;
  for (const auto& row : rows) {
    const std::string verdict = row[3];
    pass += verdict.rfind("PASS", 0) == 0;
    fail += verdict.rfind("FAIL", 0) == 0;
  }
  EXPECT_EQ(pass, 13);  // 11 daily, circle, run
  EXPECT_EQ(fail, 2);   // daily-12, grid
  for (const auto& row : rows) {
    if (row[2] != "daily-12") continue;
    EXPECT_EQ(row[4], "not recorded");  // stored without an origin: said, not assumed measured
    EXPECT_EQ(row[5], "monument moved (loose clamping) probe stylus bent");
    EXPECT_EQ(row[6], "machine:work_offset: dx = -30.00 µm");
  }
}

// The budget's Monte Carlo is evaluated once per new result: a memo gives the section back while
// the machine's results up to the report's time are the same ones under the same configuration.
TEST_F(MachineReportTest, TheBudgetIsEvaluatedAgainOnlyWhenItsResultsOrConfigurationChange) {
  MachineConfig m = testing::report_machine("pm1");
  const std::string path = (dir_ / "historian.db").string();
  testing::build_report_historian(path, m);
  storage::Database db = storage::Database::open(path);
  // Twelve daily checks and three monthly ones; the newest is the ISO 230-2 run's, judged a minute
  // after its set of 2 h after day 13 (report_historian.hpp: store_checked).
  const std::int64_t newest = kT0 + 13 * kDay + kDay / 12 + 60'000'000'000;
  EXPECT_EQ(storage::results_up_to(db, "pm1", kT0 + 20 * kDay), (storage::ResultsUpTo{15, newest}));
  EXPECT_EQ(storage::results_up_to(db, "pm1", kT0 + 3 * kDay + 6 * 3'600'000'000'000),
            (storage::ResultsUpTo{3, kT0 + 3 * kDay + 6 * 3'600'000'000'000}));
  EXPECT_EQ(storage::results_up_to(db, "pm9", kT0 + 20 * kDay), (storage::ResultsUpTo{0, 0}));

  BudgetMemo memo;
  const BudgetSection first = machine_budget(db, "pm1", &m, kT0 + 14 * kDay, &memo);
  ASSERT_TRUE(first.evaluation) << first.error;
  EXPECT_EQ(memo.evaluations(), 1u);
  // A day later, nothing new stored: the same section, not evaluated again, at the new time.
  const BudgetSection later = machine_budget(db, "pm1", &m, kT0 + 15 * kDay, &memo);
  EXPECT_EQ(memo.evaluations(), 1u);
  EXPECT_EQ(memo.hits(), 1u);
  EXPECT_EQ(later.until_ns, kT0 + 15 * kDay);
  ASSERT_TRUE(later.evaluation);
  EXPECT_EQ(later.evaluation->capability_monte_carlo.total_mm,
            first.evaluation->capability_monte_carlo.total_mm);
  EXPECT_EQ(later.values, first.values);
  // Without the memo: the same figures (the memo only saves the work).
  const BudgetSection fresh = machine_budget(db, "pm1", &m, kT0 + 15 * kDay);
  EXPECT_EQ(fresh.evaluation->allocation_monte_carlo.total_mm,
            later.evaluation->allocation_monte_carlo.total_mm);
  EXPECT_EQ(memo.evaluations(), 1u);

  // A new result of a metric the budget reads (machine_y's center_dy_mm): evaluated again, from
  // one more value.
  CheckResult dy = testing::monument_result("pm1", 14, 0.002);
  dy.metrics[0].name = "center_dy_mm";
  db.store(dy);
  const BudgetSection after = machine_budget(db, "pm1", &m, kT0 + 15 * kDay, &memo);
  EXPECT_EQ(memo.evaluations(), 2u);
  EXPECT_EQ(after.values, first.values + 1);
  // Another configuration (a tighter allowable total): evaluated again.
  MachineConfig tighter = m;
  tighter.budget->allowable_total_mm *= 0.5;
  EXPECT_NE(budget_fingerprint(*tighter.budget), budget_fingerprint(*m.budget));
  const BudgetSection other = machine_budget(db, "pm1", &tighter, kT0 + 15 * kDay, &memo);
  EXPECT_EQ(memo.evaluations(), 3u);
  ASSERT_TRUE(other.evaluation);
  EXPECT_LT(other.evaluation->allocation_rss.total_mm, after.evaluation->allocation_rss.total_mm);
  // An earlier time holds fewer results: evaluated again, as of then.
  (void)machine_budget(db, "pm1", &tighter, kT0 + 5 * kDay, &memo);
  EXPECT_EQ(memo.evaluations(), 4u);
  // The report takes the memo too.
  MachineReportQuery q;
  q.machine_id = "pm1";
  q.now_ns = kT0 + 15 * kDay;
  q.machine = &m;
  q.budget_memo = &memo;
  (void)machine_budget(db, "pm1", &m, q.now_ns, &memo);
  const std::size_t evaluated = memo.evaluations();
  const MachineReport r = gather_machine_report(db, q);
  EXPECT_EQ(memo.evaluations(), evaluated);
  ASSERT_TRUE(r.budget.evaluation);
  EXPECT_EQ(r.budget.evaluation->capability_monte_carlo.total_mm,
            after.evaluation->capability_monte_carlo.total_mm);
}

// Issue 37, point 4: the report historian's pm1 is NEEDS_INTERVENTION from day 14 (a daily check
// failed). Its errors' total is far within the part's allowance all along, but from day 14 the
// budget is HELD and the report says "NOT within budget" with the hold; a status QUALIFIED after
// it (an intervention, no new result) clears it, also through the memo.
TEST_F(MachineReportTest, AHeldMachineIsNeverWithinBudget) {
  MachineConfig m = testing::report_machine("pm1");
  const std::string path = (dir_ / "historian.db").string();
  testing::build_report_historian(path, m);
  storage::Database db = storage::Database::open(path);
  BudgetMemo memo;
  const BudgetSection before = machine_budget(db, "pm1", &m, kT0 + 14 * kDay - 1, &memo);
  ASSERT_TRUE(before.evaluation) << before.error;
  EXPECT_TRUE(before.evaluation->today.within_budget);
  EXPECT_EQ(before.judgement.verdict, solver::BudgetVerdict::WithinBudget);

  const BudgetSection held = machine_budget(db, "pm1", &m, kT0 + 15 * kDay, &memo);
  ASSERT_TRUE(held.evaluation) << held.error;
  EXPECT_TRUE(held.evaluation->today.within_budget);  // the arithmetic alone
  EXPECT_TRUE(held.standing.held);
  EXPECT_EQ(held.judgement.verdict, solver::BudgetVerdict::Held);
  MachineReportQuery q;
  q.machine_id = "pm1";
  q.now_ns = kT0 + 15 * kDay;
  q.machine = &m;
  q.budget_memo = &memo;
  const std::string sections = machine_report_sections(gather_machine_report(db, q));
  EXPECT_NE(sections.find("NOT within budget: the machine is held: NEEDS_INTERVENTION since "
                          "2026-03-16 00:00 UTC: daily 3 failed: center_dx_mm out of tolerance"),
            std::string::npos)
      << sections;
  EXPECT_EQ(sections.find("): within budget"), std::string::npos);
  // In the plant's zone, as every other time of the report (issue 37 point 7): 00:00 UTC is
  // 01:00 in Berlin in March (CET, +01:00).
  CalendarConfig berlin = default_calendar_config();
  berlin.time_zone = "Europe/Berlin";
  const Calendar calendar(berlin);
  q.calendar = &calendar;
  const std::string local = machine_report_sections(gather_machine_report(db, q));
  EXPECT_NE(local.find("NEEDS_INTERVENTION since 2026-03-16 01:00 +01:00 CET: daily 3 failed"),
            std::string::npos)
      << local;
  q.calendar = nullptr;

  MachineStatus qualified;
  qualified.machine_id = "pm1";
  qualified.state = MachineState::Qualified;
  qualified.time_ns = kT0 + 15 * kDay;
  db.store(qualified);
  const std::size_t evaluated = memo.evaluations();
  const BudgetSection cleared = machine_budget(db, "pm1", &m, kT0 + 16 * kDay, &memo);
  EXPECT_EQ(memo.evaluations(), evaluated);  // no new result: from the memo, the hold read again
  EXPECT_FALSE(cleared.standing.held);
  EXPECT_EQ(cleared.judgement.verdict, solver::BudgetVerdict::WithinBudget);
}

// Issue 37 point 5: a report of measured checks carries no simulated-data banner or marker; one
// with a check of ncqual's simulator says so above everything, and marks that check's row (and a
// chart's check line); a check stored without an origin says "not recorded".
TEST_F(MachineReportTest, SimulatedChecksAreBanneredAndMarkedAndMeasuredOnesAreNot) {
  const MachineConfig m = testing::report_machine("PM1");
  const std::string path = (dir_ / "origin.db").string();
  {
    storage::Database db = storage::Database::open(path);
    for (int day = 1; day <= 2; ++day) {
      CheckResult r = testing::monument_result("PM1", day, 0.001 * day);
      r.origin = DataOrigin::Measured;
      db.store(r);
    }
  }
  MachineReportQuery q;
  q.machine_id = "PM1";
  q.now_ns = kT0 + 10 * kDay;
  q.machine = &m;
  {
    storage::Database db = storage::Database::open_readonly(path);
    const json doc = inspect(machine_report_document(gather_machine_report(db, q)));
    ASSERT_TRUE(doc["ok"].get<bool>()) << doc["error"];
    EXPECT_TRUE(doc["banners"].empty()) << doc["banners"];
    EXPECT_EQ(doc["simulated_badges"], 0);
    ASSERT_EQ(doc["checks"].size(), 2u);
    for (const auto& row : doc["checks"]) EXPECT_EQ(row[4], "measured");
  }
  {
    storage::Database db = storage::Database::open(path);
    CheckResult r = testing::monument_result("PM1", 3, 0.003);
    r.origin = DataOrigin::Simulated;
    db.store(r);
  }
  storage::Database db = storage::Database::open_readonly(path);
  const json doc = inspect(machine_report_document(gather_machine_report(db, q)));
  ASSERT_TRUE(doc["ok"].get<bool>()) << doc["error"];
  EXPECT_EQ(doc["banners"],
            json::array({"SIMULATED DATA : 1 of the 3 checks in the historian (marked SIMULATED) "
                         "were produced by ncqual's simulator, not measured on a machine: the "
                         "verdicts, charts and figures of such checks say nothing about PM1's "
                         "accuracy."}));
  EXPECT_EQ(doc["simulated_badges"], 1);
  ASSERT_EQ(doc["checks"].size(), 3u);
  EXPECT_EQ(doc["checks"][0][2], "daily-3");
  EXPECT_EQ(doc["checks"][0][4], "SIMULATED");
  EXPECT_EQ(doc["checks"][1][4], "measured");
  // The banner opens the first section, above its heading: the first thing a reader sees.
  const std::string html = machine_report_document(gather_machine_report(db, q));
  EXPECT_LT(html.find("<section class=\"ncqual-report-state\">"),
            html.find("ncqual-simulated-banner\""));
  EXPECT_LT(html.find("ncqual-simulated-banner\""), html.find("<h2"));
}

TEST_F(MachineReportTest, SectionsWithoutDataSaySoInOneSentence) {
  const MachineConfig m = testing::report_machine("PM1");
  storage::Database db = historian(m);
  MachineReportQuery q;
  q.machine_id = "PM1";
  q.since_ns = kT0 + 20 * kDay;  // after everything
  q.now_ns = kT0 + 21 * kDay;
  q.machine = &m;
  const json doc = inspect(machine_report_document(gather_machine_report(db, q)));
  ASSERT_TRUE(doc["ok"].get<bool>()) << doc["error"];
  const json* grid = section(doc, "ncqual-report-grid");
  ASSERT_TRUE(grid);
  EXPECT_TRUE((*grid)["charts"].empty());
  EXPECT_EQ((*grid)["none"], json::array({"No monthly grid since 2026-03-22."}));
  EXPECT_EQ((*section(doc, "ncqual-report-linear"))["none"],
            json::array({"No ISO 230-2 linear axis run since 2026-03-22."}));
  EXPECT_EQ((*section(doc, "ncqual-report-circles"))["none"],
            json::array({"No circular test since 2026-03-22."}));
  EXPECT_EQ((*section(doc, "ncqual-report-trends"))["none"],
            json::array({"No metric trend since 2026-03-22."}));
  EXPECT_EQ((*section(doc, "ncqual-report-checks"))["none"],
            json::array({"No check since 2026-03-22."}));
  EXPECT_TRUE((*section(doc, "ncqual-report-checks"))["charts"].empty());
}

TEST_F(MachineReportTest, OneCheckOnlyAndNoConfiguration) {
  const MachineConfig m = testing::report_machine("PM1");
  storage::Database db = historian(m);
  MachineReportQuery q;
  q.machine_id = "PM1";
  q.check_id = "daily-12";
  q.now_ns = kT0 + 14 * kDay;
  const MachineReport r = gather_machine_report(db, q);
  ASSERT_EQ(r.checks.size(), 1u);
  EXPECT_FALSE(r.grid);
  ASSERT_EQ(r.trends.size(), 1u);
  EXPECT_EQ(r.trends[0].metric, "center_dx_mm");
  EXPECT_EQ(r.trends[0].checks, 12u);  // the history up to the check
  const json doc = inspect(machine_report_document(r));
  ASSERT_TRUE(doc["ok"].get<bool>()) << doc["error"];
  EXPECT_EQ((*section(doc, "ncqual-report-grid"))["none"],
            json::array({"No monthly grid in check daily-12."}));
  EXPECT_EQ((*section(doc, "ncqual-report-budget"))["none"],
            json::array({"The error budget needs the machine's configuration (its budget: "
                         "section)."}));
  ASSERT_EQ(doc["checks"].size(), 1u);
  EXPECT_EQ(doc["checks"][0][3].get<std::string>().rfind("FAIL", 0), 0u);
}

// The drift report of issue 37 drew every part check's work offset on every trend (3,688
// lines). A trend chart marks only the restarts of its series (docs/trends.md, "What restarts a
// series"): on center_dx_mm's, the intervention and none of the 600 work offsets, the fixture's
// zero offsets or the grid's volumetric compensation.
TEST_F(MachineReportTest, ATrendChartMarksOnlyTheRestartsOfItsSeries) {
  const MachineConfig m = testing::report_machine("PM1");
  const std::string path = (dir_ / "historian.db").string();
  testing::build_report_historian(path, m);
  {
    storage::Database db = storage::Database::open(path);
    const auto compensate = [&](const std::string& id, const std::string& target, std::int64_t t) {
      Compensation c;
      c.machine_id = "PM1";
      c.request_id = id;
      c.correction = Correction{target, {NamedValue{"dx_mm", 0.001, "mm"}}};
      c.time_ns = t;
      ASSERT_TRUE(db.store(c)) << id;
    };
    for (int i = 0; i < 600; ++i) {
      compensate("part-" + std::to_string(i), "work_offset:PM1",
                 kT0 + kDay + i * (11 * kDay / 600));
    }
    compensate("fixture-1", "fixture:F1", kT0 + 4 * kDay);
    compensate("monthly-grid", "volumetric:PM1", kT0 + 13 * kDay + kDay / 2);
  }
  storage::Database db = storage::Database::open_readonly(path);
  MachineReportQuery q;
  q.machine_id = "PM1";
  q.since_ns = kT0;
  q.now_ns = kT0 + 14 * kDay;
  q.machine = &m;
  const MachineReport r = gather_machine_report(db, q);
  EXPECT_EQ(r.markers.size(), 603u);
  const std::string document = machine_report_document(r);
  std::string chart;
  for (std::size_t at = document.find("<svg"); at != std::string::npos;
       at = document.find("<svg", at + 1)) {
    const std::string svg = document.substr(at, document.find("</svg>", at) - at);
    if (svg.find("<title>PM1: center_dx_mm</title>") != std::string::npos) chart = svg;
  }
  ASSERT_FALSE(chart.empty()) << "no trend chart of center_dx_mm";
  const auto occurrences = [&](const std::string& what) {
    std::size_t n = 0;
    for (auto at = chart.find(what); at != std::string::npos; at = chart.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(occurrences("class=\"marker compensation\""), 0u);
  EXPECT_EQ(occurrences("class=\"marker intervention\""), 1u);
  EXPECT_NE(chart.find("data-label=\"intervention fix-1\""), std::string::npos);
}

TEST_F(MachineReportTest, UnknownMachineOrCheckIsNamed) {
  const MachineConfig m = testing::report_machine("PM1");
  storage::Database db = historian(m);
  MachineReportQuery q;
  q.machine_id = "PM9";
  try {
    (void)gather_machine_report(db, q);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'PM9'"), std::string::npos) << e.what();
  }
  q.machine_id = "PM1";
  q.check_id = "nope-1";
  try {
    (void)gather_machine_report(db, q);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'nope-1'"), std::string::npos) << e.what();
  }
}

TEST_F(MachineReportTest, HostileMachineNameIsEscaped) {
  const std::string hostile = "PM<1>&\"'</section><script>x</script>";
  const MachineConfig m = testing::report_machine(hostile);
  storage::Database db = historian(m);
  MachineReportQuery q;
  q.machine_id = hostile;
  q.now_ns = kT0 + 14 * kDay;
  q.machine = &m;
  const std::string html = machine_report_document(gather_machine_report(db, q));
  EXPECT_EQ(html.find("<script>"), std::string::npos);
  const json doc = inspect(html);
  ASSERT_TRUE(doc["ok"].get<bool>()) << doc["error"];
  EXPECT_TRUE(doc["forbidden"].empty()) << doc["forbidden"].dump();
  EXPECT_EQ(doc["h1"], "Qualification report: " + hostile);  // the parser gives the text back
  EXPECT_EQ(doc["sections"].size(), 7u);
}

TEST_F(MachineReportTest, SectionsFragmentAndStylesheetForTheDashboard) {
  const MachineConfig m = testing::report_machine("PM1");
  storage::Database db = historian(m);
  MachineReportQuery q;
  q.machine_id = "PM1";
  q.now_ns = kT0 + 14 * kDay;
  q.machine = &m;
  const MachineReport r = gather_machine_report(db, q);
  const std::string sections = machine_report_sections(r);
  EXPECT_EQ(sections.rfind("<section class=\"ncqual-report-state\">", 0), 0u);
  EXPECT_EQ(sections.find("<html"), std::string::npos);
  EXPECT_EQ(sections.find("<body"), std::string::npos);
  const std::string css = report_stylesheet();
  EXPECT_NE(css.find("@media print"), std::string::npos);
  EXPECT_NE(css.find("break-before: page"), std::string::npos);
  EXPECT_NE(css.find("break-inside: avoid"), std::string::npos);
  // Deterministic: the same data give the same bytes.
  EXPECT_EQ(machine_report_document(r), machine_report_document(gather_machine_report(db, q)));
}

}  // namespace
}  // namespace ncqual::report
