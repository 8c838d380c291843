// SPDX-License-Identifier: Apache-2.0
// `ncqual trend`: per period, how the machine's checks went.
//
//   ncqual trend --machine M [--kind K] [--every day|week|month] [--metrics N] [--plant F]
//                [--db F]
//     Per check kind and per calendar day, week or month (in the plant's time zone): how many
//     checks passed, failed or were invalid, and for the N metrics (default 3) that came nearest
//     their tolerance over the whole history, the value in each period nearest its tolerance.
//     A drift shows as a column creeping towards (!).
//
// Exit codes: 0, 2 bad usage (and a machine the plant does not configure), 6 no historian
// database at the path.
#include "commands.hpp"

#include "ncqual/calendar.hpp"
#include "ncqual/storage.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>

namespace ncqual::cli {
namespace {

// How much of its tolerance band a value uses: |v - centre| / half-width (> 1: out of tolerance).
double band_use(const Metric& m) {
  const double half = 0.5 * (m.upper - m.lower);
  if (!(half > 0)) return 0;
  return std::abs(m.value - 0.5 * (m.upper + m.lower)) / half;
}

struct Bucket {
  int pass = 0, fail = 0, invalid = 0;
  std::map<std::string, Metric> worst;  // per metric: the value using most of its band
};

struct Options {
  std::string plant, machine, every = "week";
  std::optional<std::string> db;
  std::optional<CheckKind> kind;
  int metrics = 3;
};

int run(const Options& o) {
  const PlantConfig plant = plant_from(o.plant);
  const std::string machine = configured_machine(plant, o.machine).machine_id;
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
  for (const auto& rec : db.history(q)) {
    if (!rec.result) continue;
    const CheckResult& r = *rec.result;
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
    std::string header = fmt::format("  {:<18}{:<14}", every + " from", "pass/fail/inv");
    for (const auto& [use, name] : ranked) header += fmt::format("{:<26}", name);
    fmt::print("{}\n", header);
    for (const auto& [start, b] : buckets) {
      std::string line = fmt::format("  {:<18}{:<14}", calendar.local_text(start).substr(0, 10),
                                     fmt::format("{}/{}/{}", b.pass, b.fail, b.invalid));
      for (const auto& [use, name] : ranked) {
        auto it = b.worst.find(name);
        line += fmt::format(
            "{:<26}", it == b.worst.end()
                          ? std::string()
                          : fmt::format("{} {}{}", format_metric_value(it->second), it->second.unit,
                                        band_use(it->second) > 1 ? " (!)" : ""));
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
  add_historian_options(cmd, o->plant, o->db);
}

}  // namespace ncqual::cli
