// SPDX-License-Identifier: Apache-2.0
// The historian's file for people and for safekeeping, while the historian keeps writing to it:
// CSV files of its tables (`ncqual export`) and a consistent copy of the whole file (`ncqual
// backup`). Both read through a read-only connection of their own; docs/export.md describes
// every file and column.
#pragma once

#include <chrono>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace ncqual::storage {

// Which rows export_csv writes: those of the machines named (all when empty) whose time is in
// [since_ns, until_ns). A row's time is its own (requests.time_ns, results.time_ns, ...); the
// rows of a sample's parts (touches, metrics, ...) follow their sample's; machines and services,
// which hold a first and a last time, are written when that span meets the range.
struct ExportFilter {
  std::int64_t since_ns = std::numeric_limits<std::int64_t>::min();
  std::int64_t until_ns = std::numeric_limits<std::int64_t>::max();
  std::vector<std::string> machines;
};

struct ExportedTable {
  std::string table;                 // "touches"
  std::string file;                  // "touches.csv", in the folder given
  std::vector<std::string> columns;  // the header, in order
  std::int64_t rows = 0;             // below the header
  std::int64_t bytes = 0;
};

struct ExportReport {
  int schema_version = 0;
  std::vector<ExportedTable> tables;  // in the order written
};

// The tables export_csv writes, in the order it writes them: every table of the historian that
// holds plant data.
std::vector<std::string> exported_tables();

// Writes `<table>.csv` into the existing folder `dir` for every table of exported_tables(),
// replacing files of those names, from one read transaction (one consistent snapshot of the
// file, however long it takes and whatever the historian commits meanwhile). RFC 4180: a header
// row of the column names, then one row per table row, fields separated by commas, lines ended
// by CRLF, a field in double quotes (and its quotes doubled) when it holds a comma, a quote, CR
// or LF; UTF-8 without a BOM. Values:
//   NULL            an empty field; an empty text is "" (quoted), so the two stay apart
//   integers        as stored
//   reals           the shortest decimal text that reads back to the same double (std::to_chars),
//                   with ".0" on an integral value; an infinite tolerance bound is inf or -inf
//   times           each column ending in _ns (ns since the epoch, UTC, as stored) is followed by
//                   one ending in _utc: the same instant as ISO 8601,
//                   2027-01-15T08:00:01.000000000Z (empty when NULL, and for
//                   services.oldest_unacknowledged_ns 0: none waiting)
//   check kinds     each INTEGER column `kind` or ending in _kind is followed by `<column>_name`
//                   (monument_positioning), unless the table holds that column already
// Throws StorageError for the database (the messages of Database::open_readonly) and
// std::runtime_error naming the file when one cannot be written.
ExportReport export_csv(const std::string& database, const ExportFilter& filter,
                        const std::string& dir);

struct BackupOptions {
  bool overwrite = false;              // replace an existing file (else StorageError)
  bool quick_check = false;            // PRAGMA quick_check of the copy instead of integrity_check
  int pages_per_step = 256;            // pages copied per step (1 MiB at SQLite's 4 KiB pages)
  std::chrono::milliseconds pause{1};  // between steps
};

struct BackupReport {
  int schema_version = 0;
  std::int64_t pages = 0;
  std::int64_t page_size = 0;
  std::int64_t bytes = 0;  // the copy's size
  int steps = 0;
  double seconds = 0;    // copying and checking
  std::string check;     // "ok", or the problems of the copy (then it is not kept)
  bool written = false;  // the copy is at the file's name
};

// A consistent copy of the historian `database` into `file` while the historian writes to it:
// SQLite's online backup API, a few pages per step with a pause between, all from one read
// transaction of the source (in WAL mode the writers go on; the copy is the file as it was when
// the backup began), into a temporary file beside `file`; then PRAGMA integrity_check (or
// quick_check) of the copy, which is renamed to `file` only when it passes, so a failed backup
// never leaves a partial file under that name. The copy is a historian file like any other (the
// historian opens it as it is). Throws StorageError (the database, the copy) naming the file.
BackupReport backup(const std::string& database, const std::string& file,
                    const BackupOptions& options = {});

}  // namespace ncqual::storage
