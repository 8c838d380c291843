// SPDX-License-Identifier: Apache-2.0
// What has changed in the historian, beyond the query API of database.hpp: SQLite's
// data_version and a cheap token that moves whenever something a page shows was stored (for a
// watcher, e.g. the dashboard, docs/dashboard.md), how many results a machine has up to a time
// (for a cache), and a machine's newest failed checks. Free functions over a Database
// connection (read-only is enough); every statement is prepared once per connection.
#pragma once

#include "ncqual/common/model.hpp"
#include "ncqual/storage/database.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace ncqual::storage {

// SQLite's PRAGMA data_version of this connection: it changes when another connection (the
// historian) has committed since this one last read, and only then. Comparable only on one
// connection, so a watcher keeps one connection open and recomputes change_token() only when
// this moved.
std::int64_t data_version(Database& db);

// A token of what the dashboard's pages show, "R.S.Q.M.C.I.W.E.F": the highest row ids of
// results (R), status changes (S), requests (Q), measurement sets (M), compensations (C) and
// interventions (I), and of the trend warnings their number (W), how many have ended (E) and a
// fingerprint of their forecast dates and texts (F, which an update of an active warning
// changes). Equal tokens: nothing a page shows was stored in between. The row ids are read off
// the tables' b-trees (no scan); the warnings, a small table, are read whole. Heartbeats do not
// move it.
std::string change_token(Database& db);

// A check that did not pass: its result's verdict and reason.
struct FailureRecord {
  std::string request_id;
  CheckKind kind = CheckKind::MonumentPositioning;
  Verdict verdict = Verdict::Fail;
  std::string reason;
  std::int64_t time_ns = 0;  // the result's time
};

// The machine's newest results with a verdict other than PASS, newest first, at most `limit`
// (1..1000; std::invalid_argument naming the value otherwise).
std::vector<FailureRecord> recent_failures(Database& db, const std::string& machine_id, int limit);

// How many results of the machine are stored with a result time up to `until_ns`, and the newest
// such time: what something evaluated from those results (the error budget) was evaluated from,
// as far as a cache needs to know (results are never changed once stored; a late one raises the
// count). Reads the index only.
struct ResultsUpTo {
  std::int64_t count = 0;
  std::int64_t newest_ns = 0;
  bool operator==(const ResultsUpTo& o) const {
    return count == o.count && newest_ns == o.newest_ns;
  }
};
ResultsUpTo results_up_to(Database& db, const std::string& machine_id, std::int64_t until_ns);

}  // namespace ncqual::storage
