// SPDX-License-Identifier: Apache-2.0
// `ncqual history`: the stored checks, newest first.
//
//   ncqual history [--plant F | --db F] [--machine M] [--kind K] [--limit N] [--since-ns T]
//                  [--json]
//
// The table shows per check its time, machine, kind, verdict and at most six metrics; --json
// prints every stored record (ncqual/storage_json.hpp). Exit codes: 0, 6 when there is no
// historian database at the path.
#include "commands.hpp"

#include "ncqual/clock.hpp"
#include "ncqual/storage.hpp"
#include "ncqual/storage_json.hpp"

#include <fmt/format.h>

#include <iostream>

namespace ncqual::cli {
namespace {

// At most kShownMetrics per row: all of them when few, else the worst-case summaries ("max")
// and the ones out of tolerance first (--json has every metric).
constexpr std::size_t kShownMetrics = 6;
std::string format_metrics(const std::vector<Metric>& metrics) {
  std::vector<const Metric*> shown;
  if (metrics.size() <= kShownMetrics) {
    for (const auto& m : metrics) shown.push_back(&m);
  } else {
    for (const auto& m : metrics) {
      if (m.name.find("max") != std::string::npos) shown.push_back(&m);
    }
    for (const auto& m : metrics) {
      if (!m.pass && m.name.find("max") == std::string::npos) shown.push_back(&m);
    }
    if (shown.size() > kShownMetrics) shown.resize(kShownMetrics);
  }
  std::string out;
  for (const Metric* m : shown) {
    if (!out.empty()) out += "  ";
    out += fmt::format("{}={}{}", m->name, format_metric_value(*m), m->pass ? "" : "(!)");
  }
  if (shown.size() < metrics.size()) {
    out += fmt::format("  (+{} more; --json for all)", metrics.size() - shown.size());
  }
  return out;
}

struct Options {
  std::string plant;
  std::optional<std::string> db, machine;
  std::optional<CheckKind> kind;
  int limit = 100;
  std::int64_t since_ns = storage::HistoryQuery{}.since_ns;
  bool json = false;
};

int run(const Options& o) {
  const std::string path = database_path(o.db, o.plant);
  auto opened = open_historian(path, "history");
  if (!opened) return kExitNotFound;
  storage::Database& db = *opened;
  storage::HistoryQuery q;
  q.machine_id = o.machine;
  q.kind = o.kind;
  q.limit = o.limit;
  q.since_ns = o.since_ns;
  const auto records = db.history(q);
  if (o.json) {
    std::cout << nlohmann::json(records).dump(2) << "\n";
  } else {
    print_check_records(records);
  }
  return kExitOk;
}

}  // namespace

void print_check_records(const std::vector<storage::CheckRecord>& records) {
  constexpr const char* kRow = "{:<24} {:<10} {:<22} {:<8} {}\n";
  fmt::print(kRow, "time (UTC)", "machine", "check", "verdict", "metrics ((!) = out of tolerance)");
  for (const auto& r : records) {
    char buf[32];
    const std::int64_t t = r.result ? r.result->time_ns : (r.request ? r.request->time_ns : 0);
    const std::string_view verdict = r.result ? to_string(r.result->verdict) : "pending";
    const std::string_view kind = r.result    ? to_string(r.result->kind)
                                  : r.request ? to_string(r.request->kind)
                                              : "?";
    fmt::print(kRow, format_iso8601(t, buf), r.machine_id, kind, verdict,
               r.result ? format_metrics(r.result->metrics) : "");
    if (r.result && r.result->verdict != Verdict::Pass) {
      if (!r.result->reason.empty()) {
        // The table shows the start of a long reason; `history --json` has all of it.
        constexpr std::size_t kShownReason = 300;
        std::string reason = r.result->reason;
        if (reason.size() > kShownReason) reason = reason.substr(0, kShownReason) + " ...";
        fmt::print("{:59} reason: {}\n", "", reason);
      }
      if (!r.result->likely_causes.empty()) {
        fmt::print("{:59} first likely cause: {}\n", "", r.result->likely_causes.front());
      }
    }
    if (r.conflicts > 0) {
      // Another sample with this request id and other content reached the historian: the row
      // above is the one stored first; `ncqual conflicts` shows the other.
      fmt::print("{:59} CONFLICT: {} other sample(s) with this request id kept beside it\n", "",
                 r.conflicts);
    }
  }
}

void add_history(CLI::App& app, Commands& commands) {
  const auto [cmd, o] = add_command(app, commands, "history", "stored checks, newest first", run);
  add_historian_options(cmd, o->plant, o->db);
  add_machine_option(cmd, o->machine, "only this machine's checks");
  add_kind_option(cmd, "--kind", o->kind, "only checks of this kind");
  cmd->add_option("--limit", o->limit, "at most N checks (0: all)")
      ->type_name("N")
      ->capture_default_str();
  cmd->add_option("--since-ns", o->since_ns,
                  "only checks from this time on (ns since the epoch, UTC)")
      ->type_name("T");
  add_json_flag(cmd, o->json);
}

}  // namespace ncqual::cli
