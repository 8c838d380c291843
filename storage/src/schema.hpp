// SPDX-License-Identifier: Apache-2.0
// The historian's schema: every migration, in order, in schema.cpp. Nothing else creates or
// alters a table.
#pragma once

#include <sqlite3.h>

#include <cstdint>
#include <vector>

namespace ncqual::storage::schema {

// "ncqu" in ASCII: PRAGMA application_id of every ncqual historian file, so that opening some
// other SQLite file by mistake is refused instead of silently getting our tables added.
inline constexpr std::int32_t kApplicationId = 0x6E637175;

struct Migration {
  int version;              // PRAGMA user_version once applied
  const char* description;  // what the step does, for error messages
  const char* sql;          // one script, applied in the same transaction as the version bump
};

const std::vector<Migration>& migrations();
int latest_version();

int user_version(sqlite3* db);
std::int32_t application_id(sqlite3* db);

// Applies every pending migration, each in its own BEGIN IMMEDIATE transaction together with its
// user_version bump, so a crash leaves the file at a whole step and two processes opening the same
// file at once cannot both apply a step.
void migrate(sqlite3* db, const char* path);

}  // namespace ncqual::storage::schema
