// SPDX-License-Identifier: Apache-2.0
// Typed writers and readers over the Fast DDS 2.9 DCPS API, in domain-model types.
#pragma once

#include "ncqual/dds/convert.hpp"
#include "ncqual/dds/participant.hpp"
#include "ncqual/dds/serialized.hpp"

#include <fastdds/dds/core/condition/StatusCondition.hpp>
#include <fastdds/dds/core/condition/WaitSet.hpp>
#include <fastdds/dds/core/status/PublicationMatchedStatus.hpp>
#include <fastdds/dds/core/status/SubscriptionMatchedStatus.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace ncqual::dds {

eprosima::fastrtps::Duration_t to_dds_duration(std::chrono::milliseconds ms);

// Waits on `condition` with `status` enabled (a publication or subscription match) until
// `matched()` reaches `count`, or the timeout; the condition's other statuses are left as they
// were. Returns whether the count was reached.
template <typename Matched>
bool wait_until_matched(eprosima::fastdds::dds::StatusCondition& condition,
                        const eprosima::fastdds::dds::StatusMask& status, const Matched& matched,
                        int count, std::chrono::milliseconds timeout) {
  using namespace eprosima::fastdds::dds;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  const StatusMask before = condition.get_enabled_statuses();
  StatusMask with_status = before;
  with_status << status;
  condition.set_enabled_statuses(with_status);
  WaitSet waitset;
  waitset.attach_condition(condition);
  bool reached = true;
  while (matched() < count) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      reached = false;
      break;
    }
    ConditionSeq active;
    waitset.wait(active, to_dds_duration(left));
  }
  condition.set_enabled_statuses(before);
  return reached;
}

// In one machine's partition (machine_partition): where a per-machine topic's writer writes and
// its reader reads. A reader bound so reads unfiltered and flags every sample that names another
// machine `foreign`; with an empty id, it reads the default partition (writers without
// partitions, which only an open plant has), unbound; on a secured plant every sample it
// receives is foreign (refused, naming its writer): a machine-bound sample travels only in its
// machine's partition there. A type of its own, so that a machine id is
// never taken for a QoS profile name (both are strings).
struct InPartitionOf {
  std::string machine_id;
};

template <typename Topic>
class Writer {
 public:
  using Model = typename Topic::Model;

  // A writer in the default partition. Of a per-machine topic (Topic::kPerMachine) only an open
  // plant carries it: ncqual's own writers of those are MachineWriters.
  explicit Writer(Participant& participant, const char* profile = Topic::kWriterProfile)
      : participant_(participant) {
    create(participant.publisher(), profile);
  }
  // The writer of one machine's samples, in its partition (machine_partition).
  Writer(Participant& participant, const InPartitionOf& where,
         const char* profile = Topic::kWriterProfile)
      : participant_(participant) {
    static_assert(Topic::kPerMachine, "only a per-machine topic has machine partitions");
    create(participant.publisher_in(machine_partition(where.machine_id)), profile);
  }
  ~Writer() { publisher_->delete_datawriter(writer_); }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // Writes one sample. False when the sample could not be queued within the profile's
  // max_blocking_time (history full of unacknowledged samples): the caller decides to retry.
  bool write(const Model& value) {
    auto wire = to_wire_as<typename Topic::Wire>(value);
    return writer_->write(&wire);
  }
  bool write_wire(const typename Topic::Wire& wire) {
    return writer_->write(const_cast<typename Topic::Wire*>(&wire));
  }

  // Blocks until every matched reader acknowledged everything written, or the timeout.
  bool wait_for_acknowledgments(std::chrono::milliseconds timeout) {
    return writer_->wait_for_acknowledgments(to_dds_duration(timeout)) ==
           eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
  }

  int matched_readers() const {
    eprosima::fastdds::dds::PublicationMatchedStatus status;
    writer_->get_publication_matched_status(status);
    return status.current_count;
  }

  // Waits (on the writer's status condition, not by polling) until at least `count` readers are
  // matched, or the timeout. Returns whether they are.
  bool wait_for_readers(int count, std::chrono::milliseconds timeout) {
    return wait_until_matched(
        writer_->get_statuscondition(), eprosima::fastdds::dds::StatusMask::publication_matched(),
        [this] { return matched_readers(); }, count, timeout);
  }

  eprosima::fastdds::dds::DataWriter* get() const { return writer_; }

 private:
  void create(eprosima::fastdds::dds::Publisher* publisher, const char* profile) {
    publisher_ = publisher;
    auto* topic = participant_.topic(
        Topic::kName, eprosima::fastdds::dds::TypeSupport(new typename Topic::PubSub()));
    eprosima::fastdds::dds::DataWriterQos qos;
    if (publisher->get_datawriter_qos_from_profile(profile, qos) ==
        eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      writer_ = publisher->create_datawriter(topic, without_writer_filters(qos));
      // Refused with its profile loaded (e.g. by the permissions of a secured plant): says so.
      if (!writer_) participant_.refused_unless_unprofiled(profile, Topic::kName, true);
    } else {
      // Without our profiles: refused, unless the plant allows reliable defaults (experiments).
      participant_.require_default_qos_allowed(profile, Topic::kName);
      writer_ = publisher->create_datawriter(topic, default_qos());
    }
    if (!writer_) throw DdsError(std::string("could not create a writer on ") + Topic::kName);
  }
  // Content filters are evaluated by the readers only. Fast DDS 2.9's writer-side filtering
  // races: a writer evaluating a matched reader's filter (DDSFilterExpression::evaluate) while a
  // filtered reader of a short-lived `ncqual` command comes or goes crashed the solver and the
  // historian in DynamicData::clear_all_values (one run in about sixty `ncqual check`s).
  static eprosima::fastdds::dds::DataWriterQos without_writer_filters(
      eprosima::fastdds::dds::DataWriterQos qos) {
    qos.writer_resource_limits().reader_filters_allocation =
        eprosima::fastrtps::ResourceLimitedContainerConfig::fixed_size_configuration(0);
    return qos;
  }
  static eprosima::fastdds::dds::DataWriterQos default_qos() {
    eprosima::fastdds::dds::DataWriterQos qos = eprosima::fastdds::dds::DATAWRITER_QOS_DEFAULT;
    qos.reliability().kind = eprosima::fastdds::dds::RELIABLE_RELIABILITY_QOS;
    return without_writer_filters(qos);
  }
  Participant& participant_;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
};

// A received sample in domain-model form. `error` names what was malformed, if anything.
template <typename Model>
struct Received {
  Model value;
  std::string error;
  std::string content_hash;  // sha256_hex of its CDR serialization (serialized.hpp)
  std::string writer;        // the GUID of the DataWriter that wrote it
  bool local = false;        // written by this process's own participant
  // Of a per-machine topic read in one machine's partition (InPartitionOf): the sample names
  // another machine, so its writer, bound to that partition, wrote on another machine's behalf.
  // `error` says so. Refused whole: not even an answer on the named machine's behalf.
  bool foreign = false;
  // Of a per-machine topic read with InPartitionOf: the partition it was read in (its
  // machine's, or "" for the default partition); nothing for other readers.
  std::optional<std::string> partition;
};

// "in partition 'ncqual/machine/pm1'", "in the default partition", or "" (not known).
template <typename Model>
std::string where_received(const Received<Model>& in) {
  if (!in.partition) return "";
  return in.partition->empty() ? "in the default partition"
                               : "in partition '" + *in.partition + "'";
}

template <typename Topic>
class Reader {
 public:
  using Model = typename Topic::Model;
  using TopicType = Topic;

  // With `machine_id`, only samples of that machine are delivered (content-filtered topic,
  // evaluated by this reader: see Writer::without_writer_filters); of a per-machine topic, read in
  // that machine's partition only. Without, a per-machine topic is read in every partition.
  explicit Reader(Participant& participant, std::optional<std::string> machine_id = std::nullopt,
                  const char* profile = Topic::kReaderProfile)
      : participant_(participant) {
    auto* topic = participant.topic(
        Topic::kName, eprosima::fastdds::dds::TypeSupport(new typename Topic::PubSub()));
    eprosima::fastdds::dds::TopicDescription* description = topic;
    if (machine_id) description = participant.machine_filter(topic, *machine_id);
    auto* subscriber = participant.subscriber();
    if constexpr (Topic::kPerMachine) {
      // "" too: "*" does not match a writer without partitions (an open plant's other writers).
      subscriber = machine_id ? participant.subscriber_in({machine_partition(*machine_id)})
                              : participant.subscriber_in({"", "*"});
    }
    create(subscriber, description, profile);
  }
  Reader(Participant& participant, const InPartitionOf& where,
         const char* profile = Topic::kReaderProfile)
      : participant_(participant),
        bound_machine_(where.machine_id),
        partition_(where.machine_id.empty() ? "" : machine_partition(where.machine_id)) {
    static_assert(Topic::kPerMachine, "only a per-machine topic has machine partitions");
    auto* topic = participant.topic(
        Topic::kName, eprosima::fastdds::dds::TypeSupport(new typename Topic::PubSub()));
    create(where.machine_id.empty()
               ? participant.subscriber()
               : participant.subscriber_in({machine_partition(where.machine_id)}),
           topic, profile);
  }
  ~Reader() { subscriber_->delete_datareader(reader_); }
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  // Takes every sample available now.
  std::vector<Received<Model>> take() {
    std::vector<Received<Model>> out;
    typename Topic::Wire wire;
    eprosima::fastdds::dds::SampleInfo info;
    while (reader_->take_next_sample(&wire, &info) ==
           eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;  // dispose / unregister notifications
      Received<Model> r;
      r.value = from_wire(wire, r.error);
      r.content_hash = sha256_hex(serialize<Topic>(wire));
      const auto& writer_guid = info.sample_identity.writer_guid();
      std::ostringstream guid;
      guid << writer_guid;
      r.writer = guid.str();
      r.local = writer_guid.guidPrefix == participant_.get()->guid().guidPrefix;
      r.partition = partition_;
      if (partition_ && partition_->empty() && participant_.secured()) {
        r.foreign = true;
        r.error = "written in the default partition by writer " + r.writer +
                  ": on a secured plant a machine's samples travel only in its partition '" +
                  machine_partition(r.value.machine_id) + "'" +
                  (r.error.empty() ? "" : "; " + r.error);
      } else if (!bound_machine_.empty() && r.value.machine_id != bound_machine_) {
        r.foreign = true;
        r.error = "written in machine '" + bound_machine_ + "''s partition '" +
                  machine_partition(bound_machine_) + "' but names machine '" + r.value.machine_id +
                  "': a writer there writes only its machine's samples" +
                  (r.error.empty() ? "" : "; " + r.error);
      }
      out.push_back(std::move(r));
    }
    return out;
  }

  int matched_writers() const {
    eprosima::fastdds::dds::SubscriptionMatchedStatus status;
    reader_->get_subscription_matched_status(status);
    return status.current_count;
  }

  // Waits (on the reader's status condition, not by polling) until at least `count` writers are
  // matched, or the timeout. Returns whether they are.
  bool wait_for_writers(int count, std::chrono::milliseconds timeout) {
    return wait_until_matched(
        reader_->get_statuscondition(), eprosima::fastdds::dds::StatusMask::subscription_matched(),
        [this] { return matched_writers(); }, count, timeout);
  }

  eprosima::fastdds::dds::StatusCondition& condition() { return reader_->get_statuscondition(); }
  eprosima::fastdds::dds::DataReader* get() const { return reader_; }

 private:
  void create(eprosima::fastdds::dds::Subscriber* subscriber,
              eprosima::fastdds::dds::TopicDescription* description, const char* profile) {
    subscriber_ = subscriber;
    reader_ = subscriber_->create_datareader_with_profile(description, profile);
    if (!reader_) {
      participant_.refused_unless_unprofiled(profile, Topic::kName, false);
      participant_.require_default_qos_allowed(profile, Topic::kName);
      eprosima::fastdds::dds::DataReaderQos qos = eprosima::fastdds::dds::DATAREADER_QOS_DEFAULT;
      qos.reliability().kind = eprosima::fastdds::dds::RELIABLE_RELIABILITY_QOS;
      reader_ = subscriber_->create_datareader(description, qos);
    }
    if (!reader_) throw DdsError(std::string("could not create a reader on ") + Topic::kName);
    reader_->get_statuscondition().set_enabled_statuses(
        eprosima::fastdds::dds::StatusMask::data_available());
  }

  Participant& participant_;
  std::string bound_machine_;  // InPartitionOf: the machine whose partition this reader reads
  std::optional<std::string> partition_;  // InPartitionOf: the partition read ("" the default)
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
};

// The writers of a per-machine topic, one per machine in its partition, each created the first
// time its machine is written (or up front, for the machines named). Writes go to the sample's
// machine's writer.
template <typename Topic>
class MachineWriters {
 public:
  using Model = typename Topic::Model;
  static_assert(Topic::kPerMachine, "only a per-machine topic has machine partitions");

  explicit MachineWriters(Participant& participant, const std::vector<std::string>& machines = {})
      : participant_(participant) {
    for (const auto& m : machines) of(m);
  }

  Writer<Topic>& of(const std::string& machine_id) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto& w = writers_[machine_id];
    if (!w) w = std::make_unique<Writer<Topic>>(participant_, InPartitionOf{machine_id});
    return *w;
  }
  bool write(const Model& value) { return of(value.machine_id).write(value); }
  bool write_wire(const typename Topic::Wire& wire) {
    return of(wire.machine_id()).write_wire(wire);
  }
  // The readers matched, summed over the machines' writers.
  int matched_readers() const {
    std::lock_guard<std::mutex> lock(mutex_);
    int n = 0;
    for (const auto& [machine, w] : writers_) n += w->matched_readers();
    return n;
  }

 private:
  Participant& participant_;
  mutable std::mutex mutex_;
  std::map<std::string, std::unique_ptr<Writer<Topic>>> writers_;
};

// The readers of a per-machine topic for a service that takes every machine's samples (the
// historian, the solver): one in each machine's partition, so that a sample naming another
// machine than its partition's is known as foreign (Received::foreign; on a secured plant only
// that machine's identities may write there), and one in the default partition for an open
// plant's writers without partitions (another vendor's program; Received::partition says which
// partition a sample came in). On a secured plant the default partition's samples are all
// refused, naming their writer: there a sample could name any machine, and only the writer's
// permissions would keep it out (Fast DDS 2.9.1 once let an acquisition write there:
// docs/deploy.md, "Threat model"). The reader stays, so that DDS Security checks (and logs)
// such a writer. A machine not named here is not heard.
template <typename Topic>
class MachineReaders {
 public:
  using TopicType = Topic;
  static_assert(Topic::kPerMachine, "only a per-machine topic has machine partitions");

  MachineReaders(Participant& participant, const std::vector<std::string>& machines) {
    readers_.push_back(std::make_unique<Reader<Topic>>(participant, InPartitionOf{}));
    for (const auto& m : machines) {
      readers_.push_back(std::make_unique<Reader<Topic>>(participant, InPartitionOf{m}));
    }
  }
  const std::vector<std::unique_ptr<Reader<Topic>>>& readers() const { return readers_; }
  // The writers matched, summed over the readers.
  int matched_writers() const {
    int n = 0;
    for (const auto& r : readers_) n += r->matched_writers();
    return n;
  }

 private:
  std::vector<std::unique_ptr<Reader<Topic>>> readers_;
};

}  // namespace ncqual::dds
