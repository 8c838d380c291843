// SPDX-License-Identifier: Apache-2.0
// Retention: Database::thin_points deletes the points of old measurement sets, a few sets a
// write transaction, and marks each set thinned.
#include "ncqual/storage/database.hpp"

#include "database_impl.hpp"
#include "sqlite.hpp"

#include "ncqual/common/clock.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <thread>
#include <vector>

namespace ncqual::storage {
namespace {

using sqlite::Query;
using sqlite::Sql;

// Retention (thin_points). The sets before a time whose points are still all stored, in time
// order from a cursor (time_ns, request_id), with the points each holds; a set without points is
// passed over (and never marked), so the cursor moves on through them.
constexpr Sql kSetsToThin{
    "select measurement sets to thin",
    "SELECT request_id, time_ns, "
    "(SELECT count(*) FROM touches AS t WHERE t.request_id = m.request_id), "
    "(SELECT count(*) FROM tracker_points AS p WHERE p.request_id = m.request_id) "
    "FROM measurement_sets AS m WHERE time_ns < ?1 AND points_thinned_ns IS NULL "
    "AND (time_ns, request_id) > (?2, ?3) ORDER BY time_ns, request_id LIMIT ?4"};
constexpr Sql kCountToThin{
    "count points to thin",
    "SELECT count(*), coalesce(sum(t), 0), coalesce(sum(p), 0), min(time_ns), max(time_ns) FROM "
    "(SELECT time_ns, "
    "(SELECT count(*) FROM touches AS t WHERE t.request_id = m.request_id) AS t, "
    "(SELECT count(*) FROM tracker_points AS p WHERE p.request_id = m.request_id) AS p "
    "FROM measurement_sets AS m WHERE time_ns < ?1 AND points_thinned_ns IS NULL) "
    "WHERE t + p > 0"};
constexpr Sql kDeleteTouches{"delete touches", "DELETE FROM touches WHERE request_id = ?1"};
constexpr Sql kDeleteTrackerPoints{"delete tracker points",
                                   "DELETE FROM tracker_points WHERE request_id = ?1"};
constexpr Sql kMarkThinned{
    "mark a measurement set thinned",
    "UPDATE measurement_sets SET points_thinned_ns = ?2, thinned_touches = thinned_touches + ?3, "
    "thinned_tracker_points = thinned_tracker_points + ?4 WHERE request_id = ?1"};

}  // namespace

ThinReport Database::thin_points(std::int64_t before_ns, const ThinOptions& options) {
  ThinReport report;
  report.dry_run = options.dry_run;
  if (options.dry_run) {
    return impl_->read([&] {
      Query q(impl_->statements, kCountToThin);
      q.bind(before_ns);
      if (q.step()) {
        report.sets = q.int64(0);
        report.touches = q.int64(1);
        report.tracker_points = q.int64(2);
        report.oldest_ns = q.optional_int64(3);
        report.newest_ns = q.optional_int64(4);
      }
      return report;
    });
  }
  const std::int64_t now_ns = options.now_ns.value_or(WallClock().now_ns());
  const int batch = std::max(1, options.sets_per_transaction);
  // Where the previous transaction stopped: every set up to it is thinned or has no points.
  std::int64_t cursor_ns = std::numeric_limits<std::int64_t>::min();
  std::string cursor_id;
  struct Candidate {
    std::string request_id;
    std::int64_t time_ns, touches, points;
  };
  // One transaction: the next sets after the cursor, selected under the write lock; true while
  // there may be more.
  const auto thin_some = [&] {
    std::vector<Candidate> candidates;
    {
      Query q(impl_->statements, kSetsToThin);
      q.bind(before_ns, cursor_ns, cursor_id, std::int64_t{batch});
      while (q.step()) candidates.push_back({q.text(0), q.int64(1), q.int64(2), q.int64(3)});
    }
    std::int64_t points = 0;
    for (const Candidate& c : candidates) {
      if (points >= options.points_per_transaction) return true;
      cursor_ns = c.time_ns;
      cursor_id = c.request_id;
      if (c.touches + c.points == 0) continue;
      Query(impl_->statements, kDeleteTouches).bind(c.request_id).run();
      Query(impl_->statements, kDeleteTrackerPoints).bind(c.request_id).run();
      Query(impl_->statements, kMarkThinned).bind(c.request_id, now_ns, c.touches, c.points).run();
      points += c.touches + c.points;
      ++report.sets;
      report.touches += c.touches;
      report.tracker_points += c.points;
      if (!report.oldest_ns) report.oldest_ns = c.time_ns;
      report.newest_ns = c.time_ns;
    }
    return static_cast<int>(candidates.size()) == batch;
  };
  const std::string what =
      "thin the points of measurement sets before " + std::to_string(before_ns);
  for (bool more = true; more; ++report.transactions) {
    if (report.transactions > 0 && options.pause.count() > 0) {
      std::this_thread::sleep_for(options.pause);  // the historian's writers get their turn
    }
    more = impl_->write(what, thin_some);
  }
  return report;
}

}  // namespace ncqual::storage
