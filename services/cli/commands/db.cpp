// SPDX-License-Identifier: Apache-2.0
// `ncqual db`: whether the historian database can be trusted, salvaging one that cannot, and
// thinning its old points (retention). Each subcommand is its file, db_<subcommand>.cpp; what
// they share is here (db.hpp).
//
//   ncqual db check [--plant F | --db F]
//     Runs the full PRAGMA integrity_check on the historian database, read only. Prints
//     "<path>: ok", or "<path>: CORRUPT" and SQLite's problems (the first 20). A file so damaged
//     that it cannot be opened is CORRUPT too, with SQLite's message. Exit codes: 0 ok, 7 corrupt,
//     6 no file at the path, 1 a file that is not a historian database of this build (the message
//     says why: another application's file, an older schema the historian migrates at start, ...).
//
//   ncqual db recover FROM TO
//     Salvages what can be read of FROM into the new file TO with the sqlite3 command-line shell
//     (Debian package sqlite3): its .recover where the shell has it, else its .dump, which reads
//     every table through its b-tree and keeps the rows it can reach. FROM is never written: the
//     shell reads a copy of it (and of its -wal) made in a temporary folder beside TO. TO must not
//     exist. TO then gets FROM's application_id and user_version (from FROM's file header, which
//     holds them even when the file cannot be opened), and passes PRAGMA integrity_check, or the
//     command fails. Prints the rows recovered per table, the rows in lost_and_found (.recover's
//     orphans), and what to do next. Stop the historian first: a file it is writing to is copied
//     as it is at that moment. Exit codes: 0 TO passes its check, 7 it does not, 6 no FROM, 1 TO
//     exists, no sqlite3 shell, or nothing of the historian's schema was recovered.
//
//   ncqual db thin [--before D] [--dry-run] [--plant F | --db F]
//     Retention by hand (docs/export.md, "Retention"): deletes the raw points (touches, tracker
//     points) of every measurement set older than D (a UTC date or time), keeping every request,
//     set row, result, metric, cause, correction, compensation and status change; each thinned
//     set keeps the date and its counts (`ncqual history`: "points thinned on ..."). Without
//     --before, the plant's historian.retention.thin_points_after_months before now. --dry-run
//     counts and changes nothing. Safe while the historian runs: short write transactions. Exit
//     codes: 0, 2 a bad date or no policy, 6 no file at the path, 1 a file that is not a
//     historian database of this build.
//
// The sqlite3 shell runs as a child process without a shell between (posix_spawnp), its output
// piped into a second sqlite3 that writes TO: the CLI links SQLite only through ncqual_storage.
#include "db.hpp"

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <ios>
#include <string>

namespace ncqual::cli {
namespace database {
namespace {

std::int32_t big_endian_int32(const unsigned char* p) {
  const std::uint32_t v = (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) |
                          (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
  return static_cast<std::int32_t>(v);
}

}  // namespace

FileHeader read_header(const std::string& path) {
  std::array<unsigned char, 100> bytes{};
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  FileHeader header;
  if (in.gcount() != static_cast<std::streamsize>(bytes.size()) ||
      std::memcmp(bytes.data(), "SQLite format 3", 16) != 0) {
    return header;
  }
  header.sqlite = true;
  header.user_version = big_endian_int32(bytes.data() + 60);
  header.application_id = big_endian_int32(bytes.data() + 68);
  return header;
}

}  // namespace database

void add_db(CLI::App& app, Commands& commands) {
  CLI::App* db = app.add_subcommand(
      "db", "the historian database itself: check it, recover it, thin its old points");
  db->require_subcommand(1);
  database::add_check(db, commands);
  database::add_recover(db, commands);
  database::add_thin(db, commands);
}

}  // namespace ncqual::cli
