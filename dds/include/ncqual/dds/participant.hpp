// SPDX-License-Identifier: Apache-2.0
// One DomainParticipant per process, its publisher, subscriber and topics. QoS comes from the
// Fast DDS XML profile file (deploy/qos/ncqual-qos.xml), never from code.
#pragma once

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/ContentFilteredTopic.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include "ncqual/common/config.hpp"
#include "ncqual/common/error.hpp"

#include <string>
#include <vector>

namespace ncqual::dds {

// Thrown when a DDS entity cannot be created; the message names what and why.
class DdsError : public Error {
 public:
  using Error::Error;
};

struct ParticipantOptions {
  int domain_id = 0;
  std::string
      qos_profiles_file;  // XML profiles; empty: FASTRTPS_DEFAULT_PROFILES_FILE or built-ins
  std::string name;       // participant name seen by tools, e.g. "ncqual-solver"
  // When the profiles are not loaded: false refuses (DdsError naming the remedies), true warns
  // and runs on Fast DDS's defaults (reliable, not durable). The plant's allow_default_qos.
  bool allow_default_qos = false;
  // How the participant finds the others: the participant profile it runs with and the
  // discovery servers' or peers' addresses that replace the profile's (the plant's network:).
  NetworkConfig network;
  // DDS Security: the plant's material and the identity to run as (empty dir: not secured).
  SecurityConfig security;
  // The older wire contracts this participant reads beside the current one (the historian's
  // second participant): announced, so that the others do not take its readers of older layouts
  // for a service of an older version.
  std::vector<int> reads_older_contracts;
};

// The options of a participant of `plant` on `domain_id`, named `name` ("ncqual-cli").
ParticipantOptions participant_options(const PlantConfig& plant, int domain_id, std::string name);

// A process's --secure and --identity over the plant's: `secure`, when given, replaces the
// plant's security directory; the identity is `identity` when given, else `default_identity`.
void apply_security_flags(ParticipantOptions& options, const std::string& secure,
                          const std::string& identity, const std::string& default_identity);

// The identities of ncqual-pki's `dir` (the names of identities/*/), sorted; for messages.
std::vector<std::string> identities_in(const std::string& dir);

// The participant profile `network` runs with: its participant_profile, else its discovery's.
std::string participant_profile(const NetworkConfig& network);

// Domain id: the --domain flag when given (>= 0), else NCQUAL_DOMAIN, else the plant config's.
int resolve_domain_id(int flag_value, int config_value);

// The partition of one machine's samples on the topics bound to a machine (CheckRequest,
// MeasurementSet, Compensation): "ncqual/machine/<id>". On a secured plant an acquisition's
// permissions name its machines' partitions only (docs/deploy.md, "Roles").
std::string machine_partition(const std::string& machine_id);

// The addresses of `host_addresses` (this host's IPv4 addresses) that the plant's network names
// (peers, discovery servers; host names looked up), in the plant's order: where a participant's
// unicast UDP transports listen when not empty (Fast DDS's interface whitelist), instead of
// every interface (docs/deploy.md, "What listens where").
std::vector<std::string> listening_addresses(const NetworkConfig& network,
                                             const std::set<std::string>& host_addresses);

// Profile names in deploy/qos/ncqual-qos.xml.
namespace profiles {
inline constexpr const char* kParticipant = "ncqual_participant";  // discovery: multicast
inline constexpr const char* kDiscoveryClient = "ncqual_participant_discovery_client";
inline constexpr const char* kPeers = "ncqual_participant_peers";
inline constexpr const char* kDurableWriter = "ncqual_durable_writer";
inline constexpr const char* kDurableReader = "ncqual_durable_reader";
inline constexpr const char* kCommandWriter = "ncqual_command_writer";
inline constexpr const char* kCommandReader = "ncqual_command_reader";
inline constexpr const char* kAckWriter = "ncqual_ack_writer";
inline constexpr const char* kAckReader = "ncqual_ack_reader";
inline constexpr const char* kAlarmWriter = "ncqual_alarm_writer";
inline constexpr const char* kAlarmReader = "ncqual_alarm_reader";
inline constexpr const char* kHeartbeatWriter = "ncqual_heartbeat_writer";
inline constexpr const char* kHeartbeatReader = "ncqual_heartbeat_reader";
}  // namespace profiles

class Participant {
 public:
  explicit Participant(const ParticipantOptions& options);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  eprosima::fastdds::dds::DomainParticipant* get() const { return participant_; }
  eprosima::fastdds::dds::Publisher* publisher() const { return publisher_; }
  eprosima::fastdds::dds::Subscriber* subscriber() const { return subscriber_; }
  // The publisher whose writers are in `partition` (created on first use).
  eprosima::fastdds::dds::Publisher* publisher_in(const std::string& partition);
  // The subscriber whose readers are in `partitions` (created on first use).
  eprosima::fastdds::dds::Subscriber* subscriber_in(const std::vector<std::string>& partitions);
  int domain_id() const { return domain_id_; }
  // Runs with DDS Security (the plant's security: section).
  bool secured() const { return !security_.dir.empty(); }
  // Its security: the plant's material (dir; from the plant file or --secure) and its identity.
  const SecurityConfig& security() const { return security_; }
  // For a writer or reader whose profile is not loaded: throws the DdsError naming the remedies,
  // unless the plant allows Fast DDS's defaults (then the caller uses them).
  void require_default_qos_allowed(const std::string& profile, const std::string& topic) const;
  // For a writer (or reader) that could not be created: when its profile is loaded, the refusal
  // had another cause (a secured plant's permissions): throws the DdsError that says so.
  void refused_unless_unprofiled(const std::string& profile, const std::string& topic,
                                 bool writer) const;

  // The topic of this name, created on first use with its type registered.
  eprosima::fastdds::dds::Topic* topic(const std::string& name,
                                       const eprosima::fastdds::dds::TypeSupport& type);
  // A content-filtered view of `topic` that passes only samples of one machine.
  eprosima::fastdds::dds::ContentFilteredTopic* machine_filter(eprosima::fastdds::dds::Topic* topic,
                                                               const std::string& machine_id);

  // The participants of the domain that speak another wire contract than this process
  // (docs/architecture.md, "Changing the wire contract"), one sentence each naming both: an
  // endpoint of an ncqual topic with another type name (an older or newer layout of a changed
  // type, or another system's type), or a participant that announces another contract. Each is
  // logged as an error once when it is discovered, and is forgotten when it leaves.
  std::vector<std::string> contract_mismatches() const;

 private:
  class ContractWatch;
  std::unique_ptr<ContractWatch> watch_;  // outlives participant_ (declared before it)
  int domain_id_ = 0;
  bool allow_default_qos_ = false;
  SecurityConfig security_;
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  std::mutex mutex_;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
  std::map<std::string, eprosima::fastdds::dds::ContentFilteredTopic*> filtered_;
  std::map<std::string, eprosima::fastdds::dds::Publisher*> partition_publishers_;
  std::map<std::vector<std::string>, eprosima::fastdds::dds::Subscriber*> partition_subscribers_;
};

}  // namespace ncqual::dds
