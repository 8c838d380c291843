// SPDX-License-Identifier: Apache-2.0
// `ncqual db check`: the full PRAGMA integrity_check of the historian database, read only, and
// what a file that is not one of this build's historian databases is.
#include "db.hpp"

#include "ncqual/storage/database.hpp"

#include <cstddef>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

namespace ncqual::cli::database {
namespace {

// SQLite's primary result codes (sqlite3.h; the storage keeps SQLite to itself): a malformed file,
// and one whose header is not an SQLite header.
constexpr int kSqliteCorrupt = 11;
constexpr int kSqliteNotADatabase = 26;

// Whether a StorageError from opening or checking `path` means the file is damaged (malformed, or
// an SQLite header followed by something SQLite cannot read) rather than someone else's file.
bool is_corruption(const storage::StorageError& error, const std::string& path) {
  const int primary = error.sqlite_code() & 0xff;
  return primary == kSqliteCorrupt || (primary == kSqliteNotADatabase && read_header(path).sqlite);
}

struct CheckOptions {
  std::string plant;
  std::optional<std::string> db;
};

int run_check(const CheckOptions& o) {
  const std::string path = database_path(o.db, o.plant);
  std::string report;
  try {
    auto db = open_historian(path, "db check");
    if (!db) return kExitNotFound;
    report = db->integrity_check();
  } catch (const storage::StorageError& e) {
    // Not a historian database of this build (another application's file, another schema
    // version, not SQLite at all), or unreadable: say why, naming the file.
    if (!is_corruption(e, path)) {
      const std::string what = e.what();
      throw std::runtime_error(what.find(path) == std::string::npos ? path + ": " + what : what);
    }
    report = e.what();
  }
  if (report == "ok") {
    std::cout << path << ": ok\n";
    return kExitOk;
  }
  std::cout << path << ": CORRUPT\n";
  std::istringstream lines(report);
  std::size_t count = 0;
  for (std::string line; std::getline(lines, line); ++count) {
    if (count < kShownProblems) std::cout << "  " << line << "\n";
  }
  if (count > kShownProblems) std::cout << "  ... and " << count - kShownProblems << " more\n";
  std::cout << "`ncqual db recover " << path << " NEW_FILE` salvages what can be read of it\n";
  return kExitCorrupt;
}

}  // namespace

void add_check(CLI::App* db, Commands& commands) {
  const auto [check, c] = add_command(
      *db, commands, "check",
      "PRAGMA integrity_check of the historian database: ok, or CORRUPT and the problems (exit 7)",
      run_check);
  add_historian_options(check, c->plant, c->db);
}

}  // namespace ncqual::cli::database
