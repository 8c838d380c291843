// SPDX-License-Identifier: Apache-2.0
// `ncqual export` and `ncqual backup`: the historian's data for people and for safekeeping, while
// the historian keeps writing (docs/export.md).
//
//   ncqual export --since D [--until D] [--machine M,...] --csv DIR [--overwrite]
//                 [--plant F | --db F]
//     One CSV file per table of the historian (storage::exported_tables) into DIR, from one read
//     transaction: the rows of [--since, --until) (dates or times in the plant's zone; a row's own
//     time, the parts of a sample by their sample's) of the machines named (all without --machine);
//     then manifest.json (this build, the database and its schema version, the filter, rows, bytes
//     and columns per file, when), written last: a folder without it is an export that did not end.
//     DIR is created; an existing DIR must be empty, or --overwrite replaces the files of those
//     names. Exit codes: 0, 2 bad usage (a date, DIR a file or not empty, a machine the
//     plant does not configure, or without a plant config the historian does not hold), 6 no file
//     at the path, 1 anything else (the message says).
//
//   ncqual backup --out FILE [--overwrite] [--quick] [--step-pages N] [--plant F | --db F]
//     A consistent copy of the historian into FILE with SQLite's online backup API, the
//     historian running or not (storage::backup): the file as it was when the backup began,
//     PRAGMA integrity_check'ed (--quick: quick_check) before it takes FILE's name. Prints the
//     pages, the size and the time. Exit codes: 0, 2 FILE exists (without --overwrite) or is a
//     folder, 6 no historian at the path, 7 the copy fails its check (nothing is written), 1
//     anything else.
#include "commands.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/common/json.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/storage/export.hpp"
#include "ncqual/common/version.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <set>
#include <sstream>

namespace ncqual::cli {
namespace {

namespace fs = std::filesystem;

std::string iso(std::int64_t ns) {
  char buffer[32];
  return std::string(format_iso8601(ns, buffer));
}

std::string size_text(std::int64_t bytes) {
  constexpr std::int64_t kMiB = std::int64_t{1} << 20;
  return bytes < kMiB ? fmt::format("{:.1f} KiB", bytes / 1024.0)
                      : fmt::format("{:.1f} MiB", static_cast<double>(bytes) / kMiB);
}

// ---- manifest.json ------------------------------------------------------------------------------

struct FilterDocument {
  std::int64_t since_ns = 0;
  std::string since_utc;
  std::optional<std::int64_t> until_ns;  // null: up to the newest row
  std::optional<std::string> until_utc;
  std::vector<std::string> machines;  // empty: every machine
};

struct FileDocument {
  std::string file;
  std::string table;
  std::int64_t rows = 0;
  std::int64_t bytes = 0;
  std::vector<std::string> columns;
};

struct ManifestDocument {
  std::string ncqual;    // "ncqual 0.1.0 (git 8c8baf2)": the build that wrote the export
  std::string database;  // the historian file read
  int schema_version = 0;
  std::int64_t created_ns = 0;
  std::string created_utc;
  std::string format;  // what the files are, in a sentence; docs/export.md has every column
  FilterDocument filter;
  std::vector<FileDocument> files;
};

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(FilterDocument, since_ns, since_utc, until_ns, until_utc,
                                   machines)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(FileDocument, file, table, rows, bytes, columns)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ManifestDocument, ncqual, database, schema_version, created_ns,
                                   created_utc, format, filter, files)

constexpr const char* kFormat =
    "RFC 4180 CSV, UTF-8, CRLF, a header row; NULL an empty field, an empty text \"\"; reals to "
    "the shortest round-trip digits; each *_ns column (ns since the epoch, UTC) followed by its "
    "*_utc (ISO 8601); docs/export.md";

// ---- export -------------------------------------------------------------------------------------

struct ExportOptions {
  std::string plant;
  std::optional<std::string> db;
  std::string since, until, csv;
  std::vector<std::string> machines;
  bool overwrite = false;
};

// DIR ready to be written: created when missing; refused when it is a file, or not empty without
// --overwrite. With --overwrite the old manifest goes first: until the new one is written, the
// folder is not a finished export.
void prepare_folder(const ExportOptions& o) {
  const fs::path dir = o.csv;
  std::error_code error;
  const fs::file_status status = fs::status(dir, error);
  if (fs::exists(status)) {
    if (!fs::is_directory(status)) {
      throw UsageError("--csv '" + o.csv + "' is a file, not a folder: name a folder");
    }
    if (!fs::is_empty(dir) && !o.overwrite) {
      throw UsageError("--csv '" + o.csv +
                       "' is not empty: name a new folder, or --overwrite to replace the files of "
                       "an export there");
    }
    fs::remove(dir / "manifest.json");
    return;
  }
  fs::create_directories(dir);
}

int run_export(const ExportOptions& o) {
  storage::ExportFilter filter;
  const Calendar calendar = plant_calendar(o.plant);
  filter.since_ns = plant_time_option("--since", o.since, calendar);
  if (!o.until.empty()) {
    filter.until_ns = plant_time_option("--until", o.until, calendar);
    if (filter.until_ns <= filter.since_ns) {
      throw UsageError("--until " + o.until + " is not after --since " + o.since);
    }
  }
  const std::string path = database_path(o.db, o.plant);
  const bool configured = check_machines_configured(o.machines, o.plant);
  {
    auto db = open_historian(path, "export");
    if (!db) return kExitNotFound;
    if (!configured) check_machines_held(o.machines, *db, path);
  }
  filter.machines = o.machines;
  prepare_folder(o);

  const auto started = std::chrono::steady_clock::now();
  const storage::ExportReport report = storage::export_csv(path, filter, o.csv);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  ManifestDocument manifest;
  manifest.ncqual = version_line("ncqual");
  manifest.database = fs::absolute(path).lexically_normal().string();
  manifest.schema_version = report.schema_version;
  manifest.created_ns = WallClock().now_ns();
  manifest.created_utc = iso(manifest.created_ns);
  manifest.format = kFormat;
  manifest.filter.since_ns = filter.since_ns;
  manifest.filter.since_utc = iso(filter.since_ns);
  if (!o.until.empty()) {
    manifest.filter.until_ns = filter.until_ns;
    manifest.filter.until_utc = iso(filter.until_ns);
  }
  manifest.filter.machines = filter.machines;
  std::int64_t rows = 0, bytes = 0;
  for (const auto& t : report.tables) {
    manifest.files.push_back({t.file, t.table, t.rows, t.bytes, t.columns});
    rows += t.rows;
    bytes += t.bytes;
  }
  const fs::path manifest_path = fs::path(o.csv) / "manifest.json";
  {
    std::ofstream out(manifest_path);
    out << nlohmann::json(manifest).dump(2) << "\n";
    if (!out.flush()) throw std::runtime_error("cannot write " + manifest_path.string());
  }

  std::cout << fmt::format("exported {} into {}: {} files, {} rows, {}, in {:.2f} s\n", path, o.csv,
                           report.tables.size(), rows, size_text(bytes), seconds);
  std::cout << fmt::format(
      "  from {} to {}, {}\n", calendar.local_text(filter.since_ns, true),
      o.until.empty() ? std::string("the newest row") : calendar.local_text(filter.until_ns, true),
      filter.machines.empty() ? std::string("every machine")
                              : "machines " + fmt::format("{}", fmt::join(filter.machines, ",")));
  for (const auto& t : report.tables) {
    std::cout << fmt::format("  {:<28} {:>9} rows\n", t.file, t.rows);
  }
  std::cout << "  manifest.json (docs/export.md describes every column)\n";
  return kExitOk;
}

// ---- backup -------------------------------------------------------------------------------------

struct BackupOptions {
  std::string plant;
  std::optional<std::string> db;
  std::string out;
  bool overwrite = false;
  bool quick = false;
  int step_pages = storage::BackupOptions{}.pages_per_step;
};

int run_backup(const BackupOptions& o) {
  const std::string path = database_path(o.db, o.plant);
  std::error_code error;
  const fs::file_status status = fs::symlink_status(o.out, error);
  if (fs::is_directory(status)) {
    throw UsageError("--out '" + o.out + "' is a folder: name the backup file");
  }
  if (fs::exists(status) && !o.overwrite) {
    throw UsageError("--out '" + o.out + "' exists already; name another file, or --overwrite");
  }
  if (o.step_pages < 1)
    throw UsageError("--step-pages " + std::to_string(o.step_pages) + ": at least 1");
  if (!open_historian(path, "backup")) return kExitNotFound;
  if (!fs::path(o.out).parent_path().empty()) fs::create_directories(fs::path(o.out).parent_path());

  storage::BackupOptions options;
  options.overwrite = o.overwrite;
  options.quick_check = o.quick;
  options.pages_per_step = o.step_pages;
  const storage::BackupReport r = storage::backup(path, o.out, options);
  const char* check = o.quick ? "quick_check" : "integrity_check";
  if (!r.written) {
    std::cerr << "ncqual backup: the copy of " << path << " fails PRAGMA " << check
              << "; nothing was written to " << o.out << ":\n";
    std::istringstream lines(r.check);
    int shown = 0;
    for (std::string line; shown < 20 && std::getline(lines, line); ++shown) {
      std::cerr << "  " << line << "\n";
    }
    std::cerr << "`ncqual db check` checks the historian itself\n";
    return kExitCorrupt;
  }
  std::cout << fmt::format(
      "backed up {} (schema version {}) to {}: {} pages of {} bytes ({}) in {:.2f} s, {} "
      "step{}; PRAGMA {}: ok\n",
      path, r.schema_version, o.out, r.pages, r.page_size, size_text(r.bytes), r.seconds, r.steps,
      r.steps == 1 ? "" : "s", check);
  return kExitOk;
}

}  // namespace

void add_export(CLI::App& app, Commands& commands) {
  const auto [cmd, o] = add_command(
      app, commands, "export",
      "CSV files of the historian's tables for a time range and machines, from one snapshot,\n"
      "with manifest.json; read only, the historian may be running (docs/export.md)",
      run_export);
  cmd->add_option(
         "--since", o->since,
         std::string("from this date or time on (2027-01-01, 2027-01-01T06:00), ") + kPlantZoneHelp)
      ->type_name("D")
      ->required();
  cmd->add_option("--until", o->until,
                  std::string("before this date or time, ") + kPlantZoneHelp +
                      " (default: up to the newest)")
      ->type_name("D");
  cmd->add_option("--machine", o->machines, "only these machines' rows (default: every machine)")
      ->delimiter(',')
      ->type_name("M,...");
  cmd->add_option("--csv", o->csv, "the folder to write into (created; must be empty)")
      ->type_name("DIR")
      ->required();
  cmd->add_flag("--overwrite", o->overwrite, "write into a folder that is not empty");
  add_historian_options(cmd, o->plant, o->db);
}

void add_backup(CLI::App& app, Commands& commands) {
  const auto [cmd, o] = add_command(
      app, commands, "backup",
      "a consistent copy of the historian into FILE while it runs (SQLite's online backup),\n"
      "checked with PRAGMA integrity_check before it takes the name",
      run_backup);
  cmd->add_option("--out", o->out, "the backup file (must not exist)")
      ->type_name("FILE")
      ->required();
  cmd->add_flag("--overwrite", o->overwrite, "replace FILE if it exists");
  cmd->add_flag("--quick", o->quick, "check the copy with PRAGMA quick_check (faster)");
  cmd->add_option("--step-pages", o->step_pages, "pages copied per step, a short pause between")
      ->type_name("N")
      ->capture_default_str();
  add_historian_options(cmd, o->plant, o->db);
}

}  // namespace ncqual::cli
