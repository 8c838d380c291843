// SPDX-License-Identifier: Apache-2.0
// What the historian does with one sample it received, with no DDS (the executable passes what
// the reader said of it, and acknowledges as told): the acknowledgement of docs/architecture.md,
// "Acknowledged storage".
//
//   unreadable (the reader's error)        -> REFUSED with the reader's reason
//   refused by validation (never storable) -> REFUSED with the storage's reason
//   stored now                             -> STORED; the trend watch follows
//   the same sample again                  -> DUPLICATE
//   its id stored with other content       -> CONFLICT: kept beside the first, raised as an alarm
//                                             once (a resend of the same content is not raised)
//   the database failed (locked, full, …)  -> storage::StorageError rethrown: not acknowledged;
//                                             the ingest keeps the sample (ingest.hpp)
#pragma once

#include "ncqual/historian/ingest.hpp"

#include "ncqual/common/model.hpp"
#include "ncqual/storage/database.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace ncqual::historian {

// A sample as the reader gave it.
struct Arrival {
  std::string error;         // why it could not be read; "" when it could
  std::string content_hash;  // of its serialization
  std::string writer;        // its DataWriter's GUID
  // Of a per-machine topic: "in partition '…'" or "in the default partition"; "" otherwise.
  std::string where;
};

// How a topic's samples are named: in log lines ("measurement set"), as the part of a check two
// conflicting samples are ("measurements", "results"; nullptr for other topics), and the topic's
// name (in an alarm's id).
struct SampleKind {
  const char* what;
  const char* check_part;
  const char* topic;
};

// A writer's GUID as people read it (the plant identity it carries on a secured plant).
using NameWriter = std::function<std::string(const std::string& guid)>;

// What became of a sample.
struct Outcome {
  AckOutcome ack = AckOutcome::Refused;
  std::string ack_detail;  // the reason of a refusal; the first content of a conflict
  // A conflict not raised before: an active Conflict alarm "conflict/<topic>/<sample id>/<content
  // hash>" (its source, instance and time are the publisher's to fill).
  std::optional<Alarm> alarm;
  bool newly_stored = false;  // stored now: what follows a store (the trend watch) runs
};

// Stores one sample (Model: CheckRequest, MeasurementSet, CheckResult, MachineStatus,
// Compensation, Intervention) and says what to acknowledge; logs what it did. `open_plant`: a
// per-machine sample's partition is logged at info when stored (on a secured plant the
// permissions already bind writers to partitions). Throws storage::StorageError (non-zero
// sqlite_code) when the database failed.
template <typename Model>
Outcome store_sample(storage::Database& db, const SampleKind& kind, const Model& value,
                     const Arrival& in, std::int64_t now_ns, bool open_plant,
                     const NameWriter& name);

// The text of a conflict (its log line and alarm). For a check's measurement set or result it
// opens with what the scheduler holds the machine for (Scheduler::conflict): "conflicting
// measurements of REQUEST of machine 'M' from WRITER A and WRITER B (...)".
std::string conflict_text(const SampleKind& kind, const std::string& id,
                          const std::string& machine_id, const storage::StoreResult& stored,
                          const std::string& writer, const std::string& content_hash,
                          const NameWriter& name);

// A heartbeat is a service's latest word: stored when the database is well and nothing waits
// (never acknowledged, never kept in the backlog); skipped otherwise, and logged when unreadable or
// when its store failed.
void store_heartbeat(storage::Database& db, const Ingest& ingest, const Heartbeat& beat,
                     const std::string& error);

// A change of the storage's health, logged, as the Storage alarm "storage/<instance>": active with
// "<health>: <detail>", or cleared with "<db> stores and acknowledges again" (its source and
// time are the publisher's to fill).
Alarm storage_alarm(storage::StorageHealth health, const std::string& detail,
                    const std::string& db_path, const std::string& instance);

}  // namespace ncqual::historian
