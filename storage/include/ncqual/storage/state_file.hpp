// SPDX-License-Identifier: Apache-2.0
// A service's own durable state: named JSON documents in one SQLite file (WAL mode), replaced
// together in one transaction. The scheduler keeps its state here (one document per machine, per
// fixture, and its simulated clock), so a kill at any moment leaves either the state before a
// decision or the state after it, never half of one.
//
// The file also holds the service's outbox: every sample it sent that is not yet acknowledged by
// all the roles it awaits (docs/architecture.md, "Acknowledged storage"). A decision and what it
// sends are saved in one transaction, so a kill can never keep the one and lose the other.
//
// Not the historian: the historian records what happened for people and trends; this file holds
// what a service needs to go on where it stopped. Knows nothing of what the documents or the
// samples mean.
#pragma once

#include "ncqual/storage/database.hpp"

#include <map>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::storage {

// One sample sent and kept until every role it awaits has acknowledged it. Named by topic, sample
// id and content hash: a different sample under the same id is another entry.
struct OutboxEntry {
  std::string topic;
  std::string sample_id;
  std::string content_hash;
  std::string machine_id;
  std::vector<std::uint8_t> payload;  // the serialized sample; empty in outbox_index()
  std::vector<std::string> awaiting;  // roles still to acknowledge it, sorted
  std::int64_t queued_ns = 0;         // wall clock when it was first queued
};

struct OutboxSummary {
  std::int64_t depth = 0;
  std::int64_t oldest_queued_ns = 0;  // 0 when empty
};

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
  // Writes these documents (insert or replace), removes the keys in `erase` and queues the
  // outbox entries (an entry already queued stays as it is), all in one transaction. Throws
  // StorageError; then nothing of the call is in the file.
  void save(const std::map<std::string, std::string>& documents,
            const std::vector<std::string>& erase = {}, const std::vector<OutboxEntry>& queue = {});

  // ---- The outbox --------------------------------------------------------------------------
  // Every entry without its payload, oldest first.
  std::vector<OutboxEntry> outbox_index();
  // The payload of one entry; nothing when it is no longer queued.
  std::optional<std::vector<std::uint8_t>> outbox_payload(const std::string& topic,
                                                          const std::string& sample_id,
                                                          const std::string& content_hash);
  // `role` has acknowledged the entry: it no longer awaits it, and the entry is removed once it
  // awaits no one. Returns the roles it still awaits; nothing when no such entry was queued (or
  // it did not await `role`).
  std::optional<std::vector<std::string>> acknowledge(const std::string& topic,
                                                      const std::string& sample_id,
                                                      const std::string& content_hash,
                                                      const std::string& role);
  // Removes an entry whatever it awaits (a sample refused for good). True when it was queued.
  bool discard(const std::string& topic, const std::string& sample_id,
               const std::string& content_hash);
  OutboxSummary outbox_summary();

  const std::string& path() const;

 private:
  struct Impl;
  explicit StateFile(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace ncqual::storage
