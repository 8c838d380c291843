// SPDX-License-Identifier: Apache-2.0
#include "ncqual/acquisition/station.hpp"

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/json.hpp"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

namespace ncqual::acquisition {
namespace {

// The state file's document of a measured request: {"seq": N}, its place in the order measured.
struct PerformedEntry {
  std::int64_t seq = 0;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(PerformedEntry, seq)

// The state file's document of an applied compensation.
struct AppliedEntry {
  std::int64_t seq = 0;
  Correction correction;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(AppliedEntry, seq, correction)

}  // namespace

// ---- PerformedRequests
// ---------------------------------------------------------------------------

PerformedRequests::PerformedRequests(storage::StateFile& state, std::string machine_id,
                                     std::size_t capacity)
    : state_(state), machine_id_(std::move(machine_id)), capacity_(capacity) {}

void PerformedRequests::load(const std::map<std::string, std::string>& documents) {
  const std::string prefix = "performed/" + machine_id_ + "/";
  std::vector<std::pair<std::int64_t, std::string>> found;
  for (auto it = documents.lower_bound(prefix);
       it != documents.end() && it->first.compare(0, prefix.size(), prefix) == 0; ++it) {
    try {
      found.emplace_back(nlohmann::json::parse(it->second).get<PerformedEntry>().seq,
                         it->first.substr(prefix.size()));
    } catch (const nlohmann::json::exception&) {
      spdlog::warn("{}: state file {} entry '{}' is not readable; ignored", machine_id_,
                   state_.path(), it->first);
    }
  }
  std::sort(found.begin(), found.end());
  for (const auto& [seq, request_id] : found) {
    ids_.insert(request_id);
    order_.push_back(request_id);
    next_seq_ = std::max(next_seq_, seq + 1);
  }
  if (!found.empty()) {
    spdlog::info("{}: {} performed requests remembered from {}", machine_id_, found.size(),
                 state_.path());
  }
  const std::string applied_prefix = "applied/" + machine_id_ + "/";
  std::vector<std::pair<std::int64_t, std::pair<std::string, Correction>>> applied;
  for (auto it = documents.lower_bound(applied_prefix);
       it != documents.end() && it->first.compare(0, applied_prefix.size(), applied_prefix) == 0;
       ++it) {
    try {
      auto entry = nlohmann::json::parse(it->second).get<AppliedEntry>();
      applied.push_back(
          {entry.seq, {it->first.substr(applied_prefix.size()), std::move(entry.correction)}});
      next_seq_ = std::max(next_seq_, entry.seq + 1);
    } catch (const nlohmann::json::exception& e) {
      spdlog::error(
          "{}: state file {} entry '{}' is not readable ({}); that compensation is not "
          "restored",
          machine_id_, state_.path(), it->first, e.what());
    }
  }
  std::sort(applied.begin(), applied.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [seq, entry] : applied) applied_.push_back(std::move(entry));
}

void PerformedRequests::record_applied(const std::string& request_id,
                                       const Correction& correction) {
  state_.save({{"applied/" + machine_id_ + "/" + request_id,
                nlohmann::json(AppliedEntry{next_seq_, correction}).dump()}},
              {});
  ++next_seq_;
}

void PerformedRequests::record(const std::string& request_id,
                               const std::vector<storage::OutboxEntry>& queue) {
  const std::string prefix = "performed/" + machine_id_ + "/";
  // The oldest beyond the capacity go in the same transaction; memory follows once it committed.
  const std::size_t excess = order_.size() + 1 > capacity_ ? order_.size() + 1 - capacity_ : 0;
  std::vector<std::string> erase;
  erase.reserve(excess);
  for (std::size_t i = 0; i < excess; ++i) erase.push_back(prefix + order_[i]);
  state_.save({{prefix + request_id, nlohmann::json(PerformedEntry{next_seq_}).dump()}}, erase,
              queue);
  ++next_seq_;
  ids_.insert(request_id);
  order_.push_back(request_id);
  while (order_.size() > capacity_) {
    ids_.erase(order_.front());
    order_.pop_front();
  }
}

// ---- Station
// -------------------------------------------------------------------------------------

Station::Station(std::string machine_id, std::unique_ptr<Instruments> instruments,
                 PerformedRequests performed, StationOptions options, Publish publish, Queue queue)
    : machine_id_(std::move(machine_id)),
      instruments_(std::move(instruments)),
      performed_(std::move(performed)),
      options_(options),
      publish_(std::move(publish)),
      queue_(std::move(queue)) {
  for (const auto& [request_id, correction] : performed_.applied()) {
    applied_.insert(request_id);
    if (const std::string refused = instruments_->restore(correction); !refused.empty()) {
      spdlog::error("{}: compensation of {} not restored: {}", machine_id_, request_id, refused);
    }
  }
  if (!performed_.applied().empty()) {
    spdlog::info("{}: {} applied compensation(s) remembered", machine_id_,
                 performed_.applied().size());
  }
}

bool Station::is_waiting(const std::string& request_id) const {
  if (running_.count(request_id)) return true;
  return std::any_of(waiting_.begin(), waiting_.end(), [&](const auto& entry) {
    return std::any_of(entry.second.begin(), entry.second.end(),
                       [&](const CheckRequest& r) { return r.request_id == request_id; });
  });
}

std::size_t Station::waiting() const {
  std::size_t n = 0;
  for (const auto& [correction, requests] : waiting_) n += requests.size();
  return n;
}

bool Station::on_request(const CheckRequest& req, const std::string& malformed,
                         std::int64_t now_ns) {
  if (req.machine_id != machine_id_) return false;  // the reader's filter should have done this
  if (performed_.contains(req.request_id)) {
    spdlog::debug("{} {}: already performed, not measured again", req.machine_id, req.request_id);
    return true;
  }
  if (is_waiting(req.request_id)) return false;  // sent again while it waits for its correction
  // Anything else not performed is taken afresh: one ignored as history is ignored again, one
  // whose record failed is measured again.
  // Requests older than this are history, not work: a restarted acquisition must not move the
  // machine for checks long since answered.
  if (!options_.simulated_clock && now_ns - req.time_ns > options_.max_request_age_ns) {
    spdlog::info("{} {}: request from {} s ago ignored (older than --max-request-age-s)",
                 req.machine_id, req.request_id, (now_ns - req.time_ns) / 1000000000);
    return true;
  }
  if (malformed.empty() && !req.verifies_correction_of.empty() &&
      !applied_.count(req.verifies_correction_of)) {
    spdlog::info("{} {}: waiting for the Compensation of {} before measuring", req.machine_id,
                 req.request_id, req.verifies_correction_of);
    waiting_[req.verifies_correction_of].push_back(req);
    return false;
  }
  return measure(req, malformed, now_ns);
}

bool Station::on_compensation(const Compensation& c, std::int64_t now_ns) {
  if (c.machine_id != machine_id_) return false;
  if (applied_.count(c.request_id)) return true;
  if (const std::string refused = instruments_->apply(c.correction); !refused.empty()) {
    spdlog::error("{}: {}", c.request_id, refused);
  } else if (c.correction.target.rfind("fixture:", 0) == 0) {
    spdlog::info("{}: applied {} zero offsets to {}", c.request_id, c.correction.offsets.size(),
                 c.correction.target);
  }
  applied_.insert(c.request_id);  // never applied twice in this run, recorded or not
  try {
    performed_.record_applied(c.request_id, c.correction);
  } catch (const std::exception& e) {
    // Applied but not recorded: a restart would not restore it. Not settled, so it comes again.
    spdlog::error("{}: compensation of {} applied but not recorded: {}", machine_id_, c.request_id,
                  e.what());
    return false;
  }
  // The requests that waited for this correction are measured now.
  if (auto it = waiting_.find(c.request_id); it != waiting_.end()) {
    const std::vector<CheckRequest> requests = std::move(it->second);
    waiting_.erase(it);
    for (const auto& req : requests) measure(req, "", now_ns);
  }
  return true;
}

// On a simulated clock the measurement is taken at the request's time and takes the
// instrument's time; on the wall clock it is taken now.
std::int64_t Station::measured_at(const CheckRequest& req, std::int64_t now_ns) const {
  return options_.simulated_clock
             ? req.time_ns +
                   static_cast<std::int64_t>(check_kind_info(req.kind).duration_min * 60e9)
             : now_ns;
}

bool Station::measure(const CheckRequest& req, const std::string& malformed, std::int64_t now_ns) {
  const std::int64_t at = measured_at(req, now_ns);
  if (!malformed.empty()) {
    return finish(req, unmeasured(req, at, "malformed CheckRequest: " + malformed));
  }
  std::optional<MeasurementSet> set = instruments_->measure(req, at);
  if (!set) {
    // Handed over (a control runs the program): not settled until poll() brings the set back.
    running_[req.request_id] = req;
    return false;
  }
  return finish(req, *set);
}

std::size_t Station::poll(std::int64_t now_ns) {
  std::size_t finished = 0;
  for (MeasurementSet& set : instruments_->poll()) {
    const auto it = running_.find(set.request_id);
    if (it == running_.end()) {
      spdlog::error(
          "{}: the instruments returned a measurement of {}, a request not handed to "
          "them in this run; not published",
          machine_id_, set.request_id);
      continue;
    }
    const CheckRequest req = std::move(it->second);
    running_.erase(it);
    if (options_.simulated_clock) set.time_ns = measured_at(req, now_ns);
    finish(req, set);
    ++finished;
  }
  return finished;
}

bool Station::finish(const CheckRequest& req, MeasurementSet set) {
  // The driver says whether it measured or simulated: every set, also one with an error.
  set.origin = instruments_->origin();
  spdlog::info("{} {} {}: {} touches, {} tracker points, {}{}", set.machine_id, set.request_id,
               to_string(set.kind), set.touches.size(), set.tracker_points.size(),
               to_string(set.origin), set.error.empty() ? "" : " (" + set.error + ")");
  // Recorded before it is published, with its outbox entry: a kill after this point sends the
  // set again at the next start rather than moving the machine again.
  try {
    performed_.record(req.request_id, queue_ ? queue_(set) : std::vector<storage::OutboxEntry>{});
  } catch (const std::exception& e) {
    // Not settled and not written (nothing unrecorded leaves): the request comes again and is
    // measured again then.
    spdlog::error("{}: {} not recorded as performed (it will be measured again): {}", machine_id_,
                  req.request_id, e.what());
    return false;
  }
  if (!publish_(set)) {
    spdlog::error("{}: measurement set could not be written now", set.request_id);
  }
  return true;
}

}  // namespace ncqual::acquisition
