// SPDX-License-Identifier: Apache-2.0
// One machine's report (docs/report.md): what `ncqual report` writes as one self-contained HTML
// file and what the dashboard's machine page shows live. Gathered from the historian (read-only
// is enough), drawn with ncqual_charts (inline SVG, no script needed to see it).
//
// CONTRACT shared by `ncqual report` and the dashboard (ncqual-web): gather once, then render the
// sections (the dashboard) or the whole document (`ncqual report`). Units inside are mm and
// radians (the evaluations' and the historian's); µm and degrees only in what people read.
#pragma once

#include "ncqual/common/calendar.hpp"
#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/report/metric_trend.hpp"
#include "ncqual/solver/error_budget.hpp"
#include "ncqual/solver/global_checks.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/storage/trend.hpp"
#include "ncqual/storage/changes.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::report {

class BudgetMemo;  // below

struct MachineReportQuery {
  std::string machine_id;
  std::optional<std::string> check_id;  // one check (its request id) instead of a period
  std::int64_t since_ns = std::numeric_limits<std::int64_t>::min();  // checks from then on
  std::int64_t now_ns = 0;  // "as of": the report's date, due dates, forecasts
  // The machine's configuration (the plant's): the nominal positions of the monthly grid, circle
  // and linear run, and the budget: section. Without it those sections say that they need it.
  const MachineConfig* machine = nullptr;
  // Budget sections already evaluated (a dashboard keeps one); none: evaluated every time.
  BudgetMemo* budget_memo = nullptr;
  // The plant's calendar: every time a person reads is in its time zone with the offset
  // ("2027-01-15 09:00 +01:00 CET", as `ncqual status` writes it); none: UTC.
  const Calendar* calendar = nullptr;
};

// A stored check a chart section draws: which one, and what became of its evaluation.
struct ReportedCheck {
  std::string request_id;
  CheckKind kind = CheckKind::GlobalGrid;
  std::int64_t time_ns = 0;  // the result's time (else the set's)
  std::optional<Verdict> verdict;
  std::string error;  // why the charts could not be drawn (e.g. points thinned); "" when drawn
  DataOrigin origin = DataOrigin::Unknown;  // measured, or simulated: its charts show no machine
};

// The monthly grid's points of one constant-Z plane (commanded Z), in grid order.
struct GridPlane {
  double z_mm = 0;
  std::vector<solver::GridPointResult> points;  // deviation_mm: master - commanded
};

struct GridSection {
  ReportedCheck check;
  // The radius of the tolerance circle and the Z limits (±): the upper limit of the check's
  // grid_max_deviation_mm; none when the result has no such metric.
  std::optional<double> tolerance_mm;
  std::vector<GridPlane> planes;  // by increasing Z
};

struct CircleSection {
  ReportedCheck check;
  std::optional<solver::CircleEvaluation> evaluation;
  std::optional<double> tolerance_mm;  // the upper limit of circle_<plane>_G_mm
};

struct LinearRunSection {
  ReportedCheck check;
  std::optional<solver::LinearRunEvaluation> evaluation;
  std::optional<double> tolerance_mm;  // the upper limit of linear_A_mm
};

// An intervention or a compensation: a restart of trend series, marked on the trend charts of
// the series it restarts (restarts_series) and on no other.
struct RestartMarker {
  std::int64_t time_ns = 0;
  std::string label;
  std::optional<CompensationKind> compensation;  // none: an intervention
};

struct BudgetSection {
  std::string error;  // why there is no budget ("" when evaluated)
  std::optional<solver::ErrorBudgetConfig> config;
  std::optional<solver::ErrorBudgetReport> evaluation;
  int last = 30;   // the newest N values of each metric make its capability (`ncqual budget`)
  int values = 0;  // values found in the historian for its metrics
  std::int64_t until_ns = 0;  // the values are those of results up to this time
  // The machine's standing up to until_ns (held, failed budget metrics) and the budget's verdict
  // with it (solver::judge_budget): a held machine is never within budget.
  solver::BudgetMachineStanding standing;
  solver::BudgetJudgement judgement;
};

// A metric of the checks in range without a chart of its own (docs/report.md, "Trends"): how
// near its tolerance it came.
struct MetricUsage {
  std::string metric;
  CheckKind kind = CheckKind::MonumentPositioning;
  std::string unit;
  int checks = 0;               // values in range (evaluated)
  double usage = 0;             // the largest |value| over its limit on the value's side (1: at it)
  double value = 0;             // that value
  double lower = 0, upper = 0;  // its band
  std::int64_t time_ns = 0;     // its check's time
};

// At most this many metrics get a trend chart: those with a trend warning of the range, then
// those with a value out of tolerance, then the nearest their tolerance (MetricUsage::usage).
constexpr std::size_t kMaxTrendCharts = 12;
// The ended trend warnings the state section lists, newest raised first.
constexpr std::size_t kEndedWarningsListed = 10;

struct MachineReport {
  std::string machine_id;
  std::int64_t now_ns = 0;
  std::optional<std::int64_t> since_ns;  // the period's start; none: everything / one check
  std::optional<std::string> check_id;   // the one check asked for
  bool configured = false;               // a machine configuration was given
  std::optional<MachineStatus> status;   // the newest stored
  // Every active warning, then the newest kEndedWarningsListed ended ones; how many more ended.
  std::vector<storage::TrendWarningRecord> warnings;
  std::size_t ended_warnings_not_listed = 0;
  std::vector<storage::CheckRecord> checks;    // in range, newest first
  std::optional<GridSection> grid;             // the newest monthly grid in range
  std::vector<CircleSection> circles;          // the newest of each plane in range
  std::optional<LinearRunSection> linear_run;  // the newest ISO 230-2 run in range
  // The metrics charted (kMaxTrendCharts at most), in machine_metrics order, and the other
  // metrics of the checks in range, nearest their tolerance first.
  std::vector<MetricTrend> trends;
  std::vector<MetricUsage> other_metrics;
  std::vector<RestartMarker> markers;  // interventions and compensations, oldest first
  BudgetSection budget;
  // The software that wrote the report (version_line: "ncqual report 0.1.0 (git ...)"), named in
  // its footer; empty: "ncqual report".
  std::string produced_by;
  // The zone of the times people read (the query's calendar; UTC without one).
  Calendar calendar{CalendarConfig{}};
};

// The machine's error budget as of `until_ns`: the values of its results up to then
// (gather_budget_history) through solver::evaluate_error_budget. Its Monte Carlo makes it the
// costliest part of a report (about 0.1 s with 100,000 draws), so a `memo` that holds the
// machine's section evaluated from the same results under the same configuration gives it back
// instead; a new result (storage::results_up_to) evaluates it again.
// Its texts read times in `calendar`'s zone (UTC without one).
BudgetSection machine_budget(storage::Database& db, const std::string& machine_id,
                             const MachineConfig* machine, std::int64_t until_ns,
                             BudgetMemo* memo = nullptr, const Calendar* calendar = nullptr);

// The newest budget section of each machine with what it was evaluated from; any thread.
class BudgetMemo {
 public:
  struct Key {
    std::string config;  // budget_fingerprint of the configuration
    // The results up to the section's time: two times with the same count and newest result
    // hold the same results (a later time holds all of an earlier one's).
    storage::ResultsUpTo results;
    bool operator==(const Key& o) const { return config == o.config && results == o.results; }
  };
  std::optional<BudgetSection> find(const std::string& machine_id, const Key& key) const;
  void keep(const std::string& machine_id, Key key, BudgetSection section);
  std::size_t hits() const;
  std::size_t evaluations() const;

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::pair<Key, BudgetSection>> newest_;
  mutable std::size_t hits_ = 0;
  std::size_t evaluations_ = 0;
};

// Every field of a budget configuration that its evaluation depends on, as text: equal texts,
// equal evaluations of equal histories.
std::string budget_fingerprint(const solver::ErrorBudgetConfig& config);

// How much of its tolerance a value uses, against the nominal 0: |value| over the limit on its
// side (0.5: half; 1: at the limit; above 1: outside). A side without a finite limit: 0.
double tolerance_usage(double value, double lower, double upper);

// Throws std::invalid_argument naming the machine or check when the historian has none such;
// StorageError for the database.
MachineReport gather_machine_report(storage::Database& db, const MachineReportQuery& query);

// The report's sections as an HTML fragment (<section class="ncqual-report-..."> elements, no
// <html>, <head> or <body>), styled by report_stylesheet(): the dashboard's machine page embeds it.
std::string machine_report_sections(const MachineReport& report);
// The CSS of the sections (screen and print), self-contained.
std::string report_stylesheet();
// The whole self-contained document (`ncqual report --out FILE.html`): <!DOCTYPE html>, the
// stylesheet inline, the sections; no network, no script; prints to PDF.
std::string machine_report_document(const MachineReport& report);

}  // namespace ncqual::report
