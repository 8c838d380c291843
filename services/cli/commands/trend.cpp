// SPDX-License-Identifier: Apache-2.0
// `ncqual trend`: per period, how the machine's checks went.
//
//   ncqual trend --machine M [--kind K] [--every day|week|month] [--metrics N] [--plant F]
//                [--db F]
//     Per check kind and per calendar day, week or month (in the plant's time zone): how many
//     checks passed, failed or were invalid, and for the N metrics (default 3) that came nearest
//     their tolerance over the whole history, the value in each period nearest its tolerance.
//     A drift shows as a column creeping towards (!). A kind some of whose checks ncqual's
//     simulator produced says how many ("SIMULATED DATA: ncqual's simulator produced n of its N
//     checks, not measured on the machine").
//
//   ncqual trend --machine M --metric NAME [--since D] [--until D] [--last N] [--json | --csv]
//                [--plant F] [--db F]
//     One metric's figures (docs/trends.md): the checks selected (of [--since, --until], the
//     newest N with --last), and over the segment since the machine's last restart (an
//     intervention, or a compensation that concerns the metric) the control chart, the Western
//     Electric signals, EWMA and CUSUM, capability, the least-squares and Theil-Sen forecasts of
//     the date the tolerance is reached, the pass rate, the warnings active now and those the
//     historian raised; "SIMULATED DATA: ncqual's simulator produced n of these N checks ..." when
//     it produced some. --json: the whole document (report::MetricTrend, names stable: "simulated",
//     each point's "origin"); --csv: the points with their EWMA, CUSUM and origin
//     (report::points_csv). A metric the machine does not report is refused with the machine's
//     metrics listed (the nearest five by name when it has more than twelve).
//
// Exit codes: 0, 2 bad usage (and a machine the plant does not configure, a metric it does not
// report), 6 no historian database at the path.
#include "commands.hpp"

#include "ncqual/common/calendar.hpp"
#include "ncqual/report/machine_report.hpp"
#include "ncqual/report/metric_trend.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/storage/trend.hpp"
#include "ncqual/common/text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <nlohmann/json.hpp>

namespace ncqual::cli {
namespace {

// How much of its tolerance a value uses, as the report ranks its metrics
// (report::tolerance_usage: against the nominal 0, one-sided bands too; > 1: out of tolerance).
double band_use(const Metric& m) { return report::tolerance_usage(m.value, m.lower, m.upper); }

struct Bucket {
  int pass = 0, fail = 0, invalid = 0;
  std::map<std::string, Metric> worst;  // per metric: the value using most of its band
};

struct Options {
  std::string plant, machine, every = "week";
  std::optional<std::string> db;
  std::optional<CheckKind> kind;
  int metrics = 3;
  // --metric mode
  std::optional<std::string> metric, since, until;
  std::optional<int> last;
  bool json = false, csv = false;
};

// ---- --metric -----------------------------------------------------------------------------------

// What the machine's metrics are, for the message that `wanted` is not one: all of them when they
// are few, else the nearest few by edit distance (a fixture machine reports hundreds).
std::string metrics_named(const std::vector<storage::MetricInfo>& known,
                          const std::string& wanted) {
  constexpr std::size_t kListedAll = 12, kNearest = 5;
  std::vector<std::pair<std::size_t, std::string>> names;
  std::set<std::string> seen;  // a metric of two kinds is in `known` twice
  for (const auto& m : known) {
    if (seen.insert(m.name).second) names.emplace_back(edit_distance(wanted, m.name), m.name);
  }
  if (names.empty()) return " (it has no results yet)";
  const std::size_t all = names.size();
  std::string list;
  if (all <= kListedAll) {
    for (const auto& [d, name] : names) list += (list.empty() ? " " : ", ") + name;
    return "; it has" + list;
  }
  std::sort(names.begin(), names.end());
  for (std::size_t i = 0; i < kNearest; ++i) list += (list.empty() ? " " : ", ") + names[i].second;
  return "; the nearest of its " + std::to_string(all) + " metrics:" + list;
}

// A value of the metric in its unit, with the decimals its band calls for.
std::string value_text(const report::MetricTrend& t, double value, int extra_decimals = 0) {
  Metric m{t.metric,
           value,
           t.unit,
           t.lower.value_or(-std::numeric_limits<double>::infinity()),
           t.upper.value_or(std::numeric_limits<double>::infinity()),
           true};
  if (extra_decimals == 0) return format_metric_value(m);
  return fmt::format("{:.{}f}", value, std::min(metric_decimals(m) + extra_decimals, 9));
}

std::string optional_ratio(const std::optional<double>& v) {
  return v ? fmt::format("{:.2f}", *v) : std::string("-");
}

// A forecast date's status (trend::to_string(DateStatus), stable in --json) as people read it.
std::string date_status_text(const std::string& status) {
  static const std::map<std::string, std::string> kText{
      {"already_beyond", "already past"},
      {"never", "never: the line heads away from the limit"},
      {"no_trend", "none: no significant trend"},
      {"no_limit", "none: no limit on the side the line heads to"},
      {"too_far", "beyond the forecast horizon"},
      {"not_enough_points", "none: too few checks"},
  };
  const auto it = kText.find(status);
  return it == kText.end() ? status : it->second;
}

// "2 of its 5 checks", "all 5 of its checks", "its only check"; "2 of these 5 checks", ...,
// "this check".
std::string simulated_checks(std::size_t simulated, std::size_t checks, const char* whose) {
  if (simulated < checks) return fmt::format("{} of {} {} checks", simulated, whose, checks);
  if (checks == 1) return std::string(whose) == "these" ? "this check" : "its only check";
  return fmt::format("all {} of {} checks", checks, whose);
}

void print_metric_trend(const report::MetricTrend& t, const Calendar& calendar) {
  const auto when = [&](std::optional<std::int64_t> ns) {
    return ns ? calendar.local_text(*ns) : std::string("-");
  };
  const auto date = [&](const report::TrendDate& d) {
    return d.time_ns ? calendar.local_text(*d.time_ns).substr(0, 10) +
                           (d.status == "date" ? "" : " (" + date_status_text(d.status) + ")")
                     : date_status_text(d.status);
  };
  std::string kinds;
  for (CheckKind k : t.check_kinds)
    kinds += (kinds.empty() ? "" : ", ") + std::string(to_string(k));
  fmt::print("{} {} ({}), tolerance {} .. {} {}\n", t.machine_id, t.metric, kinds,
             t.lower ? value_text(t, *t.lower) : "-inf", t.upper ? value_text(t, *t.upper) : "inf",
             t.unit);
  fmt::print("checks {} ({} not evaluated), {} .. {}; pass rate {} of {}", t.checks,
             t.not_evaluated, when(t.points.front().time_ns), when(t.points.back().time_ns),
             t.pass_rate.pass, t.pass_rate.pass + t.pass_rate.fail);
  if (t.pass_rate.rate) {
    fmt::print(" = {:.1f} % (95 %: {:.1f} to {:.1f} %)", 100 * *t.pass_rate.rate,
               100 * *t.pass_rate.lower, 100 * *t.pass_rate.upper);
  }
  fmt::print("{}\n", t.pass_rate.invalid ? fmt::format(", {} invalid", t.pass_rate.invalid) : "");
  if (t.simulated > 0) {
    fmt::print("SIMULATED DATA: ncqual's simulator produced {}, not measured on the machine\n",
               simulated_checks(t.simulated, t.points.size(), "these"));
  }
  fmt::print(
      "segment: {} checks {}, as of {}\n", t.segment_points,
      t.restart_ns ? "since the restart of " + when(t.restart_ns) : std::string("(no restart)"),
      when(t.now_ns));
  if (!t.error.empty()) {
    fmt::print("no figures: {}\n", t.error);
    return;
  }
  const auto& b = t.baseline;
  if (b.error.empty()) {
    fmt::print(
        "control chart (baseline of {}): centre {}, sigma within {}, overall {}, limits {} "
        ".. {}\n",
        b.points, value_text(t, b.mean, 1), value_text(t, b.sigma_within, 1),
        value_text(t, b.sigma_overall, 1), value_text(t, b.lower_control_limit, 1),
        value_text(t, b.upper_control_limit, 1));
    if (!b.watched.empty()) {
      fmt::print("one-sided: the rules, EWMA and CUSUM warn {} the centre line only\n", b.watched);
    }
  } else {
    fmt::print("control chart: {}\n", b.error);
  }
  const auto& c = t.capability;
  if (c.error.empty()) {
    fmt::print("capability ({} checks): Cp {}  Cpk {} (Cpu {}, Cpl {})  Pp {}  Ppk {}\n", c.points,
               optional_ratio(c.cp), optional_ratio(c.cpk), optional_ratio(c.cpu),
               optional_ratio(c.cpl), optional_ratio(c.pp), optional_ratio(c.ppk));
  } else {
    fmt::print("capability: {}\n", c.error);
  }
  for (const report::TrendForecast* f : {&t.least_squares, &t.theil_sen}) {
    const std::string name = f->method == "least_squares" ? "least squares" : "Theil-Sen";
    if (!f->error.empty()) {
      fmt::print("forecast ({}): {}\n", name, f->error);
      continue;
    }
    fmt::print("forecast ({}): {} {}/day (95 %: {} .. {}), {}", name,
               value_text(t, f->slope_per_day, 2), t.unit, value_text(t, f->slope_low, 2),
               value_text(t, f->slope_high, 2), f->trend ? "a trend" : "no trend");
    if (f->trend && f->heading) {
      fmt::print(", heading {} {}", *f->heading == "above" ? "up to" : "down to",
                 f->limit ? value_text(t, *f->limit) + " " + t.unit : std::string("no limit"));
    }
    fmt::print("\n  expected {}", date(f->expected));
    if (f->method == "least_squares") {
      fmt::print(", earliest {}, latest {}", date(f->earliest), date(f->latest));
    }
    fmt::print("\n");
  }
  if (!t.signals.empty()) {
    const auto& s = t.signals.back();
    fmt::print("Western Electric: {} signals in the segment, the newest rule {} {} on {}\n",
               t.signals.size(), s.rule, s.side, when(s.time_ns));
  }
  if (t.warnings.empty()) {
    fmt::print("warnings now: none\n");
  } else {
    fmt::print("warnings now:\n");
    for (const auto& w : t.warnings) {
      fmt::print("  {} ({}) since {}: {}\n", w.kind, w.side, when(w.since_ns), w.text);
    }
  }
  if (!t.raised.empty()) {
    fmt::print("raised by the historian:\n");
    for (const auto& w : t.raised) {
      fmt::print("  {} ({}) {} .. {}{}\n", w.kind, w.side, when(w.started_ns),
                 w.ended_ns ? when(w.ended_ns) : std::string("active"),
                 w.ended_by ? " (ended by " + *w.ended_by + ")" : "");
    }
  }
}

int run_metric(const Options& o, const PlantConfig& plant, const std::string& machine) {
  if (o.json && o.csv) throw UsageError("--json and --csv: choose one");
  report::MetricTrendQuery query;
  query.machine_id = machine;
  query.metric = *o.metric;
  const Calendar calendar(plant.calendar.value_or(default_calendar_config()));
  if (o.since) query.since_ns = plant_time_option("--since", *o.since, calendar);
  if (o.until) query.until_ns = plant_time_option("--until", *o.until, calendar);
  query.last = o.last;
  const std::string db_path = o.db.value_or(plant.historian_database);
  auto opened = open_historian(db_path, "trend");
  if (!opened) return kExitNotFound;
  storage::Database& db = *opened;
  const report::MetricTrend t = report::metric_trend(db, query);
  // Nothing selected: a metric the machine never reported is a usage error, named with the
  // metrics it has (looked up only then: machine_metrics counts every metric's checks).
  if (t.checks == 0) {
    const std::vector<storage::MetricInfo> known = storage::machine_metrics(db, machine);
    if (std::none_of(known.begin(), known.end(),
                     [&](const auto& m) { return m.name == *o.metric; })) {
      throw UsageError("--metric '" + *o.metric + "': no stored result of " + machine +
                       " reports it" + metrics_named(known, *o.metric));
    }
  }
  if (o.json) {
    std::cout << nlohmann::json(t).dump(2) << "\n";
  } else if (o.csv) {
    std::cout << report::points_csv(t);
  } else if (t.checks == 0) {
    fmt::print("no check of {} reports {} in the range asked\n", machine, *o.metric);
  } else {
    print_metric_trend(t, calendar);
  }
  return kExitOk;
}

int run(const Options& o) {
  const PlantConfig plant = plant_from(o.plant);
  const std::string machine = configured_machine(plant, o.machine).machine_id;
  if (o.metric) return run_metric(o, plant, machine);
  if (o.since || o.until || o.last || o.json || o.csv) {
    throw UsageError("--since, --until, --last, --json and --csv go with --metric NAME");
  }
  const std::optional<CheckKind>& only = o.kind;
  const std::string& every = o.every;
  PeriodConfig bucket_period;
  if (every == "day") {
    bucket_period.unit = PeriodUnit::Day;
  } else if (every == "week") {
    bucket_period.unit = PeriodUnit::Week;
  } else if (every == "month") {
    bucket_period.unit = PeriodUnit::Month;
  } else {
    throw UsageError("--every '" + every + "': expected day, week or month");
  }
  const int shown = o.metrics;
  const std::string db_path = o.db.value_or(plant.historian_database);
  auto opened = open_historian(db_path, "trend");
  if (!opened) return kExitNotFound;
  storage::Database& db = *opened;
  const Calendar calendar(plant.calendar.value_or(default_calendar_config()));
  storage::HistoryQuery q;
  q.machine_id = machine;
  q.kind = only;
  q.limit = 0;
  // kind -> bucket start -> counts and worst values; per kind the metrics nearest their limits.
  std::map<CheckKind, std::map<std::int64_t, Bucket>> table;
  std::map<CheckKind, std::map<std::string, double>> peak_use;
  // kind -> checks, and of them those ncqual's simulator produced.
  std::map<CheckKind, std::pair<int, int>> simulated;
  for (const auto& rec : db.history(q)) {
    if (!rec.result) continue;
    const CheckResult& r = *rec.result;
    auto& [checks, of_simulator] = simulated[r.kind];
    ++checks;
    if (storage::origin_of(rec) == DataOrigin::Simulated) ++of_simulator;
    Bucket& b = table[r.kind][calendar.period_start(bucket_period, r.time_ns)];
    (r.verdict == Verdict::Pass ? b.pass : r.verdict == Verdict::Fail ? b.fail : b.invalid)++;
    for (const auto& m : r.metrics) {
      auto it = b.worst.find(m.name);
      if (it == b.worst.end() || band_use(m) > band_use(it->second)) b.worst[m.name] = m;
      double& peak = peak_use[r.kind][m.name];
      peak = std::max(peak, band_use(m));
    }
  }
  if (table.empty()) {
    fmt::print("no stored results for {}{}\n", machine,
               only ? " of " + std::string(to_string(*only)) : "");
    return kExitOk;
  }
  for (const auto& [kind, buckets] : table) {
    // The metrics that came nearest their tolerance over the whole history.
    std::vector<std::pair<double, std::string>> ranked;
    for (const auto& [name, use] : peak_use[kind]) ranked.emplace_back(-use, name);
    std::sort(ranked.begin(), ranked.end());
    if (static_cast<int>(ranked.size()) > shown) ranked.resize(static_cast<std::size_t>(shown));
    fmt::print("\n{}  (per {}: runs, and the value nearest its tolerance; (!) out of tolerance)\n",
               to_string(kind), every);
    if (const auto [checks, of_simulator] = simulated[kind]; of_simulator > 0) {
      fmt::print("  SIMULATED DATA: ncqual's simulator produced {}, not measured on the machine\n",
                 simulated_checks(static_cast<std::size_t>(of_simulator),
                                  static_cast<std::size_t>(checks), "its"));
    }
    // A column is as wide as its metric's name and two spaces: names never run together.
    const auto width = [](const std::string& name) {
      return std::max<std::size_t>(26, name.size() + 2);
    };
    std::string header = fmt::format("  {:<18}{:<14}", every + " from", "pass/fail/inv");
    for (const auto& [use, name] : ranked) header += fmt::format("{:<{}}", name, width(name));
    fmt::print("{}\n", header);
    for (const auto& [start, b] : buckets) {
      std::string line = fmt::format("  {:<18}{:<14}", calendar.local_text(start).substr(0, 10),
                                     fmt::format("{}/{}/{}", b.pass, b.fail, b.invalid));
      for (const auto& [use, name] : ranked) {
        auto it = b.worst.find(name);
        line +=
            fmt::format("{:<{}}",
                        it == b.worst.end()
                            ? std::string()
                            : fmt::format("{} {}{}", format_metric_value(it->second),
                                          it->second.unit, band_use(it->second) > 1 ? " (!)" : ""),
                        width(name));
      }
      fmt::print("{}\n", line);
    }
  }
  return kExitOk;
}

}  // namespace

void add_trend(CLI::App& app, Commands& commands) {
  const auto [cmd, o] =
      add_command(app, commands, "trend",
                  "per period: checks passed/failed and the values nearest their tolerances", run);
  add_machine_option(cmd, o->machine, "the machine");
  add_kind_option(cmd, "--kind", o->kind, "only checks of this kind");
  cmd->add_option("--every", o->every, "the period of a row")
      ->type_name("day|week|month")
      ->capture_default_str();
  cmd->add_option("--metrics", o->metrics,
                  "the N (0 to 20) metrics that came nearest their tolerance")
      ->type_name("N")
      ->capture_default_str()
      ->check(CLI::Range(0, 20).description(""));
  cmd->add_option("--metric", o->metric,
                  "one metric's SPC, forecast and warnings (docs/trends.md) instead of the table")
      ->type_name("NAME");
  cmd->add_option(
         "--since", o->since,
         std::string("with --metric: checks at or after this date or time, ") + kPlantZoneHelp)
      ->type_name("DATE");
  cmd->add_option(
         "--until", o->until,
         std::string("with --metric: checks at or before this date or time, ") + kPlantZoneHelp)
      ->type_name("DATE");
  cmd->add_option("--last", o->last, "with --metric: only the newest N checks of the range")
      ->type_name("N")
      ->check(CLI::Range(1, 1'000'000).description(""));
  cmd->add_flag("--csv", o->csv, "with --metric: the points as CSV");
  add_json_flag(cmd, o->json);
  add_historian_options(cmd, o->plant, o->db);
}

}  // namespace ncqual::cli
