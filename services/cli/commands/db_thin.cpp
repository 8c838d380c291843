// SPDX-License-Identifier: Apache-2.0
// `ncqual db thin`: retention by hand, the raw points of old measurement sets deleted and every
// request, result and status kept.
#include "db.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/storage/database.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdint>
#include <iostream>
#include <optional>
#include <string>

namespace ncqual::cli::database {
namespace {

struct ThinOptions {
  std::string plant;
  std::optional<std::string> db;
  std::string before;
  bool dry_run = false;
};

int run_thin(const ThinOptions& o) {
  const std::int64_t now_ns = WallClock().now_ns();
  std::int64_t before_ns = 0;
  const Calendar calendar = plant_calendar(o.plant);
  if (!o.before.empty()) {
    before_ns = plant_time_option("--before", o.before, calendar);
  } else {
    const PlantConfig plant = plant_from(o.plant);
    const auto policy = plant.retention.thin_points_before_ns(now_ns);
    if (!policy) {
      throw UsageError("pass --before D, or set historian.retention.thin_points_after_months in " +
                       plant.source_path);
    }
    before_ns = *policy;
  }
  const std::string path = database_path(o.db, o.plant);
  // Read only first: a missing file is not created, and another schema version is refused
  // rather than migrated under a running historian.
  if (!open_historian(path, "db thin")) return kExitNotFound;
  auto db = o.dry_run ? storage::Database::open_readonly(path) : storage::Database::open(path);
  storage::ThinOptions options;
  options.dry_run = o.dry_run;
  options.now_ns = now_ns;
  const auto started = std::chrono::steady_clock::now();
  const storage::ThinReport r = db.thin_points(before_ns, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const std::string cut = calendar.local_text(before_ns, true);
  if (r.sets == 0) {
    std::cout << path << ": no measurement set before " << cut
              << " has points left to thin; nothing " << (o.dry_run ? "would change" : "changed")
              << "\n";
    return kExitOk;
  }
  std::cout << fmt::format(
      "{}: {} {} measurement set{} before {} (from {} to {}): {} touches and {} tracker points{}\n",
      path, o.dry_run ? "would thin" : "thinned", r.sets, r.sets == 1 ? "" : "s", cut,
      calendar.local_text(*r.oldest_ns), calendar.local_text(*r.newest_ns), r.touches,
      r.tracker_points, o.dry_run ? " (dry run: nothing changed)" : " deleted");
  if (!o.dry_run) {
    std::cout << fmt::format(
        "  in {} transaction{}, {:.2f} s; requests, results, metrics, causes, corrections and "
        "status changes are kept;\n  the freed pages are reused by new rows (the file keeps its "
        "size)\n",
        r.transactions, r.transactions == 1 ? "" : "s", seconds);
  }
  return kExitOk;
}

}  // namespace

void add_thin(CLI::App* db, Commands& commands) {
  const auto [thin, t] = add_command(
      *db, commands, "thin",
      "retention: delete the raw points (touches, tracker points) of measurement sets before D,\n"
      "keeping every request, result, metric, cause and status; safe while the historian runs",
      run_thin);
  thin->add_option("--before", t->before,
                   std::string("a date or time, e.g. 2025-01-01, ") + kPlantZoneHelp +
                       " (default: the plant's historian.retention.thin_points_after_months "
                       "before now)")
      ->type_name("D");
  thin->add_flag("--dry-run", t->dry_run, "count what would be deleted; change nothing");
  add_plant_option(thin, t->plant);
  thin->add_option("--db", t->db, "the historian database (default: the plant's)")
      ->type_name("FILE");
}

}  // namespace ncqual::cli::database
