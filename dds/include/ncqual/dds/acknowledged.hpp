// SPDX-License-Identifier: Apache-2.0
// Acknowledged delivery (docs/architecture.md, "Acknowledged storage"):
//
// - A producer keeps every sample it sends in its Outbox, a table of its own state file, with the
//   roles that must acknowledge it (the historian; for a result also the scheduler, for a
//   measurement set also the solver). It writes the sample at once, again at every start, again
//   whenever a new reader matches its writer, and again with a growing back-off (2 s to 10 s)
//   until every role has acknowledged it. At stop it waits a few seconds for what is left and
//   says what is still unacknowledged; that goes out at the next start.
// - A service that has durably done its part with a sample (the historian committed it, the
//   scheduler applied a result, the solver saved the result of a set) says so with an
//   Acknowledger: an Acknowledgement naming the topic, the sample id and the content hash.
//
// So DDS history depth never decides whether a check is lost: a sample leaves the producer's file
// only once the roles it awaits have it in theirs.
#pragma once

#include "ncqual/dds/endpoint.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/dds/topics.hpp"
#include "ncqual/storage/state_file.hpp"

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

namespace ncqual::dds {

// The outbox entry of a sample: serialized, hashed, awaiting `roles`, queued at `queued_ns`.
template <typename Topic>
storage::OutboxEntry outbox_entry(const typename Topic::Model& value,
                                  std::vector<std::string> roles, std::int64_t queued_ns) {
  storage::OutboxEntry e;
  e.topic = Topic::kName;
  e.sample_id = sample_id_of(value);
  e.machine_id = value.machine_id;
  e.payload = serialize<Topic>(to_wire_as<typename Topic::Wire>(value));
  e.content_hash = sha256_hex(e.payload);
  e.awaiting = std::move(roles);
  e.queued_ns = queued_ns;
  return e;
}

class Outbox {
 public:
  struct Options {
    std::chrono::milliseconds first_resend{2000};
    std::chrono::milliseconds max_resend{10000};
    std::chrono::milliseconds drain_patience{5000};  // at stop
  };

  // Reads the state file's outbox; everything in it is written again once the topics are routed
  // (start()). Registers with the service: acknowledgements, periodic resends, the heartbeat's
  // outbox depth, and the drain at stop.
  Outbox(Service& service, storage::StateFile& file, Options options);
  Outbox(Service& service, storage::StateFile& file) : Outbox(service, file, Options{}) {}
  ~Outbox();
  Outbox(const Outbox&) = delete;
  Outbox& operator=(const Outbox&) = delete;

  // Samples of `Topic` in this outbox are written with `writer`, a Writer or a MachineWriters
  // (which must outlive the outbox).
  template <typename Topic, template <typename> class WriterOf>
  void route(WriterOf<Topic>& writer) {
    routes_[Topic::kName] =
        Route{[&writer](const std::vector<std::uint8_t>& bytes) {
                typename Topic::Wire wire;
                return deserialize<Topic>(bytes, wire) && writer.write_wire(wire);
              },
              [&writer] { return writer.matched_readers(); }, 0};
  }
  // Writes everything the file holds (an earlier run's unacknowledged samples). Call once the
  // topics are routed.
  void start();

  // The entry of a sample, for a caller that saves it in its own transaction
  // (StateFile::save(documents, erase, queue)) and then calls written().
  template <typename Topic>
  storage::OutboxEntry entry(const typename Topic::Model& value,
                             std::vector<std::string> roles) const {
    return outbox_entry<Topic>(value, std::move(roles), now_ns());
  }
  // Adopts entries the caller saved and writes them.
  void written(const std::vector<storage::OutboxEntry>& saved);
  // Saves one sample in the outbox and writes it; nothing happens when the same sample is
  // already queued (its resend is on its way). Throws StorageError when it cannot be saved (then
  // it is not written either: the caller decides).
  template <typename Topic>
  void send(const typename Topic::Model& value, std::vector<std::string> roles) {
    storage::OutboxEntry e = entry<Topic>(value, std::move(roles));
    if (index_.count(key_of(e))) return;
    file_.save({}, {}, {e});
    written({e});
  }

  std::int64_t depth() const { return static_cast<std::int64_t>(index_.size()); }
  std::int64_t oldest_queued_ns() const;
  // Sends what is left and waits up to `patience` for acknowledgements; logs what is still
  // unacknowledged. Returns the number of samples left.
  std::int64_t drain(std::chrono::milliseconds patience);

 private:
  using Key = std::tuple<std::string, std::string, std::string>;  // topic, sample id, hash
  struct Pending {
    std::vector<std::string> awaiting;
    std::int64_t queued_ns = 0;
    std::chrono::steady_clock::time_point next_send;
    int sends = 0;
  };
  struct Route {
    std::function<bool(const std::vector<std::uint8_t>&)> write;
    std::function<int()> matched;
    int last_matched = 0;
  };
  static Key key_of(const storage::OutboxEntry& e) {
    return {e.topic, e.sample_id, e.content_hash};
  }
  std::int64_t now_ns() const;
  void on_acknowledgement(const Acknowledgement& ack);
  void resend_due();
  void upgrade_older_layouts();
  void write(const Key& key, Pending& p, const std::vector<std::uint8_t>* payload);

  Service& service_;
  storage::StateFile& file_;
  Options options_;
  std::map<Key, Pending> index_;
  std::map<std::string, Route> routes_;
  std::unique_ptr<Reader<AcknowledgementTopic>> acks_;
};

// Says what a service did with a received sample.
class Acknowledger {
 public:
  Acknowledger(Service& service, std::string role);

  template <typename Topic>
  void acknowledge(const Received<typename Topic::Model>& in, AckOutcome outcome,
                   std::string detail = "") {
    send(Acknowledgement{in.value.machine_id, Topic::kName, sample_id_of(in.value), in.content_hash,
                         outcome, role_, service_.instance(), std::move(detail),
                         service_.clock().now_ns()});
  }
  void send(const Acknowledgement& ack);

 private:
  Service& service_;
  std::string role_;
  Writer<AcknowledgementTopic> writer_;
};

}  // namespace ncqual::dds
