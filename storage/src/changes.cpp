// SPDX-License-Identifier: Apache-2.0
// What has changed in the historian: the queries of ncqual/storage/changes.hpp.
#include "ncqual/storage/changes.hpp"

#include "database_impl.hpp"
#include "sqlite.hpp"

#include <stdexcept>

namespace ncqual::storage {
namespace {

using sqlite::Query;
using sqlite::Sql;

constexpr Sql kDataVersion{"data version", "PRAGMA data_version"};
// max(rowid) and max(INTEGER PRIMARY KEY) are one step down the right edge of the b-tree.
constexpr Sql kChangeToken{
    "change token",
    "SELECT (SELECT coalesce(max(rowid), 0) FROM results), "
    "(SELECT coalesce(max(id), 0) FROM status_changes), "
    "(SELECT coalesce(max(rowid), 0) FROM requests), "
    "(SELECT coalesce(max(rowid), 0) FROM measurement_sets), "
    "(SELECT coalesce(max(id), 0) FROM compensations), "
    "(SELECT coalesce(max(rowid), 0) FROM interventions), "
    "w.n, w.ended, w.fingerprint FROM (SELECT count(*) AS n, count(ended_ns) AS ended, "
    "coalesce(sum((coalesce(expected_crossing_ns, 0) % 1000000007 + "
    "coalesce(earliest_crossing_ns, 0) % 1000000007 + length(text) + coalesce(ended_ns, 0) % 7919) "
    "% 1000000007), 0) AS fingerprint FROM trend_warnings) AS w"};
constexpr Sql kSelectFailures{
    "select recent failures",
    "SELECT request_id, kind, verdict, reason, time_ns FROM results "
    "WHERE machine_id = ?1 AND verdict <> 'PASS' ORDER BY time_ns DESC, request_id DESC LIMIT ?2"};

// Index-only (results_by_machine_time).
constexpr Sql kResultsUpTo{"results up to",
                           "SELECT count(*), coalesce(max(time_ns), 0) FROM results WHERE "
                           "machine_id = ?1 AND time_ns <= ?2"};

}  // namespace

std::int64_t data_version(Database& db) {
  auto& impl = DatabaseAccess::impl(db);
  Query q(impl.statements, kDataVersion);
  return q.step() ? q.int64(0) : 0;
}

std::string change_token(Database& db) {
  std::string token;
  auto& impl = DatabaseAccess::impl(db);
  impl.read([&] {
    Query q(impl.statements, kChangeToken);
    if (!q.step()) return;
    for (int column = 0; column < 9; ++column) {
      token += (column ? "." : "") + std::to_string(q.int64(column));
    }
  });
  return token;
}

ResultsUpTo results_up_to(Database& db, const std::string& machine_id, std::int64_t until_ns) {
  ResultsUpTo out;
  auto& impl = DatabaseAccess::impl(db);
  impl.read([&] {
    Query q(impl.statements, kResultsUpTo);
    q.bind(machine_id, until_ns);
    if (q.step()) out = {q.int64(0), q.int64(1)};
  });
  return out;
}

std::vector<FailureRecord> recent_failures(Database& db, const std::string& machine_id, int limit) {
  if (limit < 1 || limit > 1000) {
    throw std::invalid_argument("recent failures: limit " + std::to_string(limit) +
                                " is not within 1..1000");
  }
  std::vector<FailureRecord> out;
  auto& impl = DatabaseAccess::impl(db);
  impl.read([&] {
    Query q(impl.statements, kSelectFailures);
    q.bind(machine_id, limit);
    while (q.step()) {
      FailureRecord f;
      f.request_id = q.text(0);
      f.kind = static_cast<CheckKind>(q.int32(1));
      f.verdict = parse_verdict(q.text(2)).value_or(Verdict::Invalid);
      f.reason = q.text(3);
      f.time_ns = q.int64(4);
      out.push_back(std::move(f));
    }
  });
  return out;
}

}  // namespace ncqual::storage
