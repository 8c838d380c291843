// SPDX-License-Identifier: Apache-2.0
// A metric's history, restarts and trend warnings (ncqual/storage/trend.hpp).
#include "ncqual/storage/trend.hpp"

#include "database_impl.hpp"
#include "sqlite.hpp"

#include "ncqual/common/check_kinds.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>

namespace ncqual::storage {
namespace {

using sqlite::Query;
using sqlite::Sql;

// The kinds of check the machine has results of (index-only: results_by_machine_kind_time).
constexpr Sql kSelectResultKinds{"select result kinds",
                                 "SELECT DISTINCT kind FROM results WHERE machine_id = ?1"};
// The kinds of the machine's checks that ever reported a metric (reported_metrics, schema 10).
constexpr Sql kSelectKindsReporting{
    "select kinds reporting",
    "SELECT kind FROM reported_metrics WHERE machine_id = ?1 AND name = ?2 ORDER BY kind"};
// Every metric the machine's results of one kind reported, how many results and the newest's time,
// with the unit, band and place in its check of that newest value (SQLite takes a bare column from
// the row of the one max() aggregate): one walk of the kind's results
// (results_by_machine_kind_time) and their metrics.
constexpr Sql kSelectKindMetrics{
    "select metrics of a kind",
    "SELECT m.name, m.unit, m.lower, m.upper, m.idx, count(*), max(r.time_ns) FROM results AS r "
    "JOIN metrics AS m ON m.request_id = r.request_id WHERE r.machine_id = ?1 AND r.kind = ?2 "
    "GROUP BY m.name"};
// Oldest first within [since, until]; ?6 > 0 keeps the newest ?6 (read newest first).
constexpr Sql kSelectSeriesAscending{
    "select metric series",
    "SELECT r.request_id, r.time_ns, r.verdict, m.value, m.unit, m.lower, m.upper, m.pass, "
    "r.origin FROM results AS r JOIN metrics AS m ON m.request_id = r.request_id AND m.name = ?3 "
    "WHERE r.machine_id = ?1 AND r.kind = ?2 AND r.time_ns >= ?4 AND r.time_ns <= ?5 "
    "ORDER BY r.time_ns, r.request_id"};
constexpr Sql kSelectSeriesNewest{
    "select metric series (newest)",
    "SELECT r.request_id, r.time_ns, r.verdict, m.value, m.unit, m.lower, m.upper, m.pass, "
    "r.origin FROM results AS r JOIN metrics AS m ON m.request_id = r.request_id AND m.name = ?3 "
    "WHERE r.machine_id = ?1 AND r.kind = ?2 AND r.time_ns >= ?4 AND r.time_ns <= ?5 "
    "ORDER BY r.time_ns DESC, r.request_id DESC LIMIT ?6"};
// The interventions (kind NULL) and the compensations with the kind of the check that issued
// them (NULL when that check is not stored).
constexpr Sql kSelectRestarts{
    "select restarts",
    "SELECT time_ns, NULL FROM interventions WHERE machine_id = ?1 "
    "UNION ALL SELECT time_ns, target FROM compensations WHERE machine_id = ?1"};

#define NCQUAL_WARNING_COLUMNS                                                               \
  "machine_id, metric, check_kind, kind, side, started_ns, raised_by, raised_ns, ended_by, " \
  "ended_ns, expected_crossing_ns, earliest_crossing_ns, text"
constexpr Sql kSelectActiveWarnings{
    "select active trend warnings",
    "SELECT " NCQUAL_WARNING_COLUMNS
    " FROM trend_warnings WHERE machine_id = ?1 AND metric = ?2 AND ended_ns IS NULL"};
// Every filter is optional (NULL); the machine's index serves a machine, the started index the
// plant.
constexpr Sql kSelectWarnings{
    "select trend warnings",
    "SELECT " NCQUAL_WARNING_COLUMNS
    " FROM trend_warnings WHERE (?1 IS NULL OR machine_id = ?1) AND (?2 IS NULL OR metric = ?2) "
    "AND (?3 = 0 OR ended_ns IS NULL) AND (ended_ns IS NULL OR ended_ns >= ?4 OR raised_ns >= ?4) "
    "ORDER BY ended_ns IS NOT NULL, raised_ns DESC, machine_id, metric, kind LIMIT ?5"};
constexpr Sql kSelectMachineWarnings{
    "select trend warnings of a machine",
    "SELECT " NCQUAL_WARNING_COLUMNS
    " FROM trend_warnings WHERE machine_id = ?1 AND (?2 IS NULL OR metric = ?2) "
    "AND (?3 = 0 OR ended_ns IS NULL) AND (ended_ns IS NULL OR ended_ns >= ?4 OR raised_ns >= ?4) "
    "ORDER BY ended_ns IS NOT NULL, raised_ns DESC, metric, kind LIMIT ?5"};
constexpr Sql kInsertWarning{
    "insert trend warning",
    "INSERT INTO trend_warnings (" NCQUAL_WARNING_COLUMNS
    ") VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, NULL, NULL, ?9, ?10, ?11) "
    "ON CONFLICT (machine_id, metric, kind, started_ns) DO UPDATE SET ended_by = NULL, "
    "ended_ns = NULL, side = excluded.side, raised_by = excluded.raised_by, "
    "raised_ns = excluded.raised_ns, expected_crossing_ns = excluded.expected_crossing_ns, "
    "earliest_crossing_ns = excluded.earliest_crossing_ns, text = excluded.text"};
constexpr Sql kUpdateWarning{
    "update trend warning",
    "UPDATE trend_warnings SET expected_crossing_ns = ?5, earliest_crossing_ns = ?6, text = ?7 "
    "WHERE machine_id = ?1 AND metric = ?2 AND kind = ?3 AND started_ns = ?4"};
constexpr Sql kEndWarning{
    "end trend warning",
    "UPDATE trend_warnings SET ended_by = ?5, ended_ns = ?6 "
    "WHERE machine_id = ?1 AND metric = ?2 AND kind = ?3 AND started_ns = ?4"};
#undef NCQUAL_WARNING_COLUMNS

TrendWarningRecord warning_from(const Query& q) {
  TrendWarningRecord w;
  w.machine_id = q.text(0);
  w.metric = q.text(1);
  w.check_kind = static_cast<CheckKind>(q.int64(2));
  w.kind = q.text(3);
  w.side = q.text(4);
  w.started_ns = q.int64(5);
  w.raised_by = q.text(6);
  w.raised_ns = q.int64(7);
  w.ended_by = q.optional_text(8);
  w.ended_ns = q.optional_int64(9);
  w.expected_crossing_ns = q.optional_int64(10);
  w.earliest_crossing_ns = q.optional_int64(11);
  w.text = q.text(12);
  return w;
}

std::vector<CheckKind> result_kinds(sqlite::StatementCache& statements,
                                    const std::string& machine_id) {
  std::vector<CheckKind> kinds;
  Query q(statements, kSelectResultKinds);
  q.bind(machine_id);
  while (q.step()) kinds.push_back(static_cast<CheckKind>(q.int64(0)));
  std::sort(kinds.begin(), kinds.end());
  return kinds;
}

// The kinds of the machine's checks that ever reported `metric`.
std::vector<CheckKind> kinds_reporting(sqlite::StatementCache& statements,
                                       const std::string& machine_id, const std::string& metric) {
  std::vector<CheckKind> out;
  Query q(statements, kSelectKindsReporting);
  q.bind(machine_id, metric);
  while (q.step()) out.push_back(static_cast<CheckKind>(q.int64(0)));
  return out;
}

void read_series(Query& q, CheckKind kind, std::vector<MetricValue>& out) {
  while (q.step()) {
    MetricValue v;
    v.request_id = q.text(0);
    v.kind = kind;
    v.time_ns = q.int64(1);
    v.verdict = parse_verdict(q.text(2)).value_or(Verdict::Invalid);
    v.value = q.is_null(3) ? std::numeric_limits<double>::quiet_NaN() : q.real(3);
    v.unit = q.text(4);
    v.lower = q.real(5);
    v.upper = q.real(6);
    v.pass = q.int64(7) != 0;
    // NULL (stored before schema 11, or a sample that did not say): Unknown.
    if (const auto origin = q.optional_text(8)) {
      v.origin = parse_data_origin(*origin).value_or(DataOrigin::Unknown);
    }
    out.push_back(std::move(v));
  }
}

bool same_identity(const TrendWarningRecord& a, const TrendWarningRecord& b) {
  return a.kind == b.kind && a.started_ns == b.started_ns;
}

}  // namespace

std::vector<MetricValue> metric_series(Database& db, const MetricQuery& query) {
  std::vector<MetricValue> out;
  auto& impl = DatabaseAccess::impl(db);
  impl.read([&] {
    auto& statements = impl.statements;
    for (CheckKind kind : kinds_reporting(statements, query.machine_id, query.metric)) {
      const bool newest = query.last > 0;
      Query q(statements, newest ? kSelectSeriesNewest : kSelectSeriesAscending);
      q.bind(query.machine_id, static_cast<std::int64_t>(kind), query.metric, query.since_ns,
             query.until_ns);
      if (newest) q.bind_at(6, static_cast<std::int64_t>(query.last));
      read_series(q, kind, out);
    }
  });
  std::sort(out.begin(), out.end(), [](const MetricValue& a, const MetricValue& b) {
    return std::tie(a.time_ns, a.request_id) < std::tie(b.time_ns, b.request_id);
  });
  if (query.last > 0 && out.size() > static_cast<std::size_t>(query.last)) {
    out.erase(out.begin(), out.end() - query.last);
  }
  return out;
}

std::vector<MetricInfo> machine_metrics(Database& db, const std::string& machine_id) {
  std::vector<MetricInfo> out;
  auto& impl = DatabaseAccess::impl(db);
  impl.read([&] {
    auto& statements = impl.statements;
    for (CheckKind kind : result_kinds(statements, machine_id)) {
      std::vector<std::pair<std::int64_t, MetricInfo>> of_kind;  // with the place in its check
      Query q(statements, kSelectKindMetrics);
      q.bind(machine_id, static_cast<std::int64_t>(kind));
      while (q.step()) {
        MetricInfo m;
        m.name = q.text(0);
        m.kind = kind;
        m.unit = q.text(1);
        m.lower = q.real(2);
        m.upper = q.real(3);
        m.count = q.int64(5);
        m.last_ns = q.int64(6);
        of_kind.emplace_back(q.int64(4), std::move(m));
      }
      std::sort(of_kind.begin(), of_kind.end(), [](const auto& a, const auto& b) {
        return std::tie(a.first, a.second.name) < std::tie(b.first, b.second.name);
      });
      for (auto& [idx, m] : of_kind) out.push_back(std::move(m));
    }
  });
  return out;
}

std::vector<std::int64_t> restart_times(Database& db, const std::string& machine_id,
                                        CheckKind series, std::string_view metric) {
  std::vector<std::int64_t> out;
  auto& impl = DatabaseAccess::impl(db);
  impl.read([&] {
    Query q(impl.statements, kSelectRestarts);
    q.bind(machine_id);
    while (q.step()) {
      std::optional<CompensationKind> compensation;
      if (!q.is_null(1)) compensation = compensation_kind(q.text(1));
      if (restarts_series(compensation, series, metric)) out.push_back(q.int64(0));
    }
  });
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<TrendWarningRecord> trend_warnings(Database& db, const TrendWarningQuery& query) {
  std::vector<TrendWarningRecord> out;
  auto& impl = DatabaseAccess::impl(db);
  impl.read([&] {
    // "?1 IS NULL OR machine_id = ?1" would keep SQLite from the machine index: two statements.
    const bool one_machine = query.machine_id.has_value();
    Query q(impl.statements, one_machine ? kSelectMachineWarnings : kSelectWarnings);
    if (one_machine) {
      q.bind(*query.machine_id);
    } else {
      q.bind_at(1, std::nullopt);
    }
    q.bind_at(2, query.metric);
    q.bind_at(3, query.active_only);
    q.bind_at(4, query.since_ns);
    q.bind_at(5, static_cast<std::int64_t>(query.limit > 0 ? query.limit : -1));
    while (q.step()) out.push_back(warning_from(q));
  });
  return out;
}

TrendWarningChanges apply_trend_warnings(Database& db, const std::string& machine_id,
                                         const std::string& metric,
                                         const std::vector<TrendWarningRecord>& active,
                                         const std::string& by, std::int64_t at_ns) {
  TrendWarningChanges changes;
  auto& impl = DatabaseAccess::impl(db);
  impl.write("trend warnings of " + machine_id + " " + metric, [&] {
    auto& statements = impl.statements;
    std::vector<TrendWarningRecord> stored;
    {
      Query q(statements, kSelectActiveWarnings);
      q.bind(machine_id, metric);
      while (q.step()) stored.push_back(warning_from(q));
    }
    for (TrendWarningRecord& old : stored) {
      const auto now = std::find_if(active.begin(), active.end(),
                                    [&](const auto& w) { return same_identity(w, old); });
      if (now != active.end()) {
        if (now->expected_crossing_ns != old.expected_crossing_ns ||
            now->earliest_crossing_ns != old.earliest_crossing_ns || now->text != old.text) {
          Query(statements, kUpdateWarning)
              .bind(machine_id, metric, old.kind, old.started_ns, now->expected_crossing_ns,
                    now->earliest_crossing_ns, now->text)
              .run();
          old.expected_crossing_ns = now->expected_crossing_ns;
          old.earliest_crossing_ns = now->earliest_crossing_ns;
          old.text = now->text;
          changes.updated.push_back(old);
        }
        continue;
      }
      Query(statements, kEndWarning)
          .bind(machine_id, metric, old.kind, old.started_ns, by, at_ns)
          .run();
      old.ended_by = by;
      old.ended_ns = at_ns;
      changes.ended.push_back(std::move(old));
    }
    for (const TrendWarningRecord& w : active) {
      const bool known = std::any_of(stored.begin(), stored.end(),
                                     [&](const auto& old) { return same_identity(w, old); });
      if (known) continue;
      TrendWarningRecord raised = w;
      raised.machine_id = machine_id;
      raised.metric = metric;
      raised.raised_by = by;
      raised.raised_ns = at_ns;
      raised.ended_by.reset();
      raised.ended_ns.reset();
      Query(statements, kInsertWarning)
          .bind(machine_id, metric, static_cast<std::int64_t>(raised.check_kind), raised.kind,
                raised.side, raised.started_ns, by, at_ns, raised.expected_crossing_ns,
                raised.earliest_crossing_ns, raised.text)
          .run();
      changes.raised.push_back(std::move(raised));
    }
  });
  return changes;
}

}  // namespace ncqual::storage
