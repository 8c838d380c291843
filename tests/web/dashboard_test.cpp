// SPDX-License-Identifier: Apache-2.0
// The dashboard as a function (ncqual/web/dashboard.hpp), without HTTP: routes, refusals, bounds,
// escaping and the change token, on a historian written here.
#include "ncqual/web/dashboard.hpp"

#include "ncqual/storage/database.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace ncqual {
namespace {

namespace fs = std::filesystem;

constexpr std::int64_t kSecond = 1'000'000'000;
constexpr std::int64_t kNow = 1'800'000'000 * kSecond;

class Dashboard : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ncqual-web-test-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "pm1.yaml")
        << "extends: " NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml\nmachine_id: pm1\n";
    std::ofstream(dir_ / "plant.yaml") << "plant: unit\nsimulated: true\nhistorian: {database: "
                                          "historian.db}\nmachines: [pm1.yaml]\n";
    auto db = storage::Database::open((dir_ / "historian.db").string());
    store(db, "r<1>", kNow - 60 * kSecond, Verdict::Fail);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static void store(storage::Database& db, const std::string& id, std::int64_t t, Verdict v,
                    DataOrigin origin = DataOrigin::Unknown) {
    CheckResult r;
    r.origin = origin;
    r.machine_id = "pm1";
    r.request_id = id;
    r.kind = CheckKind::MonumentPositioning;
    r.verdict = v;
    r.reason = "<b>out</b> & about";
    r.time_ns = t;
    r.metrics = {{"center_dx_mm", 0.031, "mm", -0.025, 0.025, false}};
    db.store(r);
  }

  web::Dashboard make() {
    return web::Dashboard(load_plant_config((dir_ / "plant.yaml").string()),
                          (dir_ / "historian.db").string(), {}, [] { return kNow; });
  }
  fs::path dir_;
};

web::Reply get(web::Dashboard& d, const std::string& path,
               std::vector<std::pair<std::string, std::string>> params = {}) {
  return d.handle({"GET", path, std::move(params)});
}

TEST_F(Dashboard, PagesAndDocumentsOfWhatIsStored) {
  auto d = make();
  const auto plant = get(d, "/api/v1/plant");
  ASSERT_EQ(plant.status, 200) << plant.body;
  const auto j = nlohmann::json::parse(plant.body);
  EXPECT_EQ(j["status"]["machines"][0]["machine_id"], "pm1");
  EXPECT_EQ(j["failures"][0]["request_id"], "r<1>");
  EXPECT_EQ(j["failures"][0]["verdict"], "FAIL");
  const auto check = get(d, "/checks/r<1>");
  ASSERT_EQ(check.status, 200);
  EXPECT_EQ(check.content_type, "text/html; charset=utf-8");
  // Stored text is escaped, never markup.
  EXPECT_NE(check.body.find("&lt;b&gt;out&lt;/b&gt; &amp; about"), std::string::npos);
  EXPECT_EQ(check.body.find("<b>out</b>"), std::string::npos);
  EXPECT_NE(check.body.find("0.031"), std::string::npos);
  EXPECT_EQ(d.handle({"HEAD", "/", {}}).status, 200);
}

TEST_F(Dashboard, RefusalsSayWhyWithTheirStatus) {
  auto d = make();
  for (const auto& [method, path, params, status] :
       std::vector<std::tuple<std::string, std::string,
                              std::vector<std::pair<std::string, std::string>>, int>>{
           {"POST", "/api/v1/plant", {}, 405},
           {"DELETE", "/", {}, 405},
           {"GET", "/api/v1/machines/pm9", {}, 404},
           {"GET", "/machines/pm9", {}, 404},
           {"GET", "/api/v1/checks/none", {}, 404},
           {"GET", "/nothing", {}, 404},
           {"GET", "/api/v1/machines/pm1", {{"checks", "0"}}, 400},
           {"GET", "/api/v1/machines/pm1", {{"checks", "201"}}, 400},
           {"GET", "/api/v1/machines/pm1", {{"checks", "5"}, {"checks", "6"}}, 400},
           {"GET", "/machines/pm1", {{"days", "367"}}, 400},
           {"GET", "/api/v1/plant", {{"x", "1"}}, 400},
           {"GET", "/api/v1/changes", {{"since", "1;DROP"}}, 400},
           {"GET", "/api/v1/changes", {{"since", std::string(201, '1')}}, 400},
           {"GET", "/api/v1/checks/" + std::string(129, 'c'), {}, 400}}) {
    const auto r = d.handle({method, path, params});
    EXPECT_EQ(r.status, status) << method << " " << path << "\n" << r.body;
    EXPECT_LT(r.body.size(), 4096u) << path;
    if (path.rfind("/api/", 0) == 0) {
      EXPECT_EQ(nlohmann::json::parse(r.body)["error"]["status"], status) << r.body;
    }
  }
  const auto post = d.handle({"POST", "/", {}});
  EXPECT_NE(std::find(post.headers.begin(), post.headers.end(),
                      std::pair<std::string, std::string>{"Allow", "GET, HEAD"}),
            post.headers.end());
}

TEST_F(Dashboard, TheChangeTokenMovesWhenAResultIsStoredAndOnlyThen) {
  auto d = make();
  const auto token = [&](const std::string& since = "") {
    const auto r =
        since.empty() ? get(d, "/api/v1/changes") : get(d, "/api/v1/changes", {{"since", since}});
    EXPECT_EQ(r.status, 200) << r.body;
    return nlohmann::json::parse(r.body);
  };
  const std::string before = token()["token"];
  EXPECT_FALSE(token(before)["changed"]);
  {
    auto db = storage::Database::open((dir_ / "historian.db").string());
    Heartbeat beat;
    beat.service = "historian";
    beat.instance = "h:1";
    beat.state = "running";
    beat.time_ns = kNow;
    db.store(beat);  // a heartbeat is not what the pages show
    EXPECT_EQ(token()["token"], before);
    store(db, "r2", kNow, Verdict::Pass);
  }
  const auto after = token(before);
  EXPECT_TRUE(after["changed"]);
  EXPECT_NE(after["token"], before);
}

// ncqual-web evaluates the error budgets when the historian changes (Dashboard::refresh_budgets),
// so that a machine page finds its budget ready: each machine once per new result of its own.
TEST_F(Dashboard, TheBudgetsAreEvaluatedAgainOnlyForAMachineWithANewResult) {
  auto d = make();
  EXPECT_EQ(d.refresh_budgets(), 1u);  // pm1: configured, with a budget and a stored result
  EXPECT_EQ(d.refresh_budgets(), 0u);  // nothing new
  {
    auto db = storage::Database::open((dir_ / "historian.db").string());
    store(db, "r2", kNow - 30 * kSecond, Verdict::Pass);
  }
  EXPECT_EQ(d.refresh_budgets(), 1u);
  // The machine page takes the section refresh_budgets left: no evaluation of its own.
  const std::size_t evaluated = d.budgets().evaluations();
  const auto page = get(d, "/machines/pm1");
  EXPECT_EQ(page.status, 200);
  EXPECT_NE(page.body.find("ncqual-report-budget"), std::string::npos);
  EXPECT_EQ(d.budgets().evaluations(), evaluated);
  EXPECT_GE(d.budgets().hits(), 1u);
  // A stop asked before the first machine: nothing evaluated.
  {
    auto db = storage::Database::open((dir_ / "historian.db").string());
    store(db, "r3", kNow - 20 * kSecond, Verdict::Pass);
  }
  EXPECT_EQ(d.refresh_budgets([] { return true; }), 0u);
}

// Issue 37 point 7: one clock. The machine page's own tables and the report sections it embeds
// read the same check at the same local time with its offset; nothing on it is UTC. r<1> is at
// 2027-01-15 07:59Z: 08:59 in Berlin (CET, +01:00).
TEST_F(Dashboard, TheMachinePageReadsEveryTimeInThePlantsZone) {
  std::ofstream(dir_ / "plant.yaml")
      << "plant: unit\nsimulated: true\nhistorian: {database: historian.db}\nmachines: [pm1.yaml]\n"
         "scheduler:\n  calendar:\n    time_zone: Europe/Berlin\n";
  {
    auto db = storage::Database::open((dir_ / "historian.db").string());
    store(db, "r2", kNow - 30 * kSecond, Verdict::Pass);  // two checks: a trend chart
  }
  auto d = make();
  const auto page = get(d, "/machines/pm1");
  ASSERT_EQ(page.status, 200) << page.body;
  const std::string& html = page.body;
  const std::string local = "2027-01-15 08:59 +01:00 CET";
  const std::size_t report = html.find("ncqual-report-checks");
  ASSERT_NE(report, std::string::npos) << html;
  EXPECT_NE(html.find(local), std::string::npos) << "the page's failures";
  EXPECT_LT(html.find(local), report) << "the page's own table, before the report's";
  EXPECT_NE(html.find(local, report), std::string::npos) << "the report's checks table";
  EXPECT_NE(html.find("<th>time (Europe/Berlin)</th>"), std::string::npos);
  EXPECT_NE(html.find("date (Europe/Berlin)"), std::string::npos) << "the trend chart's axis";
  EXPECT_EQ(html.find("07:59"), std::string::npos) << "the UTC reading of the check";
  const std::regex utc("\\(UTC\\)|[0-9]{2}:[0-9]{2}(:[0-9]{2})? (\\+00:00 )?UTC");
  EXPECT_FALSE(std::regex_search(html, utc)) << html;
  EXPECT_NE(html.find("data-time-zone=\"Europe/Berlin\""), std::string::npos);
}

// Issue 37 point 5: a machine whose newest check is the simulator's carries a SIMULATED badge and a
// banner on the plant and machine pages, and the check's page says it; once its newest check is
// measured, neither page shows them (the old check's row stays marked). A check stored without an
// origin says "not recorded".
TEST_F(Dashboard, ASimulatedCheckIsBadgedAndBanneredAndAMeasuredOneIsNot) {
  {
    auto db = storage::Database::open((dir_ / "historian.db").string());
    store(db, "sim-1", kNow - 30 * kSecond, Verdict::Pass, DataOrigin::Simulated);
  }
  auto d = make();
  const std::string badge = "nw-badge nw-simulated";
  const std::string banner = "<div class=\"nw-simulated-banner\"";
  for (const char* path : {"/", "/machines/pm1", "/checks/sim-1"}) {
    const auto page = get(d, path);
    ASSERT_EQ(page.status, 200) << path;
    EXPECT_NE(page.body.find(badge), std::string::npos) << path;
    EXPECT_NE(page.body.find(banner), std::string::npos) << path;
    EXPECT_LT(page.body.find(banner), page.body.find("</h1>") + 200) << path << ": not on top";
  }
  EXPECT_NE(get(d, "/machines/pm1").body.find("not recorded"), std::string::npos) << "r<1>";
  const auto plant = nlohmann::json::parse(get(d, "/api/v1/plant").body);
  EXPECT_EQ(plant["status"]["machines"][0]["last_check_origin"], "simulated");
  EXPECT_EQ(nlohmann::json::parse(get(d, "/api/v1/checks/sim-1").body)["origin"], "simulated");
  {
    auto db = storage::Database::open((dir_ / "historian.db").string());
    store(db, "real-1", kNow - 10 * kSecond, Verdict::Pass, DataOrigin::Measured);
  }
  for (const char* path : {"/", "/machines/pm1", "/checks/real-1"}) {
    const auto page = get(d, path);
    ASSERT_EQ(page.status, 200) << path;
    EXPECT_EQ(page.body.find(banner), std::string::npos) << path;
    // The machine page still lists sim-1, badged in its row: not in its title.
    const std::size_t end =
        std::string(path) == "/machines/pm1" ? page.body.find("</h1>") : std::string::npos;
    EXPECT_EQ(page.body.substr(0, end).find(badge), std::string::npos) << path << ": badged";
  }
  const std::string machine = get(d, "/machines/pm1").body;
  EXPECT_NE(machine.find("data-origin=\"simulated\" class=\"nw-simulated-row\""),
            std::string::npos);
  EXPECT_NE(machine.find("data-origin=\"measured\">"), std::string::npos);
}

}  // namespace
}  // namespace ncqual
