// SPDX-License-Identifier: Apache-2.0
// Benchmark of the historian's reads on a year of a plant (docs/history-bench.md): a generated
// historian (tests/support/history_gen.hpp; or --db FILE, one ncqual-generate-history wrote) read
// as the dashboard and the command-line tool read it, each timed over --runs runs (median and
// p95, and the first, cold run) against the 50 ms target:
//   (a) the plant page: plant_status::plant_status over every machine (`ncqual status`, the
//       dashboard's plant page) and each machine's newest failed checks (storage::recent_failures);
//   (b) a machine page: plant_status of one machine, its failures, its newest 50 checks
//       (Database::history) and its report of the last 90 days (report::gather_machine_report +
//       report::machine_report_sections), as the dashboard's machine page gathers it;
//   (c) a trend query: storage::metric_series of one metric of one machine over the whole file;
//   (d) the forecast: report::metric_trend of that metric (series, restarts, trend::assess, the
//       stored warnings), and trend::assess alone on the series read in (c).
// Prints figures beside their targets with PASS/MISS; never asserts, always exits 0.
//   ncqual_history_bench [--machines N] [--days D] [--seed S] [--watch] [--monthly] [--runs R]
//                        [--db FILE] [--keep FILE]
#include "history_gen.hpp"
#include "bench_support.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/status/plant_status.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/storage/trend.hpp"
#include "ncqual/storage/changes.hpp"
#include "ncqual/trend/assess.hpp"
#if NCQUAL_BENCH_HAS_REPORT
#include "ncqual/report/machine_report.hpp"
#endif
#include "ncqual/report/metric_trend.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kTargetMs = 50;
constexpr std::int64_t kDayNs = 86'400'000'000'000;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

const char* verdict(bool pass) { return pass ? "PASS" : "MISS"; }

// Runs `body` `runs` times and prints the first run, the median and the p95 of the rest beside
// the target (`judged`; else as a figure without one). `what` says what one run read (filled by
// the first run).
void timed(const char* label, int runs, const std::function<std::string()>& body,
           bool judged = true) {
  std::vector<double> times;
  std::string what;
  double first = 0;
  for (int i = 0; i <= runs; ++i) {
    const auto t0 = Clock::now();
    std::string said = body();
    const double ms = ms_since(t0);
    if (i == 0) {
      first = ms;
      what = std::move(said);
    } else {
      times.push_back(ms);
    }
  }
  const double median = ncqual::bench::quantile(times, 0.5);
  const double p95 = ncqual::bench::quantile(times, 0.95);
  std::printf("%s\n    %s\n", label, what.c_str());
  if (!judged) {
    std::printf("    first run %.2f ms; %d runs: median %.2f ms, p95 %.2f ms   [no target]\n",
                first, runs, median, p95);
    return;
  }
  std::printf(
      "    first run %.2f ms; %d runs: median %.2f ms, p95 %.2f ms   [target < %.0f ms]  %s\n",
      first, runs, median, p95, kTargetMs, verdict(p95 < kTargetMs));
}

struct Options {
  ncqual::history::GenerateOptions generate;
  std::string db;    // an existing file to read instead of generating
  std::string keep;  // write the generated file here and keep it
  int runs = 20;
};

int run(const Options& o) {
  std::string path = o.db;
  bool remove_after = false;
  if (path.empty()) {
    path = o.keep.empty() ? (std::filesystem::temp_directory_path() /
                             ("ncqual-history-bench-" + std::to_string(::getpid()) + ".db"))
                                .string()
                          : o.keep;
    remove_after = o.keep.empty();
    std::filesystem::remove(path);
    auto db = ncqual::storage::Database::open(path);
    const auto r = ncqual::history::generate_history(db, o.generate);
    std::printf(
        "generated %d machines x %d days%s%s: %lld checks (%lld failed, %lld invalid), %lld "
        "interventions, %lld compensations, %lld warnings raised; %.1f s (monthly tracker %.1f s, "
        "trend watch %.1f s)\n",
        o.generate.machines, o.generate.days, o.generate.monthly ? " with monthly tracker" : "",
        o.generate.watch ? " with the trend watch" : "", static_cast<long long>(r.checks),
        static_cast<long long>(r.failed), static_cast<long long>(r.invalid),
        static_cast<long long>(r.interventions), static_cast<long long>(r.compensations),
        static_cast<long long>(r.warnings_raised), r.seconds, r.monthly_seconds, r.watch_seconds);
  }
  // A file of an older schema is brought up to date first (as any ncqual that writes does).
  { (void)ncqual::storage::Database::open(path); }
  auto db = ncqual::storage::Database::open_readonly(path);
  const std::vector<std::string> ids = db.machines();
  if (ids.empty()) {
    std::printf("bench: %s holds no machine\n", path.c_str());
    return 0;
  }
  const ncqual::PlantConfig plant = ncqual::history::generated_plant(o.generate, ids);
  const ncqual::Calendar calendar = ncqual::plant_status::plant_calendar(plant);
  std::printf("historian %s: %.1f MB, %zu machines, %lld results\n", path.c_str(),
              static_cast<double>(std::filesystem::file_size(path)) / (1024.0 * 1024.0), ids.size(),
              static_cast<long long>(db.count_results()));
  // The machine of the machine page and the trend: the one with the most failures.
  std::string machine = ids.front();
  std::size_t most = 0;
  for (const auto& id : ids) {
    const auto f = ncqual::storage::recent_failures(db, id, 1000);
    if (f.size() > most) most = f.size(), machine = id;
  }
  const std::string metric = "center_dy_mm";
  const auto status_now = db.latest_status(machine);
  const std::int64_t now = status_now ? status_now->time_ns : o.generate.start_ns;
  std::printf("machine page and trend: %s (%zu failed checks), metric %s\n\n", machine.c_str(),
              most, metric.c_str());

  timed("(a) plant page: plant_status of every machine + each one's newest 20 failed checks",
        o.runs, [&] {
          const auto s = ncqual::plant_status::plant_status(db, plant, calendar, {{}, now});
          std::size_t failures = 0, warnings = 0;
          for (const auto& m : s.machines) {
            failures += ncqual::storage::recent_failures(db, m.machine_id, 20).size();
            warnings += m.warnings.size();
          }
          return std::to_string(s.machines.size()) + " machines, " + std::to_string(failures) +
                 " failed checks, " + std::to_string(warnings) + " active warnings";
        });

  double gather_total_ms = 0, render_total_ms = 0;
  int report_runs = 0;
#if NCQUAL_BENCH_HAS_REPORT
  // The error budget is evaluated once per new result, not per page: the dashboard's refresh
  // (web::Dashboard::refresh_budgets) does it when the historian changes and the page finds it
  // in the memo. Its cost, timed apart, is what each new result of the machine costs the
  // dashboard off the page.
  ncqual::report::BudgetMemo budgets;
  const ncqual::MachineConfig* machine_config = plant.find_machine(machine);
  timed(
      "(b0) the machine's error budget evaluated anew, as after a new result (off the page)",
      o.runs,
      [&] {
        const auto b = ncqual::report::machine_budget(db, machine, machine_config, now);
        return std::to_string(b.values) + " values, " +
               (b.evaluation ? std::to_string(b.config->samples) + " Monte Carlo draws"
                             : "not evaluated: " + b.error);
      },
      false);
  (void)ncqual::report::machine_budget(db, machine, machine_config, now, &budgets);
#endif
  timed("(b) machine page: status, failures, newest 50 checks, report of the last 90 days", o.runs,
        [&] {
          auto s = ncqual::plant_status::plant_status(db, plant, calendar, {machine, now});
          const auto failures = ncqual::storage::recent_failures(db, machine, 20);
          ncqual::storage::HistoryQuery history;
          history.machine_id = machine;
          history.limit = 50;
          const auto checks = db.history(history);
          std::string said = std::to_string(failures.size()) + " failures, " +
                             std::to_string(checks.size()) + " checks";
#if NCQUAL_BENCH_HAS_REPORT
          ncqual::report::MachineReportQuery query;
          query.machine_id = machine;
          query.since_ns = now - 90 * kDayNs;
          query.now_ns = now;
          query.machine = machine_config;
          query.budget_memo = &budgets;  // as the dashboard's refresh keeps it
          const auto g0 = Clock::now();
          const auto report = ncqual::report::gather_machine_report(db, query);
          const double gather_ms = ms_since(g0);
          const auto r0 = Clock::now();
          const std::string html = ncqual::report::machine_report_sections(report);
          const double render_ms = ms_since(r0);
          gather_total_ms += gather_ms;
          render_total_ms += render_ms;
          ++report_runs;
          said += ", report: " + std::to_string(report.checks.size()) + " checks, " +
                  std::to_string(report.trends.size()) + " trends, " +
                  std::to_string(html.size() / 1024) + " kB of sections";
#else
          said += "; report: not built (report/ has no machine_report yet): status part only";
#endif
          return said;
        });

  if (report_runs > 0) {
    std::printf(
        "    of it, mean per run: gather_machine_report %.1f ms, machine_report_sections %.1f ms\n",
        gather_total_ms / report_runs, render_total_ms / report_runs);
  }

  std::vector<ncqual::storage::MetricValue> series;
  timed("(c) trend query: metric_series of one metric of one machine over the whole file", o.runs,
        [&] {
          series = ncqual::storage::metric_series(db, {machine, metric});
          return std::to_string(series.size()) + " values";
        });

  timed("(d) forecast: report::metric_trend of that metric (series, restarts, assess, warnings)",
        o.runs, [&] {
          ncqual::report::MetricTrendQuery query;
          query.machine_id = machine;
          query.metric = metric;
          const auto t = ncqual::report::metric_trend(db, query);
          return std::to_string(t.checks) + " checks, " + std::to_string(t.segment_points) +
                 " in the segment, forecast " + t.least_squares.expected.status +
                 (t.error.empty() ? "" : " (" + t.error + ")");
        });

  std::vector<ncqual::trend::Point> points;
  ncqual::trend::Band band;
  for (const auto& v : series) {
    if (std::isfinite(v.value)) points.push_back({v.time_ns, v.value});
    band = {v.lower, v.upper};
  }
  const auto restarts = ncqual::storage::restart_times(
      db, machine, ncqual::CheckKind::MonumentPositioning, "center_dy_mm");
  timed("(d') forecast: trend::assess alone on the series of (c), in memory", o.runs, [&] {
    const auto a = ncqual::trend::assess(points, band, restarts, now);
    return std::to_string(points.size()) + " points, " + std::to_string(restarts.size()) +
           " restarts, " + std::to_string(a.segment.points.size()) + " in the segment" +
           (a.error.empty() ? "" : " (" + a.error + ")");
  });
  if (remove_after) {
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  o.generate.machines = 50;
  o.generate.days = 365;
  o.generate.machine_file = std::string(NCQUAL_SOURCE_DIR) + "/deploy/machines/pm1.yaml";
  try {
    for (int i = 1; i < argc; ++i) {
      if (ncqual::history::read_generate_option(argc, argv, i, o.generate)) continue;
      const std::string arg = argv[i];
      if (arg == "--runs") {
        o.runs = std::max(1, std::stoi(ncqual::history::option_value(argc, argv, i)));
      } else if (arg == "--db") {
        o.db = ncqual::history::option_value(argc, argv, i);
      } else if (arg == "--keep") {
        o.keep = ncqual::history::option_value(argc, argv, i);
      } else {
        throw std::invalid_argument("unknown argument '" + arg + "'");
      }
    }
    return run(o);
  } catch (const std::exception& e) {
    std::printf("bench failed: %s\n", e.what());
    return 0;
  }
}
