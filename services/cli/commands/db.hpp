// SPDX-License-Identifier: Apache-2.0
// What the subcommands of `ncqual db` share (db.cpp): an SQLite file's header, read without
// SQLite, and how many problems a report shows; each subcommand adds itself to `db`
// (db_<subcommand>.cpp).
#pragma once

#include "commands.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

namespace ncqual::cli::database {

// The problems a report lists at the most (db check, db recover).
inline constexpr std::size_t kShownProblems = 20;

// The file header (https://www.sqlite.org/fileformat.html, 1.3).
struct FileHeader {
  bool sqlite = false;  // starts with "SQLite format 3\0"
  std::int32_t user_version = 0;
  std::int32_t application_id = 0;
};

// The first 100 bytes of the file: user_version is the big-endian 4-byte integer at offset 60,
// application_id the one at 68. Nothing when the file has no SQLite header.
FileHeader read_header(const std::string& path);

// Each adds its subcommand to `db`, and what runs it to `commands`; add_db adds them in this
// order, the order of the help.
void add_check(CLI::App* db, Commands& commands);
void add_recover(CLI::App* db, Commands& commands);
void add_thin(CLI::App* db, Commands& commands);

}  // namespace ncqual::cli::database
