// SPDX-License-Identifier: Apache-2.0
// ncqual's topics as bytes: readers and writers that carry each sample's serialized payload
// exactly as it is on the wire (encapsulation header included), for the recorder and the replay.
// They match ncqual's own endpoints by type name and QoS profile, as another vendor's would, and
// never look inside a sample but for its key (machine_id, through the topic's own generated type)
// and, for a per-machine topic written again, its machine's partition.
//
// A participant registers one type per type name: a process uses either the raw or the typed
// endpoints of a topic, never both (the recorder's heartbeat goes out raw for that reason).
#pragma once

#include "ncqual/dds/participant.hpp"

#include <fastdds/dds/core/condition/StatusCondition.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/topic/TopicDataType.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::dds {

// A layout an older wire contract gave a topic's type (docs/architecture.md, "Changing the wire
// contract"): what a recording of an older version holds and an older service writes.
struct OlderLayout {
  std::string type_name;  // "ncqual::msg::CheckResult"
  int contract = 1;
  // The same sample in the topic's current layout (fields it did not have: their defaults, an
  // origin Unknown); false, with `error` saying why, when `bytes` are not a sample of this layout
  // or hold a value out of range.
  std::function<bool(const std::vector<std::uint8_t>& bytes, std::vector<std::uint8_t>& current,
                     std::string& error)>
      upgrade;
};

// One of ncqual's topics (topics.hpp) at run time.
struct TopicInfo {
  std::string name;       // "ncqual/CheckResult"
  std::string type_name;  // "ncqual::msg::v2::CheckResult"
  int contract = 1;       // the wire contract of type_name (that of the type's last change)
  std::vector<OlderLayout> older;  // the layouts older contracts gave it, newest first
  const char* writer_profile = nullptr;
  const char* reader_profile = nullptr;
  bool per_machine = false;  // travels in its machine's partition (machine_partition)
  bool keyed = false;        // the type has a key (machine_id)
  std::function<eprosima::fastdds::dds::TopicDataType*()> make_type;  // the generated PubSubType
  // The machine_id of serialized bytes of this topic; false (with `error` saying why) when the
  // bytes are not a sample of this topic's type.
  std::function<bool(const std::vector<std::uint8_t>&, std::string& machine_id, std::string& error)>
      machine_of;
};

// Every ncqual topic, in the order of topics.hpp.
const std::vector<TopicInfo>& ncqual_topics();
// The topic named `name` ("ncqual/CheckResult" or "CheckResult", any case); nullptr when none.
const TopicInfo* find_topic(std::string_view name);
// The wire contract a type name of an ncqual topic belongs to: N for "ncqual::msg::vN::Type", 1
// for "ncqual::msg::Type"; nothing for a type that is not ncqual's.
std::optional<int> contract_of_type(std::string_view type_name);

// A sample as bytes.
struct RawSample {
  std::vector<std::uint8_t> bytes;  // serialized payload, encapsulation header included
};

// A topic's type as bytes: registered under the generated type's name, with its key; deserializing
// copies the payload, serializing copies it back.
class RawType : public eprosima::fastdds::dds::TopicDataType {
 public:
  explicit RawType(const TopicInfo& topic);
  ~RawType() override;
  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override;
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override;
  std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override;
  void* createData() override;
  void deleteData(void* data) override;
  bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle,
              bool force_md5) override;

 private:
  std::unique_ptr<eprosima::fastdds::dds::TopicDataType> real_;
};

// A received sample as bytes, with its times.
struct RawReceived {
  std::vector<std::uint8_t> bytes;
  std::int64_t source_time_ns = 0;     // the writer's source timestamp
  std::int64_t reception_time_ns = 0;  // when this participant received it
  std::string writer;                  // the GUID of the DataWriter that wrote it
  bool local = false;                  // written by this process's own participant
};

// A reader of one topic with its profile's QoS (reader_profile), in every partition (a
// per-machine topic) or the default one. Samples are taken as bytes.
class RawReader {
 public:
  RawReader(Participant& participant, const TopicInfo& topic);
  ~RawReader();
  RawReader(const RawReader&) = delete;
  RawReader& operator=(const RawReader&) = delete;

  std::vector<RawReceived> take();
  const TopicInfo& topic() const { return topic_; }
  int matched_writers() const;
  eprosima::fastdds::dds::StatusCondition& condition() { return reader_->get_statuscondition(); }
  eprosima::fastdds::dds::DataReader* get() const { return reader_; }
  // The reader's QoS as channel metadata: reliability, durability, history, partitions.
  std::map<std::string, std::string> qos_description() const;
  // Samples the reader knows it lost (a best-effort topic's, a KEEP_LAST history overrun);
  // growing only.
  std::int64_t lost() const;

 private:
  Participant& participant_;
  TopicInfo topic_;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
};

// The writers of one topic with its profile's QoS (writer_profile): one in the default
// partition, and for a per-machine topic one in each machine's partition, created the first time
// that machine's sample is written, as ncqual's own MachineWriters.
struct RawWriterOptions {
  // The reliable writers' heartbeat period instead of the profile's (500 ms). A writer's
  // readers acknowledge what they received when its heartbeat asks them to, so a writer that
  // waits for acknowledgements between bursts (a replay as fast as the readers take it) waits
  // about a heartbeat period each time. Not a matched QoS: readers see no difference.
  std::optional<std::chrono::milliseconds> heartbeat_period;
};

class RawWriter {
 public:
  RawWriter(Participant& participant, const TopicInfo& topic, RawWriterOptions options = {});
  ~RawWriter();
  RawWriter(const RawWriter&) = delete;
  RawWriter& operator=(const RawWriter&) = delete;

  // Writes `bytes` with `source_time_ns` as its source timestamp (0: now). `machine_id` picks
  // the partition of a per-machine topic (ignored otherwise). False when the sample could not be
  // queued within the profile's max_blocking_time.
  bool write(const std::vector<std::uint8_t>& bytes, const std::string& machine_id,
             std::int64_t source_time_ns = 0);
  // Waits until every matched reader of every writer acknowledged everything, or the timeout.
  bool wait_for_acknowledgments(std::chrono::milliseconds timeout);
  // The same for the writer of `machine_id`'s partition only ("" the default one).
  bool wait_for_acknowledgments(const std::string& machine_id, std::chrono::milliseconds timeout);
  // The writers' history depth (KEEP_LAST; per instance): how many samples of one machine may be
  // written before the oldest not yet acknowledged is overwritten. 0 for KEEP_ALL.
  int history_depth();
  // The readers matched by the writer of `machine_id` (created if needed; "" the default one).
  int matched_readers(const std::string& machine_id = "");
  // Waits until the writer of `machine_id` has `count` readers, or the timeout.
  bool wait_for_readers(const std::string& machine_id, int count,
                        std::chrono::milliseconds timeout);
  const TopicInfo& topic() const { return topic_; }

 private:
  eprosima::fastdds::dds::DataWriter* writer_of(const std::string& machine_id);

  Participant& participant_;
  TopicInfo topic_;
  RawWriterOptions options_;
  std::mutex mutex_;
  int depth_ = -1;  // history_depth(), once known
  // "" is the default partition's writer.
  std::map<std::string,
           std::pair<eprosima::fastdds::dds::Publisher*, eprosima::fastdds::dds::DataWriter*>>
      writers_;
};

}  // namespace ncqual::dds
