// SPDX-License-Identifier: Apache-2.0
// The trend watch off the ingest path: the historian stores and acknowledges a sample first,
// then hands the watch's work for it to this worker, which runs it on its own thread and its own
// connection to the database (Database::open_another), in the order handed over. A slow
// assessment (a machine with years of checks, many warnings ending at an intervention) never
// delays storing or acknowledging; SQLite's WAL lets the two connections read while the other
// writes, and each write transaction of the watch is short.
//
// A job that fails (the database) is logged and dropped: the sample stays stored, and the
// metric's next result assesses it again. At stop the jobs waiting are finished, for at most
// kFinishAtStop; the ones still waiting then are dropped and counted in the log, for the same
// reason.
#pragma once

#include "ncqual/historian/trend_watch.hpp"

#include "ncqual/common/model.hpp"
#include "ncqual/storage/database.hpp"

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace ncqual::historian {

class WatchWorker {
 public:
  // Called on the worker's thread with the warnings raised or ended by one job (never empty),
  // once the worker has logged each.
  using Publish = std::function<void(const std::vector<TrendWarning>&)>;

  // How long the destructor lets the waiting jobs finish: a stop right after a burst (a
  // simulated month in seconds) still warns of all of it; within systemd's default stop
  // timeout (90 s).
  static constexpr std::chrono::seconds kFinishAtStop{60};

  WatchWorker(storage::Database connection, Publish publish, TrendWatch watch = TrendWatch());
  ~WatchWorker();  // the waiting jobs finish (at most kFinishAtStop); the rest are dropped
  WatchWorker(const WatchWorker&) = delete;
  WatchWorker& operator=(const WatchWorker&) = delete;

  void after_result(const CheckResult& result);
  void after_intervention(const Intervention& intervention);
  void after_compensation(const Compensation& compensation);
  // What follows any sample newly stored: the three above; nothing for the other kinds.
  void after_stored(const CheckResult& result) { after_result(result); }
  void after_stored(const Intervention& intervention) { after_intervention(intervention); }
  void after_stored(const Compensation& compensation) { after_compensation(compensation); }
  template <typename Other>
  void after_stored(const Other& /*not watched*/) {}

  // Jobs handed over and not finished yet (the one in hand included).
  std::size_t pending() const;
  // Blocks until every job handed over before the call has finished (tests, orderly stops).
  void drain();

 private:
  using Job = std::function<std::vector<TrendWarning>(storage::Database&, TrendWatch&)>;
  void submit(std::string what, Job job);
  void run();

  storage::Database db_;
  Publish publish_;
  TrendWatch watch_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable idle_;
  std::deque<std::pair<std::string, Job>> jobs_;
  std::size_t in_hand_ = 0;
  bool stopping_ = false;
  std::thread thread_;  // last: started when everything above is ready
};

}  // namespace ncqual::historian
