// SPDX-License-Identifier: Apache-2.0
#include "ncqual/dds/raw.hpp"

#include "ncqual/dds/endpoint.hpp"
#include "ncqual/dds/topics.hpp"

#include <fastdds/dds/core/status/PublicationMatchedStatus.hpp>
#include <fastdds/dds/core/status/BaseStatus.hpp>
#include <fastdds/dds/core/status/SubscriptionMatchedStatus.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <sstream>

namespace ncqual::dds {

namespace {

using eprosima::fastrtps::types::ReturnCode_t;

std::int64_t to_ns(const eprosima::fastrtps::rtps::Time_t& t) {
  return static_cast<std::int64_t>(t.seconds()) * 1000000000LL +
         static_cast<std::int64_t>(t.nanosec());
}

template <typename Topic>
TopicInfo info_of() {
  TopicInfo t;
  t.name = Topic::kName;
  typename Topic::PubSub type;
  t.type_name = type.getName();
  t.contract = Topic::kContract;
  t.writer_profile = Topic::kWriterProfile;
  t.reader_profile = Topic::kReaderProfile;
  t.per_machine = Topic::kPerMachine;
  t.keyed = type.m_isGetKeyDefined;
  t.make_type = [] { return new typename Topic::PubSub(); };
  t.machine_of = [](const std::vector<std::uint8_t>& bytes, std::string& machine_id,
                    std::string& error) {
    typename Topic::Wire wire;
    if (!deserialize<Topic>(bytes, wire)) {
      error = std::to_string(bytes.size()) + " bytes that are not a serialized " +
              std::string(typename Topic::PubSub().getName());
      return false;
    }
    machine_id = wire.machine_id();
    return true;
  };
  return t;
}

// `Older`'s layout of `Current`'s topic, read and written again as `Current`.
template <typename Older, typename Current>
OlderLayout older_layout() {
  static_assert(std::string_view(Older::kName) == std::string_view(Current::kName));
  OlderLayout o;
  o.type_name = typename Older::PubSub().getName();
  o.contract = Older::kContract;
  o.upgrade = [](const std::vector<std::uint8_t>& bytes, std::vector<std::uint8_t>& current,
                 std::string& error) {
    typename Older::Wire wire;
    if (!deserialize<Older>(bytes, wire)) {
      error = std::to_string(bytes.size()) + " bytes that are not a serialized " +
              std::string(typename Older::PubSub().getName());
      return false;
    }
    std::string malformed;
    const typename Current::Model model = from_wire(wire, malformed);
    if (!malformed.empty()) {
      error = "not written again in wire contract " + std::to_string(Current::kContract) + ": " +
              malformed;
      return false;
    }
    current = serialize<Current>(to_wire(model));
    return true;
  };
  return o;
}

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

}  // namespace

const std::vector<TopicInfo>& ncqual_topics() {
  static const std::vector<TopicInfo> topics = [] {
    std::vector<TopicInfo> t{
        info_of<CheckRequestTopic>(), info_of<MeasurementSetTopic>(),
        info_of<CheckResultTopic>(),  info_of<MachineStatusTopic>(),
        info_of<CompensationTopic>(), info_of<CheckCommandTopic>(),
        info_of<InterventionTopic>(), info_of<AcknowledgementTopic>(),
        info_of<AlarmTopic>(),        info_of<HeartbeatTopic>(),
        info_of<TrendWarningTopic>(),
    };
    t[1].older.push_back(older_layout<MeasurementSetContract1Topic, MeasurementSetTopic>());
    t[2].older.push_back(older_layout<CheckResultContract1Topic, CheckResultTopic>());
    return t;
  }();
  return topics;
}

std::optional<int> contract_of_type(std::string_view type_name) {
  constexpr std::string_view kModule = "ncqual::msg::";
  if (type_name.substr(0, kModule.size()) != kModule) return std::nullopt;
  const std::string_view rest = type_name.substr(kModule.size());
  if (rest.size() > 1 && rest[0] == 'v' && std::isdigit(static_cast<unsigned char>(rest[1]))) {
    const auto end = rest.find("::");
    if (end == std::string_view::npos) return std::nullopt;
    int n = 0;
    for (std::size_t i = 1; i < end; ++i) {
      if (!std::isdigit(static_cast<unsigned char>(rest[i]))) return std::nullopt;
      n = n * 10 + (rest[i] - '0');
    }
    return n;
  }
  return 1;
}

const TopicInfo* find_topic(std::string_view name) {
  const std::string wanted = lower(name);
  for (const auto& t : ncqual_topics()) {
    const std::string full = lower(t.name);
    if (wanted == full || "ncqual/" + wanted == full) return &t;
  }
  return nullptr;
}

// ---- RawType ---------------------------------------------------------------------------------

RawType::RawType(const TopicInfo& topic) : real_(topic.make_type()) {
  setName(real_->getName());
  m_typeSize = real_->m_typeSize;
  m_isGetKeyDefined = real_->m_isGetKeyDefined;
}

RawType::~RawType() = default;

bool RawType::serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) {
  const auto& bytes = static_cast<RawSample*>(data)->bytes;
  if (bytes.size() < 4 || bytes.size() > payload->max_size) return false;
  std::memcpy(payload->data, bytes.data(), bytes.size());
  payload->length = static_cast<std::uint32_t>(bytes.size());
  // The encapsulation identifier's low byte: 1 for little-endian CDR (CDR_LE), 0 big-endian.
  payload->encapsulation = (bytes[1] & 1) != 0 ? CDR_LE : CDR_BE;
  return true;
}

bool RawType::deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) {
  auto& bytes = static_cast<RawSample*>(data)->bytes;
  bytes.assign(payload->data, payload->data + payload->length);
  return true;
}

std::function<std::uint32_t()> RawType::getSerializedSizeProvider(void* data) {
  const auto size = static_cast<std::uint32_t>(static_cast<RawSample*>(data)->bytes.size());
  return [size] { return size; };
}

void* RawType::createData() { return new RawSample(); }

void RawType::deleteData(void* data) { delete static_cast<RawSample*>(data); }

bool RawType::getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle,
                     bool force_md5) {
  // The key is the real type's: the sample is read into it and asked.
  const auto& bytes = static_cast<RawSample*>(data)->bytes;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(bytes.size()));
  std::copy(bytes.begin(), bytes.end(), payload.data);
  payload.length = static_cast<std::uint32_t>(bytes.size());
  void* sample = real_->createData();
  bool ok = false;
  try {
    ok = real_->deserialize(&payload, sample) && real_->getKey(sample, handle, force_md5);
  } catch (const std::exception&) {
    ok = false;  // Fast CDR throws on a truncated buffer
  }
  real_->deleteData(sample);
  return ok;
}

// ---- RawReader -------------------------------------------------------------------------------

RawReader::RawReader(Participant& participant, const TopicInfo& topic)
    : participant_(participant), topic_(topic) {
  using namespace eprosima::fastdds::dds;
  auto* t = participant.topic(topic.name, TypeSupport(new RawType(topic)));
  // A per-machine topic in every machine's partition and the default one ("*" does not match a
  // writer without partitions).
  subscriber_ = topic.per_machine ? participant.subscriber_in({"", "*"}) : participant.subscriber();
  reader_ = subscriber_->create_datareader_with_profile(t, topic.reader_profile);
  if (!reader_) {
    participant_.refused_unless_unprofiled(topic.reader_profile, topic.name, false);
    participant_.require_default_qos_allowed(topic.reader_profile, topic.name);
    DataReaderQos qos = DATAREADER_QOS_DEFAULT;
    qos.reliability().kind = RELIABLE_RELIABILITY_QOS;
    reader_ = subscriber_->create_datareader(t, qos);
  }
  if (!reader_) throw DdsError("could not create a reader on " + topic.name);
  reader_->get_statuscondition().set_enabled_statuses(StatusMask::data_available());
}

RawReader::~RawReader() { subscriber_->delete_datareader(reader_); }

std::vector<RawReceived> RawReader::take() {
  std::vector<RawReceived> out;
  RawSample sample;
  eprosima::fastdds::dds::SampleInfo info;
  while (reader_->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK) {
    if (!info.valid_data) continue;  // dispose / unregister notifications
    RawReceived r;
    r.bytes = std::move(sample.bytes);
    r.source_time_ns = to_ns(info.source_timestamp);
    r.reception_time_ns = to_ns(info.reception_timestamp);
    const auto& guid = info.sample_identity.writer_guid();
    std::ostringstream text;
    text << guid;
    r.writer = text.str();
    r.local = guid.guidPrefix == participant_.get()->guid().guidPrefix;
    out.push_back(std::move(r));
    sample.bytes.clear();
  }
  return out;
}

int RawReader::matched_writers() const {
  eprosima::fastdds::dds::SubscriptionMatchedStatus status;
  reader_->get_subscription_matched_status(status);
  return status.current_count;
}

std::int64_t RawReader::lost() const {
  eprosima::fastdds::dds::SampleLostStatus status;
  reader_->get_sample_lost_status(status);
  return status.total_count;
}

std::map<std::string, std::string> RawReader::qos_description() const {
  using namespace eprosima::fastdds::dds;
  const DataReaderQos qos = reader_->get_qos();
  std::map<std::string, std::string> m;
  m["reliability"] =
      qos.reliability().kind == RELIABLE_RELIABILITY_QOS ? "RELIABLE" : "BEST_EFFORT";
  switch (qos.durability().kind) {
    case VOLATILE_DURABILITY_QOS: m["durability"] = "VOLATILE"; break;
    case TRANSIENT_LOCAL_DURABILITY_QOS: m["durability"] = "TRANSIENT_LOCAL"; break;
    case TRANSIENT_DURABILITY_QOS: m["durability"] = "TRANSIENT"; break;
    case PERSISTENT_DURABILITY_QOS: m["durability"] = "PERSISTENT"; break;
  }
  m["history"] = qos.history().kind == KEEP_ALL_HISTORY_QOS
                     ? "KEEP_ALL"
                     : "KEEP_LAST " + std::to_string(qos.history().depth);
  return m;
}

// ---- RawWriter -------------------------------------------------------------------------------

RawWriter::RawWriter(Participant& participant, const TopicInfo& topic, RawWriterOptions options)
    : participant_(participant), topic_(topic), options_(options) {
  participant.topic(topic.name, eprosima::fastdds::dds::TypeSupport(new RawType(topic)));
}

RawWriter::~RawWriter() {
  for (auto& [machine, w] : writers_) w.first->delete_datawriter(w.second);
}

eprosima::fastdds::dds::DataWriter* RawWriter::writer_of(const std::string& machine_id) {
  using namespace eprosima::fastdds::dds;
  const std::string key = topic_.per_machine ? machine_id : "";
  std::lock_guard<std::mutex> lock(mutex_);
  if (auto it = writers_.find(key); it != writers_.end()) return it->second.second;
  auto* t = participant_.topic(topic_.name, TypeSupport(new RawType(topic_)));
  Publisher* publisher =
      key.empty() ? participant_.publisher() : participant_.publisher_in(machine_partition(key));
  DataWriterQos qos;
  DataWriter* writer = nullptr;
  if (publisher->get_datawriter_qos_from_profile(topic_.writer_profile, qos) ==
      ReturnCode_t::RETCODE_OK) {
    // Content filters are evaluated by the readers only (endpoint.hpp, without_writer_filters):
    // a raw writer could not evaluate them anyway.
    qos.writer_resource_limits().reader_filters_allocation =
        eprosima::fastrtps::ResourceLimitedContainerConfig::fixed_size_configuration(0);
    if (options_.heartbeat_period) {
      qos.reliable_writer_qos().times.heartbeatPeriod = to_dds_duration(*options_.heartbeat_period);
    }
    writer = publisher->create_datawriter(t, qos);
    if (!writer) participant_.refused_unless_unprofiled(topic_.writer_profile, topic_.name, true);
  } else {
    participant_.require_default_qos_allowed(topic_.writer_profile, topic_.name);
    qos = DATAWRITER_QOS_DEFAULT;
    qos.reliability().kind = RELIABLE_RELIABILITY_QOS;
    qos.writer_resource_limits().reader_filters_allocation =
        eprosima::fastrtps::ResourceLimitedContainerConfig::fixed_size_configuration(0);
    writer = publisher->create_datawriter(t, qos);
  }
  if (!writer) throw DdsError("could not create a writer on " + topic_.name);
  writers_[key] = {publisher, writer};
  return writer;
}

bool RawWriter::write(const std::vector<std::uint8_t>& bytes, const std::string& machine_id,
                      std::int64_t source_time_ns) {
  auto* writer = writer_of(machine_id);
  RawSample sample{bytes};
  if (source_time_ns <= 0) return writer->write(&sample);
  const eprosima::fastrtps::Time_t stamp(static_cast<std::int32_t>(source_time_ns / 1000000000LL),
                                         static_cast<std::uint32_t>(source_time_ns % 1000000000LL));
  return writer->write_w_timestamp(&sample, eprosima::fastrtps::rtps::c_InstanceHandle_Unknown,
                                   stamp) == ReturnCode_t::RETCODE_OK;
}

bool RawWriter::wait_for_acknowledgments(const std::string& machine_id,
                                         std::chrono::milliseconds timeout) {
  return writer_of(machine_id)->wait_for_acknowledgments(to_dds_duration(timeout)) ==
         ReturnCode_t::RETCODE_OK;
}

int RawWriter::history_depth() {
  using namespace eprosima::fastdds::dds;
  std::lock_guard<std::mutex> lock(mutex_);
  if (depth_ < 0) {
    DataWriterQos qos = DATAWRITER_QOS_DEFAULT;  // without the profile: KEEP_LAST 1, as created
    participant_.publisher()->get_datawriter_qos_from_profile(topic_.writer_profile, qos);
    depth_ = qos.history().kind == KEEP_LAST_HISTORY_QOS ? qos.history().depth : 0;
  }
  return depth_;
}

bool RawWriter::wait_for_acknowledgments(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::vector<eprosima::fastdds::dds::DataWriter*> writers;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto& [machine, w] : writers_) writers.push_back(w.second);
  }
  for (auto* w : writers) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    if (w->wait_for_acknowledgments(to_dds_duration(left)) != ReturnCode_t::RETCODE_OK) {
      return false;
    }
  }
  return true;
}

int RawWriter::matched_readers(const std::string& machine_id) {
  eprosima::fastdds::dds::PublicationMatchedStatus status;
  writer_of(machine_id)->get_publication_matched_status(status);
  return status.current_count;
}

bool RawWriter::wait_for_readers(const std::string& machine_id, int count,
                                 std::chrono::milliseconds timeout) {
  auto* writer = writer_of(machine_id);
  return wait_until_matched(
      writer->get_statuscondition(), eprosima::fastdds::dds::StatusMask::publication_matched(),
      [writer] {
        eprosima::fastdds::dds::PublicationMatchedStatus status;
        writer->get_publication_matched_status(status);
        return status.current_count;
      },
      count, timeout);
}

}  // namespace ncqual::dds
