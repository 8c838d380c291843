// SPDX-License-Identifier: Apache-2.0
#include "ncqual/historian/watch_worker.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <exception>

namespace ncqual::historian {

WatchWorker::WatchWorker(storage::Database connection, Publish publish, TrendWatch watch)
    : db_(std::move(connection)),
      publish_(std::move(publish)),
      watch_(std::move(watch)),
      thread_([this] { run(); }) {}

WatchWorker::~WatchWorker() {
  std::size_t dropped = 0;
  {
    // The jobs waiting are finished first (a stop right after a run still warns of it), for a
    // bounded time: a long backlog (a replay) is left to the metrics' next results.
    std::unique_lock lock(mutex_);
    if (!jobs_.empty()) {
      spdlog::info("trend watch: {} assessment(s) to finish before stopping (at most {} s)",
                   jobs_.size() + in_hand_, kFinishAtStop.count());
    }
    idle_.wait_for(lock, kFinishAtStop, [this] { return jobs_.empty() && in_hand_ == 0; });
    stopping_ = true;
    dropped = jobs_.size();
    jobs_.clear();
  }
  wake_.notify_all();
  thread_.join();
  if (dropped > 0) {
    spdlog::info(
        "trend watch stopped with {} assessment(s) not done; the next result of each metric "
        "assesses it again",
        dropped);
  }
}

void WatchWorker::after_result(const CheckResult& result) {
  submit("result " + result.request_id, [result](storage::Database& db, TrendWatch& watch) {
    return watch.after_result(db, result);
  });
}

void WatchWorker::after_intervention(const Intervention& intervention) {
  submit("intervention " + intervention.intervention_id,
         [intervention](storage::Database& db, TrendWatch& watch) {
           return watch.after_intervention(db, intervention);
         });
}

void WatchWorker::after_compensation(const Compensation& compensation) {
  submit("compensation " + compensation.request_id,
         [compensation](storage::Database& db, TrendWatch& watch) {
           return watch.after_compensation(db, compensation);
         });
}

std::size_t WatchWorker::pending() const {
  std::lock_guard lock(mutex_);
  return jobs_.size() + in_hand_;
}

void WatchWorker::drain() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [this] { return (jobs_.empty() && in_hand_ == 0) || stopping_; });
}

void WatchWorker::submit(std::string what, Job job) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return;
    jobs_.emplace_back(std::move(what), std::move(job));
  }
  wake_.notify_one();
}

void WatchWorker::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
    if (stopping_) break;
    auto [what, job] = std::move(jobs_.front());
    jobs_.pop_front();
    in_hand_ = 1;
    lock.unlock();
    const auto started = std::chrono::steady_clock::now();
    try {
      const std::vector<TrendWarning> changes = job(db_, watch_);
      for (const TrendWarning& w : changes) {
        if (w.active) {
          spdlog::warn("trend warning raised: {}", w.text);
        } else {
          spdlog::info("trend warning of {} {} ({}) ended by {}", w.machine_id, w.metric, w.kind,
                       w.ended_by);
        }
      }
      if (!changes.empty()) publish_(changes);
    } catch (const std::exception& e) {
      spdlog::error("trend watch after {}: {}; its metrics are assessed again at their next result",
                    what, e.what());
    }
    spdlog::debug(
        "trend watch after {}: {:.1f} ms", what,
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started)
            .count());
    lock.lock();
    in_hand_ = 0;
    if (jobs_.empty()) idle_.notify_all();
  }
  in_hand_ = 0;
  idle_.notify_all();
}

}  // namespace ncqual::historian
