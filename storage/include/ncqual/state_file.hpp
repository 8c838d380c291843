// SPDX-License-Identifier: Apache-2.0
// A service's own durable state: named JSON documents in one SQLite file (WAL mode), replaced
// together in one transaction. The scheduler keeps its state here (one document per machine, per
// fixture, and its simulated clock), so a kill at any moment leaves either the state before a
// decision or the state after it, never half of one.
//
// Not the historian: the historian records what happened for people and trends; this file holds
// what a service needs to go on where it stopped. Knows nothing of what the documents mean.
#pragma once

#include "ncqual/storage.hpp"

#include <map>
#include <memory>
#include <string>

namespace ncqual::storage {

class StateFile {
 public:
  // Opens or creates `path` (":memory:" for tests). Throws StorageError naming the path when it
  // cannot, or when the file is some other application's (e.g. a historian database).
  static StateFile open(const std::string& path);

  StateFile(StateFile&&) noexcept;
  StateFile& operator=(StateFile&&) noexcept;
  ~StateFile();

  // Every document, by key.
  std::map<std::string, std::string> load();
  // Writes these documents (insert or replace) and removes the keys in `erase`, all in one
  // transaction. Throws StorageError; then nothing of the call is in the file.
  void save(const std::map<std::string, std::string>& documents,
            const std::vector<std::string>& erase = {});

  const std::string& path() const;

 private:
  struct Impl;
  explicit StateFile(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace ncqual::storage
