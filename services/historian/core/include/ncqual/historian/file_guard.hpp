// SPDX-License-Identifier: Apache-2.0
// The historian's database file itself, checked every second: removed or replaced while open,
// every later commit would go where nobody reads it. Then every attempt is held (Ingest::hold),
// what the connection holds is copied once to <file>.rescued-<time>, and the hold is released when
// the path names the opened file again (moved back).
#pragma once

#include "ncqual/storage/database.hpp"

#include <cstdint>
#include <string>

namespace ncqual::historian {

// "<path>.rescued-<UTC time without colons>", e.g. "h.db.rescued-2026-11-28T071500Z".
std::string rescue_name(const std::string& path, std::int64_t now_ns);

class FileGuard {
 public:
  FileGuard(storage::Database& db, std::string path) : db_(db), path_(std::move(path)) {}
  // "" while the file is the one opened; else why every attempt is held (give it to
  // Ingest::hold). The first check that finds a problem copies what the connection holds.
  std::string check(std::int64_t now_ns);
  // The copy made for the current problem; "" when none was made or the problem is over.
  const std::string& rescued_to() const { return rescued_to_; }

 private:
  storage::Database& db_;
  std::string path_;
  bool rescued_ = false;
  std::string rescued_to_;
};

}  // namespace ncqual::historian
