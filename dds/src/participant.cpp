// SPDX-License-Identifier: Apache-2.0
#include "ncqual/dds/participant.hpp"

#include "ncqual/dds/identity.hpp"
#include "ncqual/dds/raw.hpp"
#include "ncqual/dds/topics.hpp"

#include "ncqualTypeObject.h"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/dds/log/Log.hpp>
#include <fastdds/rtps/attributes/ServerAttributes.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include <ifaddrs.h>
#include <netinet/in.h>
#include <arpa/inet.h>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>
#include <cctype>

namespace ncqual::dds {
using namespace eprosima::fastdds::dds;

int resolve_domain_id(int flag_value, int config_value) {
  if (flag_value >= 0) return flag_value;
  if (const char* env = std::getenv("NCQUAL_DOMAIN"); env && *env) {
    char* end = nullptr;
    const long v = std::strtol(env, &end, 10);
    if (*end != '\0' || v < 0 || v > 232) {
      throw DdsError(std::string("NCQUAL_DOMAIN = '") + env +
                     "': expected an integer from 0 to 232");
    }
    return static_cast<int>(v);
  }
  return config_value;
}

namespace {

// Profiles are loaded once per process; loading the same file twice is harmless but noisy.
void load_profiles_once(const std::string& file) {
  static std::mutex mutex;
  static std::string loaded;
  std::lock_guard<std::mutex> lock(mutex);
  if (file.empty() || file == loaded) return;
  if (!std::filesystem::exists(file)) throw DdsError("QoS profiles file '" + file + "' not found");
  if (DomainParticipantFactory::get_instance()->load_XML_profiles_file(file) !=
      eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
    throw DdsError("QoS profiles file '" + file + "' could not be loaded (invalid XML profile?)");
  }
  loaded = file;
}

// "<plant file>: network.<list>[i]", as config problems name a value.
std::string where(const NetworkConfig& network, const char* list, std::size_t i) {
  return (network.source_path.empty() ? "" : network.source_path + ": ") + "network." + list + "[" +
         std::to_string(i) + "]";
}

// The IPv4 locator of `address` (a host name is looked up now), on `default_port` when it
// names none.
eprosima::fastrtps::rtps::Locator_t locator_of(const NetworkAddress& address, int default_port,
                                               const std::string& what) {
  using eprosima::fastrtps::rtps::IPLocator;
  eprosima::fastrtps::rtps::Locator_t locator;
  std::string ip = address.host;
  if (!IPLocator::isIPv4(ip)) {
    const auto found = IPLocator::resolveNameDNS(ip).first;
    if (found.empty()) {
      throw DdsError(what + " = '" + to_string(address) +
                     "': neither an IPv4 address nor a host name this host can resolve");
    }
    ip = *found.begin();
  }
  IPLocator::setIPv4(locator, ip);
  IPLocator::setPhysicalPort(
      locator, static_cast<std::uint16_t>(address.port != 0 ? address.port : default_port));
  return locator;
}

// The plant's addresses over the profile's: the discovery servers (a client of them, each with
// the GUID prefix `fastdds discovery -i <its index>` takes) or the initial peers.
void apply_network(const NetworkConfig& network, DomainParticipantQos& qos) {
  using eprosima::fastrtps::rtps::DiscoveryProtocol_t;
  auto& builtin = qos.wire_protocol().builtin;
  if (!network.servers.empty()) {
    auto& discovery = builtin.discovery_config;
    if (discovery.discoveryProtocol == DiscoveryProtocol_t::SIMPLE) {
      discovery.discoveryProtocol = DiscoveryProtocol_t::CLIENT;
    }
    discovery.m_DiscoveryServers.clear();
    for (std::size_t id = 0; id < network.servers.size(); ++id) {
      eprosima::fastdds::rtps::RemoteServerAttributes server;
      eprosima::fastdds::rtps::get_server_client_default_guidPrefix(static_cast<int>(id),
                                                                    server.guidPrefix);
      server.metatrafficUnicastLocatorList.push_back(
          locator_of(network.servers[id], eprosima::fastdds::rtps::DEFAULT_ROS2_SERVER_PORT,
                     where(network, "servers", id)));
      discovery.m_DiscoveryServers.push_back(server);
    }
  }
  if (!network.peers.empty()) {
    builtin.initialPeersList.clear();
    // Port 0: Fast DDS tries the domain's well-known ports of the first participants of a host
    // (the transport's maxInitialPeersRange of them).
    for (std::size_t i = 0; i < network.peers.size(); ++i) {
      builtin.initialPeersList.push_back(
          locator_of(network.peers[i], 0, where(network, "peers", i)));
    }
  }
}

// This host's IPv4 addresses (every interface that is up, loopback too).
std::set<std::string> host_ipv4_addresses() {
  std::set<std::string> out;
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) return out;
  for (const ifaddrs* a = list; a != nullptr; a = a->ifa_next) {
    if (a->ifa_addr == nullptr || a->ifa_addr->sa_family != AF_INET) continue;
    char text[INET_ADDRSTRLEN] = {};
    const auto* in = reinterpret_cast<const sockaddr_in*>(a->ifa_addr);
    if (inet_ntop(AF_INET, &in->sin_addr, text, sizeof text) != nullptr) out.insert(text);
  }
  freeifaddrs(list);
  return out;
}

}  // namespace

std::vector<std::string> listening_addresses(const NetworkConfig& network,
                                             const std::set<std::string>& host_addresses) {
  using eprosima::fastrtps::rtps::IPLocator;
  std::vector<std::string> out;
  const auto consider = [&](const std::vector<NetworkAddress>& list, const char* what) {
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string ip =
          IPLocator::toIPv4string(locator_of(list[i], 0, where(network, what, i)));
      if (host_addresses.count(ip) && std::find(out.begin(), out.end(), ip) == out.end()) {
        out.push_back(ip);
      }
    }
  };
  consider(network.peers, "peers");
  consider(network.servers, "servers");
  return out;
}

namespace {

// The plant's addresses of this host, as the UDP transports' interface whitelist: unicast
// sockets are bound to them instead of every interface (0.0.0.0), and nothing goes out through
// another interface. Multicast sockets (discovery: multicast) still bind 0.0.0.0; a host none of
// whose addresses the plant names listens everywhere, and on a peers plant says so.
void restrict_interfaces(const NetworkConfig& network, DomainParticipantQos& qos) {
  using eprosima::fastdds::rtps::UDPv4TransportDescriptor;
  if (network.peers.empty() && network.servers.empty()) return;
  const std::vector<std::string> listen = listening_addresses(network, host_ipv4_addresses());
  if (listen.empty()) {
    if (!network.peers.empty()) {
      static std::once_flag said;
      std::call_once(said, [&] {
        spdlog::warn(
            "{}network.peers names none of this host's addresses: listening on every "
            "interface (list this host's address on the plant network there)",
            network.source_path.empty() ? "" : network.source_path + ": ");
      });
    }
    return;
  }
  for (auto& transport : qos.transport().user_transports) {
    const auto* udp = dynamic_cast<const UDPv4TransportDescriptor*>(transport.get());
    if (udp == nullptr) continue;
    auto restricted = std::make_shared<UDPv4TransportDescriptor>(*udp);
    restricted->interfaceWhiteList = listen;
    transport = restricted;
  }
  static std::once_flag said;
  std::call_once(said, [&] {
    std::string joined;
    for (const auto& ip : listen) joined += (joined.empty() ? "" : ", ") + ip;
    spdlog::info("listening on {} only: this host's addresses among the plant's", joined);
  });
}

// "file://" + the absolute path of `dir`/`relative`, which must exist.
std::string file_uri(const std::string& dir, const std::string& relative, const std::string& what) {
  const std::filesystem::path path = std::filesystem::path(dir) / relative;
  if (!std::filesystem::exists(path)) {
    throw DdsError("security: " + what + " " + path.string() + " not found");
  }
  return "file://" + std::filesystem::absolute(path).lexically_normal().string();
}

// The builtin plugins of DDS Security (authentication PKI-DH, access control Access-Permissions,
// cryptography AES-GCM-GMAC) with the plant's CA, revocation list and governance, and the
// identity's certificate, key and signed permissions.
void apply_security(const SecurityConfig& security, DomainParticipantQos& qos) {
  if (security.dir.empty()) return;
  if (!std::filesystem::is_directory(security.dir)) {
    throw DdsError("security: " + security.dir +
                   " is not a directory of ncqual-pki's (deploy/security/ncqual-pki init)");
  }
  const std::string identity = "identities/" + security.identity;
  if (security.identity.empty() ||
      !std::filesystem::is_directory(std::filesystem::path(security.dir) / identity)) {
    std::string known;
    for (const auto& name : identities_in(security.dir))
      known += (known.empty() ? "" : ", ") + name;
    throw DdsError("security: no identity '" + security.identity + "' in " + security.dir +
                   "/identities (there: " + (known.empty() ? "none" : known) +
                   "); pass --identity NAME, or make it with ncqual-pki add");
  }
  const std::string auth = "dds.sec.auth.builtin.PKI-DH.";
  const std::string access = "dds.sec.access.builtin.Access-Permissions.";
  auto& p = qos.properties().properties();
  p.emplace_back("dds.sec.auth.plugin", "builtin.PKI-DH");
  p.emplace_back(auth + "identity_ca", file_uri(security.dir, "ca/ca.pem", "the plant CA"));
  p.emplace_back(auth + "identity_certificate",
                 file_uri(security.dir, identity + "/cert.pem", "the identity's certificate"));
  p.emplace_back(auth + "private_key",
                 file_uri(security.dir, identity + "/key.pem", "the identity's private key"));
  p.emplace_back(auth + "identity_crl",
                 file_uri(security.dir, "ca/crl.pem", "the plant's revocation list"));
  p.emplace_back("dds.sec.access.plugin", "builtin.Access-Permissions");
  p.emplace_back(access + "permissions_ca", file_uri(security.dir, "ca/ca.pem", "the plant CA"));
  p.emplace_back(access + "governance",
                 file_uri(security.dir, "governance.p7s", "the signed governance"));
  p.emplace_back(access + "permissions", file_uri(security.dir, identity + "/permissions.p7s",
                                                  "the identity's signed permissions"));
  p.emplace_back("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
}

}  // namespace

std::string machine_partition(const std::string& machine_id) {
  return "ncqual/machine/" + machine_id;
}

std::vector<std::string> identities_in(const std::string& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::filesystem::path(dir) / "identities", ec)) {
    if (entry.is_directory()) names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

ParticipantOptions participant_options(const PlantConfig& plant, int domain_id, std::string name) {
  ParticipantOptions o;
  o.domain_id = domain_id;
  o.qos_profiles_file = plant.qos_profiles_file;
  o.name = std::move(name);
  o.allow_default_qos = plant.allow_default_qos;
  o.network = plant.network;
  o.security = plant.security;
  return o;
}

void apply_security_flags(ParticipantOptions& options, const std::string& secure,
                          const std::string& identity, const std::string& default_identity) {
  if (!secure.empty()) options.security.dir = secure;
  options.security.identity = identity.empty() ? default_identity : identity;
}

std::string participant_profile(const NetworkConfig& network) {
  if (!network.participant_profile.empty()) return network.participant_profile;
  switch (network.discovery) {
    case Discovery::Server: return profiles::kDiscoveryClient;
    case Discovery::Peers: return profiles::kPeers;
    case Discovery::Multicast: break;
  }
  return profiles::kParticipant;
}

// Fast DDS 2.9.1 (Debian 12's) matches a newly discovered peer's handshake reader through one
// scratch proxy per participant, unguarded (SecurityManager::match_builtin_endpoints): when two
// receive threads discover participants at once, one peer's handshake reader is never matched
// and that pair never authenticates, for as long as both run. With multicast discovery the
// announcements arrive on two threads (multicast and unicast); with peers or a discovery server
// on one. Fixed upstream in Fast DDS 2.10 (eProsima/Fast-DDS#3362). SecurePlant under load: 4
// of 16 runs failed so with multicast, none of 15 with peers (docs/deploy.md, "Security").
namespace {
void warn_if_secured_over_multicast(const ParticipantOptions& options) {
  if (options.security.dir.empty() || options.network.discovery != Discovery::Multicast ||
      !options.network.participant_profile.empty()) {
    return;
  }
  static std::once_flag said;
  std::call_once(said, [] {
    spdlog::warn(
        "secured with discovery: multicast: Fast DDS 2.9 can leave a pair of secured "
        "participants unauthenticated for good when they start together (a race fixed in Fast "
        "DDS 2.10); use network: {discovery: peers, peers: [...]} in the plant config "
        "(docs/deploy.md, \"Security\")");
  });
}
}  // namespace

// A remote endpoint that DDS Security refuses (its permissions do not allow its topic or
// partition, e.g. a writer moved into another machine's partition) is logged by Fast DDS with its
// GUID only. Said again in the service's own log, naming the identity whose subject bits the GUID
// carries (identity.hpp), so that an attempt is on record with who made it.
namespace {
class RefusedEndpointLog : public eprosima::fastdds::dds::LogConsumer {
 public:
  explicit RefusedEndpointLog(std::string dir) : dir_(std::move(dir)) {}
  void Consume(const eprosima::fastdds::dds::Log::Entry& entry) override {
    if (entry.kind != eprosima::fastdds::dds::Log::Kind::Error) return;
    if (entry.message.find("Error checking create remote") == std::string::npos) return;
    if (!loaded_) {  // on the logging thread, the first time one is refused
      loaded_ = true;
      identities_ = plant_identities_to_name(dir_, "refused endpoints");
    }
    if (const auto said = describe_refused_endpoint(entry.message, identities_)) {
      spdlog::error("{}", *said);
    }
  }

 private:
  std::string dir_;
  bool loaded_ = false;
  std::vector<PlantIdentity> identities_;
};

void log_refused_endpoints(const SecurityConfig& security) {
  if (security.dir.empty()) return;
  static std::once_flag registered;
  std::call_once(registered, [&] {
    eprosima::fastdds::dds::Log::RegisterConsumer(
        std::make_unique<RefusedEndpointLog>(security.dir));
  });
}
}  // namespace

// ---- Wire contracts of the others --------------------------------------------------------------

namespace {

// The participants of this process: their endpoints are never another version's.
std::mutex local_mutex;
std::set<eprosima::fastrtps::rtps::GuidPrefix_t> local_participants;

bool is_local(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix) {
  std::lock_guard<std::mutex> lock(local_mutex);
  return local_participants.count(prefix) != 0;
}

// Every ncqual participant announces its wire contract in its USER_DATA:
// "ncqual;contract=2" or, reading older layouts beside, "ncqual;contract=2;reads=1".
constexpr std::string_view kUserDataTag = "ncqual;contract=";

std::vector<eprosima::fastrtps::rtps::octet> contract_user_data(const std::vector<int>& reads) {
  std::string text = std::string(kUserDataTag) + std::to_string(kWireContract);
  for (std::size_t i = 0; i < reads.size(); ++i) {
    text += (i == 0 ? ";reads=" : ",") + std::to_string(reads[i]);
  }
  return {text.begin(), text.end()};
}

struct Announced {
  std::optional<int> contract;  // nothing: not said (ncqual before contract 2, another system)
  std::set<int> reads;
};

Announced announced(const std::vector<eprosima::fastrtps::rtps::octet>& data) {
  const std::string text(data.begin(), data.end());
  Announced a;
  if (text.rfind(kUserDataTag, 0) != 0) return a;
  std::size_t at = kUserDataTag.size();
  const auto number = [&text, &at]() -> std::optional<int> {
    int n = 0;
    const std::size_t start = at;
    while (at < text.size() && std::isdigit(static_cast<unsigned char>(text[at])) &&
           at - start < 6) {
      n = n * 10 + (text[at++] - '0');
    }
    return at > start ? std::optional<int>(n) : std::nullopt;
  };
  a.contract = number();
  if (text.compare(at, 7, ";reads=") == 0) {
    at += 7;
    while (const auto n = number()) {
      a.reads.insert(*n);
      if (at >= text.size() || text[at] != ',') break;
      ++at;
    }
  }
  return a;
}

std::string prefix_text(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix) {
  std::ostringstream out;
  out << prefix;
  return out.str();
}

}  // namespace

// Listens to discovery: the others' announced contracts and the types of their endpoints on
// ncqual's topics. Called on Fast DDS's threads.
class Participant::ContractWatch : public DomainParticipantListener {
 public:
  // `log`: log each mismatch once (a process's second participant hears the same as its first
  // and keeps quiet).
  ContractWatch(std::string own_name, bool log) : own_name_(std::move(own_name)), log_(log) {}

  std::vector<std::string> mismatches() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::string> out;
    for (const auto& [key, text] : mismatches_) out.push_back(text);
    return out;
  }

  void on_participant_discovery(
      DomainParticipant* /*participant*/,
      eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override {
    using Status = eprosima::fastrtps::rtps::ParticipantDiscoveryInfo;
    const auto& data = info.info;
    const auto prefix = data.m_guid.guidPrefix;
    if (is_local(prefix)) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (info.status == Status::REMOVED_PARTICIPANT || info.status == Status::DROPPED_PARTICIPANT) {
      remotes_.erase(prefix);
      const std::string start = prefix_text(prefix);
      for (auto it = mismatches_.begin(); it != mismatches_.end();) {
        it = it->first.rfind(start, 0) == 0 ? mismatches_.erase(it) : std::next(it);
      }
      return;
    }
    Remote& r = remotes_[prefix];
    r.name = data.m_participantName.to_string();
    r.announced = announced(data.m_userData.data_vec());
    if (r.announced.contract && *r.announced.contract != kWireContract) {
      note(prefix_text(prefix), "participant '" + r.name + "' (GUID prefix " + prefix_text(prefix) +
                                    ") speaks wire contract " +
                                    std::to_string(*r.announced.contract) + "; " + own());
    }
  }
  void on_subscriber_discovery(DomainParticipant* /*participant*/,
                               eprosima::fastrtps::rtps::ReaderDiscoveryInfo&& info) override {
    using Status = eprosima::fastrtps::rtps::ReaderDiscoveryInfo;
    endpoint(info.info.guid(), info.info.topicName().to_string(), info.info.typeName().to_string(),
             false, info.status == Status::REMOVED_READER);
  }
  void on_publisher_discovery(DomainParticipant* /*participant*/,
                              eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override {
    using Status = eprosima::fastrtps::rtps::WriterDiscoveryInfo;
    endpoint(info.info.guid(), info.info.topicName().to_string(), info.info.typeName().to_string(),
             true, info.status == Status::REMOVED_WRITER);
  }

 private:
  struct Remote {
    std::string name;
    Announced announced;
  };

  // "this process (ncqual-solver) speaks wire contract 2 (ncqual::msg::v2::CheckResult). ..."
  std::string own(const std::string& type = "") const {
    return "this process (" + own_name_ + ") speaks wire contract " +
           std::to_string(kWireContract) + (type.empty() ? "" : " (" + type + ")") +
           ". Services of two contracts do not read each other's samples of the types that "
           "changed: upgrade the plant's services together (docs/deploy.md, \"Upgrading\")";
  }

  void note(const std::string& key, const std::string& text) {
    if (mismatches_.emplace(key, text).second && log_) spdlog::error("wire contract: {}", text);
  }

  void endpoint(const eprosima::fastrtps::rtps::GUID_t& guid, const std::string& topic,
                const std::string& type, bool writer, bool removed) {
    if (is_local(guid.guidPrefix)) return;
    const TopicInfo* ours = nullptr;
    for (const auto& t : ncqual_topics()) {
      if (t.name == topic) ours = &t;
    }
    if (ours == nullptr || ours->type_name == type) return;
    std::ostringstream id;
    id << guid;
    const std::string key = prefix_text(guid.guidPrefix) + " " + id.str();
    std::lock_guard<std::mutex> lock(mutex_);
    if (removed) {
      mismatches_.erase(key);
      return;
    }
    const auto their = contract_of_type(type);
    const auto remote = remotes_.find(guid.guidPrefix);
    // A reader of an older layout in a participant that reads it beside the current one (the
    // historian's second participant) is not another version.
    if (!writer && their && remote != remotes_.end() &&
        remote->second.announced.reads.count(*their))
      return;
    const std::string who = remote != remotes_.end() && !remote->second.name.empty()
                                ? "participant '" + remote->second.name + "'"
                                : std::string("a participant");
    std::string text = who + " (GUID prefix " + prefix_text(guid.guidPrefix) + ") " +
                       (writer ? "writes " : "reads ") + topic + " as " + type;
    if (their) {
      text += " (wire contract " + std::to_string(*their) + "); " + own(ours->type_name);
    } else {
      text += ", which is not ncqual's type of that topic (" + ours->type_name +
              "): DDS never matches them";
    }
    note(key, text);
  }

  std::string own_name_;
  bool log_ = true;
  mutable std::mutex mutex_;
  std::map<eprosima::fastrtps::rtps::GuidPrefix_t, Remote> remotes_;
  std::map<std::string, std::string> mismatches_;  // by "<prefix> <endpoint GUID>" or "<prefix>"
};

std::vector<std::string> Participant::contract_mismatches() const { return watch_->mismatches(); }

// What to do when the profiles are not there, said once for all of the process's refusals.
constexpr const char* kProfilesRemedy =
    "set qos_profiles in the plant config (deploy/qos/ncqual-qos.xml) or "
    "FASTRTPS_DEFAULT_PROFILES_FILE; allow_default_qos: true runs on Fast DDS's defaults, which "
    "are not durable, for an experiment";

Participant::Participant(const ParticipantOptions& options)
    : domain_id_(options.domain_id),
      allow_default_qos_(options.allow_default_qos),
      security_(options.security) {
  load_profiles_once(options.qos_profiles_file);
  // TypeObjects of our types, for the content filters (they are not announced: topic()).
  static std::once_flag types_registered;
  std::call_once(types_registered, [] { registerncqualTypes(); });
  auto* factory = DomainParticipantFactory::get_instance();
  DomainParticipantQos qos;
  const std::string profile = participant_profile(options.network);
  if (factory->get_participant_qos_from_profile(profile, qos) !=
      eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
    // Without our profiles file the Fast DDS defaults apply: reliable readers and writers, but
    // VOLATILE, so a restarted historian would miss what was published while it was down.
    if (!allow_default_qos_) {
      throw DdsError("QoS profiles not loaded (participant profile '" + profile +
                     "' not found): " + kProfilesRemedy);
    }
    spdlog::warn(
        "QoS profiles not loaded: allow_default_qos is true, running on Fast DDS's "
        "defaults, which are not durable");
    qos = PARTICIPANT_QOS_DEFAULT;
  }
  apply_network(options.network, qos);
  restrict_interfaces(options.network, qos);
  apply_security(options.security, qos);
  warn_if_secured_over_multicast(options);
  log_refused_endpoints(options.security);
  if (!options.name.empty()) qos.name(options.name);
  qos.user_data().data_vec(contract_user_data(options.reads_older_contracts));
  watch_ = std::make_unique<ContractWatch>(options.name.empty() ? "ncqual" : options.name,
                                           options.reads_older_contracts.empty());
  // The listener hears discovery only: no status of the entities goes to it.
  participant_ =
      factory->create_participant(options.domain_id, qos, watch_.get(), StatusMask::none());
  if (participant_) {
    std::lock_guard<std::mutex> lock(local_mutex);
    local_participants.insert(participant_->guid().guidPrefix);
  }
  if (!participant_) {
    throw DdsError(
        "could not create a DDS participant on domain " + std::to_string(options.domain_id) +
        (options.security.dir.empty()
             ? std::string()
             : " secured as '" + options.security.identity +
                   "': its certificate or permissions were refused (expired, not yet valid, "
                   "revoked, or not signed by " +
                   options.security.dir + "/ca/ca.pem; Fast DDS's log above says which)"));
  }
  publisher_ = participant_->create_publisher(PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
  if (!publisher_ || !subscriber_) throw DdsError("could not create a DDS publisher/subscriber");
}

Participant::~Participant() {
  if (participant_) {
    {
      std::lock_guard<std::mutex> lock(local_mutex);
      local_participants.erase(participant_->guid().guidPrefix);
    }
    participant_->delete_contained_entities();
    DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }
}

void Participant::require_default_qos_allowed(const std::string& profile,
                                              const std::string& topic) const {
  if (!allow_default_qos_) {
    throw DdsError("QoS profile '" + profile + "' of " + topic +
                   " is not loaded: " + kProfilesRemedy);
  }
}

void Participant::refused_unless_unprofiled(const std::string& profile, const std::string& topic,
                                            bool writer) const {
  bool loaded = false;
  if (writer) {
    DataWriterQos qos;
    loaded = publisher_->get_datawriter_qos_from_profile(profile, qos) ==
             eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
  } else {
    DataReaderQos qos;
    loaded = subscriber_->get_datareader_qos_from_profile(profile, qos) ==
             eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
  }
  if (!loaded) return;
  const std::string what = std::string(writer ? "a writer of " : "a reader of ") + topic;
  if (!security_.dir.empty()) {
    throw DdsError("could not create " + what + ": the permissions of identity '" +
                   security_.identity + "' (" + security_.dir + "/identities/" +
                   security_.identity + "/permissions.xml) do not allow it to " +
                   (writer ? "publish" : "subscribe") + " " + topic);
  }
  throw DdsError("could not create " + what + " with QoS profile '" + profile +
                 "' (Fast DDS's log above says why)");
}

Publisher* Participant::publisher_in(const std::string& partition) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (auto it = partition_publishers_.find(partition); it != partition_publishers_.end()) {
    return it->second;
  }
  PublisherQos qos = PUBLISHER_QOS_DEFAULT;
  qos.partition().push_back(partition.c_str());
  Publisher* p = participant_->create_publisher(qos);
  if (!p) throw DdsError("could not create a publisher in partition '" + partition + "'");
  partition_publishers_[partition] = p;
  return p;
}

Subscriber* Participant::subscriber_in(const std::vector<std::string>& partitions) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (auto it = partition_subscribers_.find(partitions); it != partition_subscribers_.end()) {
    return it->second;
  }
  SubscriberQos qos = SUBSCRIBER_QOS_DEFAULT;
  for (const auto& p : partitions) qos.partition().push_back(p.c_str());
  Subscriber* s = participant_->create_subscriber(qos);
  if (!s) throw DdsError("could not create a subscriber in the partitions asked");
  partition_subscribers_[partitions] = s;
  return s;
}

Topic* Participant::topic(const std::string& name, const TypeSupport& type) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (auto it = topics_.find(name); it != topics_.end()) return it->second;
  // No TypeObject or TypeInformation in the endpoints' discovery data. The TypeObjects stay
  // registered in this process (the content filters use them), but announced they crash Fast DDS
  // 2.9's own discovery server (`fastdds discovery` builds a dynamic type of each and faults in
  // TypeObjectFactory::is_type_identifier_complete), and Cyclone DDS 0.10 does not read the
  // TypeInformation parameter. Endpoints match by type name, as every vendor's do.
  type->auto_fill_type_object(false);
  type->auto_fill_type_information(false);
  type.register_type(participant_);
  Topic* t = participant_->create_topic(name, type.get_type_name(), TOPIC_QOS_DEFAULT);
  if (!t) throw DdsError("could not create topic '" + name + "'");
  topics_[name] = t;
  return t;
}

ContentFilteredTopic* Participant::machine_filter(Topic* topic, const std::string& machine_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string name = topic->get_name() + "|machine_id=" + machine_id;
  if (auto it = filtered_.find(name); it != filtered_.end()) return it->second;
  ContentFilteredTopic* cft = participant_->create_contentfilteredtopic(
      name, topic, "machine_id = %0", {"'" + machine_id + "'"});
  if (!cft) throw DdsError("could not create a machine filter on '" + topic->get_name() + "'");
  filtered_[name] = cft;
  return cft;
}

}  // namespace ncqual::dds
