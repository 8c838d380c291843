// SPDX-License-Identifier: Apache-2.0
// The dashboard test's historian (dashboard_in_chromium.py): a plant of two machines and its
// historian written with storage::Database, as the historian would have stored it.
//
//   ncqual_web_fixture make DIR SOURCE_DIR   DIR/plant.yaml (machines pm1, pm2 extending the
//       source tree's deploy/machines/pm1.yaml) and DIR/historian.db: ten days of monument
//       checks per machine up to an hour ago, pm1's newest a FAIL (reason, causes, correction,
//       a compensation) that holds it (NEEDS_INTERVENTION), pm2 QUALIFIED, an active forecast
//       warning on pm1's center_dx_mm, one ended, and a heartbeat; pm1's checks are simulated
//       (ncqual's simulator), pm2's measured;
//   ncqual_web_fixture add DIR ID            one more check of pm1 now, request id ID, a FAIL
//       with center_dx_mm = 0.0777 mm, simulated, and the status change it leads to.
// Times are the wall clock's, so that due dates are as a running plant's.
#include "ncqual/common/clock.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/storage/trend.hpp"

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

namespace {

using namespace ncqual;

constexpr std::int64_t kSecond = 1'000'000'000;
constexpr std::int64_t kHour = 3600 * kSecond;
constexpr std::int64_t kDay = 24 * kHour;

void store_check(storage::Database& db, const std::string& machine, const std::string& id,
                 std::int64_t t, double dx, bool fail) {
  const DataOrigin origin = machine == "pm1" ? DataOrigin::Simulated : DataOrigin::Measured;
  CheckRequest request;
  request.machine_id = machine;
  request.request_id = id;
  request.kind = CheckKind::MonumentPositioning;
  request.requested_by = "scheduler";
  request.time_ns = t;
  db.store(request);
  MeasurementSet set;
  set.machine_id = machine;
  set.request_id = id;
  set.kind = CheckKind::MonumentPositioning;
  set.instrument = "touch_probe";
  set.frame = "machine";
  set.time_ns = t + kSecond;
  set.origin = origin;
  for (int i = 0; i < 6; ++i) {
    Touch touch;
    touch.feature = "hole_edge";
    touch.axes = AxisPosition{1200.0 + i, 800.0, 145.0, 0.0, 0.0, 0.0};
    touch.approach = Eigen::Vector3d(1, 0, 0);
    set.touches.push_back(touch);
  }
  db.store(set);
  CheckResult result;
  result.machine_id = machine;
  result.request_id = id;
  result.kind = CheckKind::MonumentPositioning;
  result.verdict = fail ? Verdict::Fail : Verdict::Pass;
  result.time_ns = t + 2 * kSecond;
  result.produced_by = "ncqual-solver (web test)";
  result.origin = origin;
  result.metrics = {{"center_dx_mm", dx, "mm", -0.025, 0.025, std::abs(dx) <= 0.025},
                    {"center_dy_mm", -0.0031, "mm", -0.025, 0.025, true},
                    {"face_dz_mm", 0.0042, "mm", -0.025, 0.025, true}};
  if (fail) {
    result.reason = "center_dx_mm out of tolerance";
    result.likely_causes = {"machine shifted on its foundation", "monument knocked"};
    result.correction = Correction{"machine:work_offset", {{"dx_mm", -dx, "mm"}}};
    Compensation c;
    c.machine_id = machine;
    c.request_id = id;
    c.correction = *result.correction;
    c.time_ns = t + 3 * kSecond;
    db.store(c);
  }
  db.store(result);
  MachineStatus status;
  status.machine_id = machine;
  status.request_id = id;
  status.state = fail ? MachineState::NeedsIntervention : MachineState::Qualified;
  status.last_kind = CheckKind::MonumentPositioning;
  status.last_verdict = result.verdict;
  status.detail =
      fail ? "held by " + id + ": center_dx_mm out of tolerance" : "monument_positioning passed";
  status.time_ns = t + 4 * kSecond;
  db.store(status);
}

void write(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

int make(const std::filesystem::path& dir, const std::string& source_dir) {
  std::filesystem::create_directories(dir);
  const std::string base = source_dir + "/deploy/machines/pm1.yaml";
  write(dir / "pm1.yaml", "extends: " + base + "\nmachine_id: pm1\n");
  write(dir / "pm2.yaml",
        "extends: " + base + "\nmachine_id: pm2\ndescription: Five-axis post mill, bay 4\n");
  write(dir / "plant.yaml",
        "plant: web-test\nsimulated: true\nhistorian:\n  database: historian.db\nmachines: "
        "[pm1.yaml, pm2.yaml]\n"
        "web:\n  bind: 127.0.0.1\n  port: 8470\n"
        "scheduler:\n  calendar:\n    time_zone: Europe/Berlin\n");  // times in CET/CEST
  auto db = storage::Database::open((dir / "historian.db").string());
  const std::int64_t now = WallClock().now_ns();
  for (int day = 10; day >= 1; --day) {
    const std::int64_t t = now - day * kDay + 23 * kHour;  // the newest an hour ago
    // center_dx_mm drifts 2.1 um a day; the newest is out of tolerance.
    store_check(db, "pm1", "pm1-day-" + std::to_string(11 - day), t,
                day == 1 ? 0.0271 : 0.002 + 0.0021 * (10 - day), day == 1);
    store_check(db, "pm2", "pm2-day-" + std::to_string(11 - day), t + 10 * kSecond,
                0.001 - 0.0001 * day, false);
  }
  // The trend watch's warnings, as the historian keeps them: an active forecast on pm1 and one
  // that a later check ended.
  storage::TrendWarningRecord forecast;
  forecast.machine_id = "pm1";
  forecast.metric = "center_dx_mm";
  forecast.check_kind = CheckKind::MonumentPositioning;
  forecast.kind = "forecast";
  forecast.side = "above";
  forecast.started_ns = now - 4 * kDay;
  forecast.raised_by = "pm1-day-7";
  forecast.raised_ns = now - 4 * kDay;
  forecast.expected_crossing_ns = now + 3 * kDay;
  forecast.earliest_crossing_ns = now + kDay;
  forecast.text =
      "center_dx_mm rises 2.1 um a day and reaches its upper limit 0.025 mm in about "
      "3 days";
  storage::apply_trend_warnings(db, "pm1", "center_dx_mm", {forecast}, "pm1-day-7", now - 4 * kDay);
  storage::TrendWarningRecord ewma = forecast;
  ewma.metric = "face_dz_mm";
  ewma.kind = "ewma";
  ewma.expected_crossing_ns.reset();
  ewma.earliest_crossing_ns.reset();
  ewma.text = "face_dz_mm: the EWMA left its control limits";
  storage::apply_trend_warnings(db, "pm1", "face_dz_mm", {ewma}, "pm1-day-7", now - 4 * kDay);
  storage::apply_trend_warnings(db, "pm1", "face_dz_mm", {}, "pm1-day-8", now - 3 * kDay);
  Heartbeat beat;
  beat.service = "historian";
  beat.instance = "server-1:100";
  beat.state = "running";
  beat.health = "ok";
  beat.time_ns = now;
  db.store(beat);
  return 0;
}

int add(const std::filesystem::path& dir, const std::string& id) {
  auto db = storage::Database::open((dir / "historian.db").string());
  store_check(db, "pm1", id, WallClock().now_ns(), 0.0777, true);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string usage = "usage: ncqual_web_fixture make DIR SOURCE_DIR | add DIR ID\n";
  if (argc != 4) {
    std::cerr << usage;
    return 2;
  }
  const std::string what = argv[1];
  try {
    if (what == "make") return make(argv[2], argv[3]);
    if (what == "add") return add(argv[2], argv[3]);
  } catch (const std::exception& e) {
    std::cerr << "ncqual_web_fixture: " << e.what() << "\n";
    return 1;
  }
  std::cerr << usage;
  return 2;
}
