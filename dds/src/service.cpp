// SPDX-License-Identifier: Apache-2.0
#include "ncqual/dds/service.hpp"

#include "ncqual/common/log.hpp"
#include "ncqual/common/service_manager.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <utility>

#include <spdlog/spdlog.h>

#include <unistd.h>

namespace ncqual::dds {

std::string plant_file_from(const std::string& flag_value) {
  std::string path = plant_config_path(flag_value);
  if (path.empty()) throw ConfigError("no plant config: pass --plant FILE or set NCQUAL_PLANT");
  return path;
}

ServiceMain::ServiceMain(std::string service, const std::string& description)
    : service_(std::move(service)), app_(description, "ncqual-" + service_) {
  command_line::configure(app_);
  command_line::add_service_options(app_, options_);
}

int ServiceMain::run(int argc, char** argv, const std::function<int(PlantConfig)>& body) {
  if (const auto code = command_line::parse(app_, argc, argv)) return *code;
  try {
    init_logging(service_, options_.log_level);
    return body(load_plant_config(plant_file_from(options_.plant)));
  } catch (const std::exception& e) {
    std::cerr << app_.get_name() << ": " << e.what() << "\n";
    return command_line::kUsageExit;
  }
}

ServiceOptions ServiceMain::service_options(const PlantConfig& plant,
                                            const std::string& served) const {
  ServiceOptions options;
  options.service = service_;
  options.machine_id = served;
  options.participant = participant_options(
      plant, resolve_domain_id(options_.domain, plant.domain_id), "ncqual-" + service_);
  // The identity: --identity, else the service's own name; an acquisition's is its machine's
  // (acquisition-pm1), or its group's name given with --identity.
  std::string own = service_;
  if (service_ == "acquisition") {
    own = served.find(',') == std::string::npos ? "acquisition-" + served : "";
  }
  apply_security_flags(options.participant, options_.secure, options_.identity, own);
  if (options.participant.security.identity.empty() && !options.participant.security.dir.empty()) {
    throw ConfigError({"an acquisition of several machines (" + served +
                       ") on a secured plant needs --identity NAME: an identity made with "
                       "ncqual-pki add --role acquisition --machines " +
                       served});
  }
  return options;
}

Service::Service(const ServiceOptions& options) : options_(options) {
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  instance_ = std::string(host) + ":" + std::to_string(getpid());
  // Signals first, before Fast DDS starts its threads, so that they all inherit the mask.
  handle_termination_signals([this](int sig) {
    spdlog::info("signal {} received, stopping", sig);
    dispatcher_.stop();
  });
  participant_ = std::make_unique<Participant>(options.participant);
  if (options.raw_heartbeat) {
    raw_heartbeat_ = std::make_unique<RawWriter>(*participant_, *find_topic(HeartbeatTopic::kName));
  } else {
    heartbeat_ = std::make_unique<Writer<HeartbeatTopic>>(*participant_);
  }
  dispatcher_.every(options.heartbeat_period, [this] { beat("running"); });
  // Under a unit with WatchdogSec=: pinged from the receive loop, so a loop that hangs is
  // restarted by systemd; twice per period, as sd_watchdog_enabled(3) advises.
  if (const auto period = service_manager::watchdog_ping_period()) {
    dispatcher_.every(std::chrono::duration_cast<std::chrono::milliseconds>(*period),
                      [] { service_manager::notify("WATCHDOG=1"); });
  }
}

Service::~Service() = default;

Heartbeat Service::heartbeat(const std::string& state) const {
  Heartbeat beat;
  beat.service = options_.service;
  beat.instance = instance_;
  beat.machine_id = options_.machine_id;
  beat.state = state;
  beat.time_ns = clock_.now_ns();
  for (const auto& fill : fill_) fill(beat);
  const std::vector<std::string> mismatches = participant_->contract_mismatches();
  if (!mismatches.empty()) {
    std::string text = "wire contract: " + mismatches.front();
    if (mismatches.size() > 1) {
      text += " (and " + std::to_string(mismatches.size() - 1) + " more endpoints; see the log)";
    }
    if (beat.health.empty() || beat.health == "ok") {
      beat.health = "degraded";
      beat.health_detail = text;
    } else {
      beat.health_detail += "; " + text;
    }
  }
  return beat;
}

Participant& Service::older_contracts_participant() {
  if (!older_participant_) {
    ParticipantOptions options = options_.participant;
    options.name += " (older wire contracts)";
    options.reads_older_contracts = {1};
    older_participant_ = std::make_unique<Participant>(options);
  }
  return *older_participant_;
}

void Service::beat(const std::string& state) {
  const Heartbeat beat = heartbeat(state);
  if (raw_heartbeat_) {
    raw_heartbeat_->write(serialize<HeartbeatTopic>(to_wire(beat)), beat.machine_id);
  } else {
    heartbeat_->write(beat);
  }
}

int Service::run() {
  const SecurityConfig& security = options_.participant.security;
  spdlog::info("{} {} running on domain {}, discovery {} (participant profile {}), {}",
               options_.service, instance_, options_.participant.domain_id,
               to_string(options_.participant.network.discovery),
               participant_profile(options_.participant.network),
               security.dir.empty() ? std::string("not secured")
                                    : "secured as '" + security.identity + "' of " + security.dir);
  // Ready: the participant, every reader and writer, the database or state file are made
  // (Type=notify units start what is ordered after this one only now).
  service_manager::notify("READY=1\nSTATUS=running on domain " +
                          std::to_string(options_.participant.domain_id));
  beat("running");  // at once: a service that runs for less than a period is seen too
  dispatcher_.run();
  service_manager::notify("STOPPING=1\nSTATUS=stopping");
  beat("stopping");
  for (const auto& work : before_stop_) work();
  beat("stopped");
  const bool heard = raw_heartbeat_ ? raw_heartbeat_->wait_for_acknowledgments(kLastWordWait)
                                    : heartbeat_->wait_for_acknowledgments(kLastWordWait);
  spdlog::info("{} stopped{}", options_.service,
               heard ? "" : " (its last heartbeat was not acknowledged within 1 s)");
  return 0;
}

}  // namespace ncqual::dds
