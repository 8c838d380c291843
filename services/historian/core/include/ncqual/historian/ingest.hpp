// SPDX-License-Identifier: Apache-2.0
// What the historian does with each sample it receives when the database is in trouble, with no
// DDS and no clock of its own (the executable passes the time), so a test can drive it.
//
//   nothing waiting, not held  -> store now; on a database failure keep it (the backlog)
//   something waiting or held  -> keep it behind the others, in arrival order
//   retry(now), when due       -> store the waiting ones oldest first, stop at the first failure;
//                                 back-off 250 ms doubling to 4 s
//   hold(why)                  -> an outside fault (the file removed or replaced): nothing is
//                                 tried until hold("") releases it
//
// A sample is acknowledged by its Store only once committed, so nothing waiting here is
// acknowledged: its producer still has it in its outbox. Health follows the last attempt: ok,
// degraded (locked by another connection: retried), failed (full, I/O error, corrupt, held). The
// backlog is bounded; what arrives beyond it is not kept (its producer sends it again) and
// counted.
#pragma once

#include "ncqual/storage/database.hpp"

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <string>

namespace ncqual::historian {

using Steady = std::chrono::steady_clock::time_point;

struct IngestOptions {
  std::chrono::milliseconds first_retry{250};
  std::chrono::milliseconds max_retry{4000};
  std::size_t max_backlog = 200000;
};

class Ingest {
 public:
  // Stores one sample and acknowledges it; throws storage::StorageError with a non-zero
  // sqlite_code when the database failed (the sample is then kept and tried again). A sample that
  // can never be stored is the Store's to refuse (acknowledged REFUSED), not an error here.
  using Store = std::function<void()>;
  // Every change of health or fault, with its detail: the executable logs it and sends a
  // heartbeat at once.
  using OnChange = std::function<void(storage::StorageHealth, const std::string& detail)>;

  Ingest(IngestOptions options, OnChange on_change);

  // A sample received at `received_ns` (ns since the epoch, for the heartbeat's oldest waiting).
  void submit(std::int64_t received_ns, Store store, Steady now);
  // Stores what waits, oldest first, once its retry is due; stops at the first failure.
  void retry(Steady now);
  // An outside fault stops every attempt until released with an empty `why`.
  void hold(const std::string& why, Steady now);

  storage::StorageHealth health() const { return health_; }
  // Why, when not ok; with the backlog and what was not kept.
  std::string detail() const;
  std::size_t backlog() const { return waiting_.size(); }
  // Receive time of the oldest waiting sample; 0 when none waits.
  std::int64_t oldest_received_ns() const;
  // The heartbeat's storage fields: health, its detail, the backlog and the oldest waiting.
  void describe(Heartbeat& beat) const;
  // Samples not kept because the backlog was full (never acknowledged).
  std::size_t dropped() const { return dropped_; }

 private:
  struct Waiting {
    std::int64_t received_ns;
    Store store;
  };
  // Runs one store: true when committed; false (health updated) when the database failed.
  bool attempt(const Store& store, Steady now);
  // Nothing waits and the last attempt committed: ok again (news only if it was not).
  void recovered();
  void set_health(storage::StorageHealth health, std::string fault);

  const IngestOptions options_;
  const OnChange on_change_;
  std::deque<Waiting> waiting_;
  storage::StorageHealth health_ = storage::StorageHealth::Ok;
  std::string fault_;  // the fault in a few words, and SQLite's message
  std::string held_;   // the outside fault holding every attempt; "" when none
  Steady next_try_{};
  std::chrono::milliseconds delay_;
  std::size_t dropped_ = 0;
};

}  // namespace ncqual::historian
