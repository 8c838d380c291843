// SPDX-License-Identifier: Apache-2.0
// The dashboard (docs/dashboard.md): the pages and the JSON of ncqual-web, as a function from a
// request to a reply over the historian opened read-only. No HTTP here (main.cpp serves it with
// cpp-httplib), so every page and every refusal can be produced and tested without a socket.
//
//   GET /                        the plant page: every configured machine's state, next due,
//                                overdue periods, active trend warnings, last failures; services
//   GET /machines/<id>           a machine page: its status and periods, then its report's
//                                sections (ncqual/report/machine_report.hpp), live
//   GET /checks/<request id>     a check: request, measurement, verdict, metrics with their
//                                tolerances, likely causes, correction
//   GET /api/v1/plant            the same as JSON (names: docs/dashboard.md)
//   GET /machines/<id>?days=N    the report of the last N days (default 90, at most 366)
//   GET /api/v1/machines/<id>[?checks=N]
//   GET /api/v1/checks/<request id>
//   GET /api/v1/changes[?since=TOKEN]   {"token", "changed"}: the pages poll it
//
// 404 for an unknown path, machine or check (JSON under /api/, HTML elsewhere), 400 for a
// parameter that is unknown or out of range, 405 for any method but GET and HEAD, 503 while the
// historian database cannot be read. Every list is bounded (Limits).
#pragma once

#include "ncqual/common/calendar.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/report/machine_report.hpp"
#include "ncqual/storage/database.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace ncqual::web {

struct Request {
  std::string method = "GET";
  std::string path;                                         // decoded, without the query
  std::vector<std::pair<std::string, std::string>> params;  // the query's, decoded, in order
};

struct Reply {
  int status = 200;
  std::string content_type;
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;  // beyond Content-Type
};

// How much a reply may hold: every list a page or a document shows is cut to these.
struct Limits {
  int failures = 20;            // newest failed checks, per machine and on the plant page
  int checks = 50;              // newest checks on a machine page (?checks=N: 1..max_checks)
  int max_checks = 200;         // the most ?checks= may ask for
  int days = 90;                // the machine page's report: the last N days (?days=N)
  int max_days = 366;           // the most ?days= may ask for
  std::size_t max_id = 128;     // characters of a machine or request id in a path
  std::size_t max_token = 200;  // characters of ?since=
  int poll_ms = 2000;           // how often the pages ask /api/v1/changes
};

// Read-only connections to the historian, one per request at a time (a Database must not be
// used by two threads at once): taken from a free list, opened when it is empty.
class ConnectionPool {
 public:
  explicit ConnectionPool(std::string path) : path_(std::move(path)) {}
  // Runs `body` with a connection of its own; a connection whose query failed is closed.
  void with(const std::function<void(storage::Database&)>& body);
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<storage::Database>> free_;
};

// The change token (storage::change_token) as the pages poll it: read on one connection of its
// own, recomputed only when that connection's PRAGMA data_version says another one committed.
class ChangeWatch {
 public:
  explicit ChangeWatch(const std::string& path);
  std::string token();

 private:
  std::mutex mutex_;
  storage::Database db_;
  std::int64_t version_ = -1;
  std::string token_;
};

class Dashboard {
 public:
  // Opens the historian at `database_path` read-only (StorageError naming the file when it is
  // not there or not an ncqual database). `now_ns` gives "now" (the wall clock by default).
  Dashboard(PlantConfig plant, const std::string& database_path, Limits limits = {},
            std::function<std::int64_t()> now_ns = {});

  // Any thread, any number at once.
  Reply handle(const Request& request);

  const PlantConfig& plant() const { return plant_; }

  // Evaluates the error budget of every configured machine whose results changed since its last
  // evaluation (report::machine_budget with this dashboard's memo), so that a machine page finds
  // it ready: ncqual-web calls it when the change token moves, off the requests' threads. Returns
  // how many were evaluated. Any thread; stops between machines once `stop` says so.
  std::size_t refresh_budgets(const std::function<bool()>& stop = {});
  const report::BudgetMemo& budgets() const { return budgets_; }
  // The change token the pages poll (/api/v1/changes), as ChangeWatch keeps it. Any thread.
  std::string change_token() { return watch_.token(); }

 private:
  Reply route(const Request& request);
  Reply plant_page(const Request& request, bool json);
  Reply machine_page(const Request& request, const std::string& id, bool json);
  Reply check_page(const Request& request, const std::string& id, bool json);
  Reply changes(const Request& request);

  PlantConfig plant_;
  Calendar calendar_;
  Limits limits_;
  std::function<std::int64_t()> now_ns_;
  ConnectionPool pool_;
  ChangeWatch watch_;
  report::BudgetMemo budgets_;  // each machine's newest budget section (refresh_budgets)

  // The machine pages' report sections by (machine, days), with the change token they were
  // gathered at: gathered again only when the historian changed. Bounded: cleared when full.
  struct CachedReport {
    std::string token;
    std::string sections;
    std::string problem;
  };
  static constexpr std::size_t kReportCacheEntries = 64;
  std::mutex report_cache_mutex_;
  std::map<std::pair<std::string, int>, CachedReport> report_cache_;
};

// `text` with &, <, >, " and ' as character references: safe in HTML text and attributes.
std::string escape_html(const std::string& text);

}  // namespace ncqual::web
