// SPDX-License-Identifier: Apache-2.0
// What Database::open_readonly opens, for the parts of the library that read the historian
// through a connection of their own (export.cpp, backup.cpp): private to ncqual_storage.
#pragma once

#include "sqlite.hpp"

#include <string>

namespace ncqual::storage {

// A read-only connection to an existing historian file of this build's schema version, with the
// library's busy timeout. Throws StorageError naming the path: no such file, not SQLite, not an
// ncqual historian (application_id, user_version 0), another schema version.
sqlite::Connection open_readonly_connection(const std::string& path);

}  // namespace ncqual::storage
