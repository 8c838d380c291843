// SPDX-License-Identifier: Apache-2.0
#include "ncqual/historian/ingest.hpp"

#include <algorithm>
#include <utility>

namespace ncqual::historian {

Ingest::Ingest(IngestOptions options, OnChange on_change)
    : options_(options), on_change_(std::move(on_change)), delay_(options_.first_retry) {}

void Ingest::submit(std::int64_t received_ns, Store store, Steady now) {
  if (waiting_.empty() && held_.empty() && attempt(store, now)) {
    recovered();
    return;
  }
  if (waiting_.size() >= options_.max_backlog) {
    ++dropped_;  // not acknowledged: its producer keeps it and sends it again
    return;
  }
  waiting_.push_back({received_ns, std::move(store)});
}

void Ingest::retry(Steady now) {
  if (!held_.empty() || now < next_try_) return;
  while (!waiting_.empty()) {
    if (!attempt(waiting_.front().store, now)) return;
    waiting_.pop_front();
  }
  recovered();
}

void Ingest::hold(const std::string& why, Steady now) {
  if (why == held_) return;
  held_ = why;
  if (!held_.empty()) {
    set_health(storage::StorageHealth::Failed, why);
    return;
  }
  // Released: try at once.
  next_try_ = now;
  delay_ = options_.first_retry;
  retry(now);
}

bool Ingest::attempt(const Store& store, Steady now) {
  try {
    store();
  } catch (const storage::StorageError& e) {
    next_try_ = now + delay_;
    delay_ = std::min(delay_ * 2, options_.max_retry);
    set_health(storage::health_after(e.sqlite_code()),
               storage::fault_name(e.sqlite_code()) + " (" + e.what() + ")");
    return false;
  }
  delay_ = options_.first_retry;
  return true;
}

void Ingest::recovered() {
  if (health_ != storage::StorageHealth::Ok) set_health(storage::StorageHealth::Ok, "");
}

void Ingest::set_health(storage::StorageHealth health, std::string fault) {
  // A change of health, or of the kind of fault, is news; the same fault again is not.
  const auto kind = [](const std::string& f) { return f.substr(0, f.find(" (")); };
  const bool news = health != health_ || kind(fault) != kind(fault_);
  health_ = health;
  fault_ = std::move(fault);
  if (news && on_change_) on_change_(health_, detail());
}

std::string Ingest::detail() const {
  if (health_ == storage::StorageHealth::Ok && dropped_ == 0) return "";
  std::string text = fault_;
  if (!waiting_.empty()) {
    text += (text.empty() ? "" : "; ") + std::to_string(waiting_.size()) +
            " sample(s) waiting, not acknowledged";
  }
  if (dropped_ > 0) {
    text += (text.empty() ? "" : "; ") + std::to_string(dropped_) +
            " not kept (backlog full; their producers send them again)";
  }
  return text;
}

std::int64_t Ingest::oldest_received_ns() const {
  return waiting_.empty() ? 0 : waiting_.front().received_ns;
}

void Ingest::describe(Heartbeat& beat) const {
  beat.health = std::string(storage::to_string(health_));
  beat.health_detail = detail();
  beat.outbox_depth = static_cast<std::int64_t>(waiting_.size());
  beat.oldest_unacknowledged_ns = oldest_received_ns();
}

}  // namespace ncqual::historian
