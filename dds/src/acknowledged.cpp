// SPDX-License-Identifier: Apache-2.0
#include "ncqual/dds/acknowledged.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/dds/raw.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace ncqual::dds {

namespace {
std::string roles_text(const std::vector<std::string>& roles) {
  std::string out;
  for (const auto& r : roles) out += (out.empty() ? "" : ", ") + r;
  return out;
}
}  // namespace

Outbox::Outbox(Service& service, storage::StateFile& file, Options options)
    : service_(service), file_(file), options_(options) {
  const auto now = std::chrono::steady_clock::now();
  for (auto& e : file_.outbox_index()) {
    index_[key_of(e)] = Pending{e.awaiting, e.queued_ns, now, 0};
  }
  if (!index_.empty()) {
    spdlog::info("outbox {}: {} samples not yet acknowledged from the last run", file_.path(),
                 index_.size());
  }
  acks_ = std::make_unique<Reader<AcknowledgementTopic>>(service_.participant());
  service_.dispatcher().on(*acks_, [this](const Received<Acknowledgement>& in) {
    if (!in.error.empty()) {
      spdlog::warn("acknowledgement of {} {} from {} ignored: {}", in.value.topic,
                   in.value.sample_id, in.value.instance, in.error);
      return;
    }
    on_acknowledgement(in.value);
  });
  service_.dispatcher().every(std::chrono::milliseconds(250), [this] { resend_due(); });
  service_.on_heartbeat([this](Heartbeat& beat) {
    beat.outbox_depth = depth();
    beat.oldest_unacknowledged_ns = oldest_queued_ns();
  });
  service_.before_stop([this] { drain(options_.drain_patience); });
}

Outbox::~Outbox() = default;

std::int64_t Outbox::now_ns() const { return service_.clock().now_ns(); }

std::int64_t Outbox::oldest_queued_ns() const {
  std::int64_t oldest = 0;
  for (const auto& [key, p] : index_) {
    if (oldest == 0 || p.queued_ns < oldest) oldest = p.queued_ns;
  }
  return oldest;
}

void Outbox::start() {
  upgrade_older_layouts();
  for (auto& [key, p] : index_) write(key, p, nullptr);
}

// A sample an older version left in the file in an older wire contract's layout of its topic
// (docs/architecture.md, "Changing the wire contract"): this version's writers and readers speak
// the current layout only, so it is queued again in that layout (a new content hash, the same
// roles awaited) and the old entry removed. Saved before the old one is removed: a kill between
// the two leaves both, and the next start upgrades the old one again into the same entry.
void Outbox::upgrade_older_layouts() {
  std::vector<Key> keys;
  for (const auto& [key, p] : index_) keys.push_back(key);
  for (const Key& key : keys) {
    const auto& [topic, sample_id, hash] = key;
    const TopicInfo* info = find_topic(topic);
    if (info == nullptr || info->older.empty()) continue;
    const auto payload = file_.outbox_payload(topic, sample_id, hash);
    std::string machine_id;
    std::string error;
    if (!payload || info->machine_of(*payload, machine_id, error)) continue;  // current layout
    for (const OlderLayout& layout : info->older) {
      std::vector<std::uint8_t> current;
      std::string why;
      if (!layout.upgrade(*payload, current, why)) continue;
      const Pending pending = index_.at(key);
      storage::OutboxEntry e;
      e.topic = topic;
      e.sample_id = sample_id;
      info->machine_of(current, e.machine_id, why);
      e.content_hash = sha256_hex(current);
      e.payload = std::move(current);
      e.awaiting = pending.awaiting;
      e.queued_ns = pending.queued_ns;
      file_.save({}, {}, {e});
      file_.discard(topic, sample_id, hash);
      index_.erase(key);
      index_[key_of(e)] = pending;
      spdlog::warn(
          "outbox {}: {} {} was queued by an older version in wire contract {}; sent in contract "
          "{} instead (content hash {} -> {})",
          file_.path(), topic, sample_id, layout.contract, info->contract, hash.substr(0, 12),
          e.content_hash.substr(0, 12));
      break;
    }
  }
}

void Outbox::written(const std::vector<storage::OutboxEntry>& saved) {
  for (const auto& e : saved) {
    auto [it, added] = index_.try_emplace(
        key_of(e), Pending{e.awaiting, e.queued_ns, std::chrono::steady_clock::now(), 0});
    if (!added) continue;  // already on its way: its resend timer sends it again
    write(it->first, it->second, e.payload.empty() ? nullptr : &e.payload);
  }
}

void Outbox::write(const Key& key, Pending& p, const std::vector<std::uint8_t>* payload) {
  const auto& [topic, sample_id, hash] = key;
  auto route = routes_.find(topic);
  if (route == routes_.end()) {
    spdlog::error("outbox: no writer for {} ({}); kept", topic, sample_id);
    return;
  }
  std::optional<std::vector<std::uint8_t>> loaded;
  if (!payload) {
    loaded = file_.outbox_payload(topic, sample_id, hash);
    if (!loaded) return;  // acknowledged meanwhile
    payload = &*loaded;
  }
  if (!route->second.write(*payload)) {
    spdlog::warn("outbox: {} {} could not be written now; sent again later", topic, sample_id);
  }
  ++p.sends;
  const auto backoff =
      std::min(options_.max_resend, options_.first_resend * (1 << std::min(p.sends - 1, 8)));
  p.next_send = std::chrono::steady_clock::now() + backoff;
}

void Outbox::resend_due() {
  // A reader that matched since the last look (a restarted historian, scheduler or solver) gets
  // every sample of its topic at once, not at the end of a back-off.
  std::vector<std::string> rematched;
  for (auto& [topic, route] : routes_) {
    const int matched = route.matched();
    if (matched > route.last_matched) rematched.push_back(topic);
    route.last_matched = matched;
  }
  const auto now = std::chrono::steady_clock::now();
  for (auto& [key, p] : index_) {
    const bool reader_new =
        std::find(rematched.begin(), rematched.end(), std::get<0>(key)) != rematched.end();
    if (reader_new || p.next_send <= now) write(key, p, nullptr);
  }
}

void Outbox::on_acknowledgement(const Acknowledgement& ack) {
  auto it = index_.find(Key{ack.topic, ack.sample_id, ack.content_hash});
  if (it == index_.end()) return;  // another producer's sample, or acknowledged before
  Pending& p = it->second;
  if (std::find(p.awaiting.begin(), p.awaiting.end(), ack.by) == p.awaiting.end()) return;
  try {
    if (ack.outcome == AckOutcome::Refused) {
      // Refused for good (malformed, invalid): sending it again would change nothing.
      spdlog::error("{} {} of '{}' refused by the {} ({}): {}; removed from the outbox", ack.topic,
                    ack.sample_id, ack.machine_id, ack.by, ack.instance, ack.detail);
      file_.discard(ack.topic, ack.sample_id, ack.content_hash);
      index_.erase(it);
      return;
    }
    if (ack.outcome == AckOutcome::Conflict) {
      spdlog::warn(
          "{} {} of '{}': the {} holds another sample with this id ({}); ours is kept "
          "beside it and the conflict flagged",
          ack.topic, ack.sample_id, ack.machine_id, ack.by, ack.detail);
    }
    const auto left = file_.acknowledge(ack.topic, ack.sample_id, ack.content_hash, ack.by);
    if (!left || left->empty()) {
      index_.erase(it);
    } else {
      p.awaiting = *left;
    }
  } catch (const storage::StorageError& e) {
    // Kept: the sample goes out again and is acknowledged again.
    spdlog::error("outbox {}: acknowledgement of {} {} not recorded: {}", file_.path(), ack.topic,
                  ack.sample_id, e.what());
  }
}

std::int64_t Outbox::drain(std::chrono::milliseconds patience) {
  if (!index_.empty()) {
    start();  // everything left, now
    service_.dispatcher().drain_until([this] { return index_.empty(); }, patience);
  }
  if (index_.empty()) {
    spdlog::info("outbox {}: every sample acknowledged", file_.path());
    return 0;
  }
  std::map<std::string, int> by_role;
  for (const auto& [key, p] : index_) {
    by_role[std::get<0>(key) + " awaiting " + roles_text(p.awaiting)]++;
  }
  std::string what;
  for (const auto& [k, n] : by_role)
    what += (what.empty() ? "" : "; ") + std::to_string(n) + " " + k;
  char oldest[32];
  spdlog::warn(
      "outbox {}: {} samples not yet acknowledged ({}), oldest queued {}; they are sent "
      "again at the next start",
      file_.path(), index_.size(), what, format_iso8601(oldest_queued_ns(), oldest));
  return depth();
}

Acknowledger::Acknowledger(Service& service, std::string role)
    : service_(service), role_(std::move(role)), writer_(service.participant()) {}

void Acknowledger::send(const Acknowledgement& ack) {
  if (!writer_.write(ack)) {
    spdlog::warn("acknowledgement of {} {} could not be written; the producer sends it again",
                 ack.topic, ack.sample_id);
  }
}

}  // namespace ncqual::dds
