// SPDX-License-Identifier: Apache-2.0
// What every ncqual service shares: its plant config, one participant, the receive loop,
// periodic heartbeats, and a clean stop on SIGINT/SIGTERM. Executables only parse their
// arguments, wire their readers and writers to a library, and call run().
#pragma once

#include "ncqual/common/clock.hpp"
#include "ncqual/common/command_line.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/dds/dispatcher.hpp"
#include "ncqual/dds/raw.hpp"
#include "ncqual/dds/topics.hpp"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace ncqual::dds {

struct ServiceOptions {
  std::string service;  // "scheduler", "acquisition", "solver", "historian", "recorder"
  std::string
      machine_id;  // for an acquisition service: its machine, or its machines joined by commas
  ParticipantOptions participant;  // its domain, QoS profiles and network (named ncqual-<service>)
  std::chrono::milliseconds heartbeat_period{kHeartbeatPeriod};
  // The heartbeat goes out through a RawWriter (raw.hpp): for a service whose participant reads
  // every topic raw (the recorder), as a participant registers one type per type name.
  bool raw_heartbeat = false;
};

class Service {
 public:
  explicit Service(const ServiceOptions& options);
  ~Service();

  Participant& participant() { return *participant_; }
  // A second participant, made on first use, that reads the layouts older wire contracts gave
  // the types that changed (topics.hpp's *Contract1Topic): a participant has one type per topic
  // name. The historian's, so that it stores what a service of an older version sends.
  Participant& older_contracts_participant();
  Dispatcher& dispatcher() { return dispatcher_; }
  const Clock& clock() const { return clock_; }
  const std::string& instance() const { return instance_; }

  // Runs the receive loop until SIGINT/SIGTERM or stop(), announcing itself by heartbeat (one at
  // once, then one every period); then says "stopping", runs the before_stop work (an outbox's
  // drain) in the order registered and says "stopped", waiting (at most kLastWordWait) until the
  // historian acknowledged that last heartbeat: `ncqual status` then shows the service stopped,
  // not running until its heartbeat grows stale.
  int run();
  void stop() { dispatcher_.stop(); }

  // Work to do between the stop and the last heartbeat (on the dispatcher's thread).
  void before_stop(std::function<void()> work) { before_stop_.push_back(std::move(work)); }
  // Fills the heartbeat's health and outbox fields; called before every heartbeat. Beside what
  // they say, a participant of another wire contract in the domain makes the health "degraded"
  // (Participant::contract_mismatches).
  void on_heartbeat(std::function<void(Heartbeat&)> fill) { fill_.push_back(std::move(fill)); }
  // Writes a heartbeat now (a health change should not wait for the period).
  void beat(const std::string& state);
  // The heartbeat this service would write now in `state` ("running", "stopping", "stopped"):
  // for the historian, which stores its own last one itself (it no longer reads its own).
  Heartbeat heartbeat(const std::string& state) const;

  // How long run() waits at most for the acknowledgement of the last heartbeat.
  static constexpr std::chrono::milliseconds kLastWordWait{1000};

 private:
  ServiceOptions options_;
  std::string instance_;
  WallClock clock_;
  std::unique_ptr<Participant> participant_;
  std::unique_ptr<Participant> older_participant_;
  Dispatcher dispatcher_;
  std::unique_ptr<Writer<HeartbeatTopic>> heartbeat_;
  std::unique_ptr<RawWriter> raw_heartbeat_;
  std::vector<std::function<void()>> before_stop_;
  std::vector<std::function<void(Heartbeat&)>> fill_;
};

// The plant config a service runs with: --plant FILE, else NCQUAL_PLANT; a service cannot run
// without one, so this throws ConfigError when neither is given.
std::string plant_file_from(const std::string& flag_value);

// What a service's main does around its own wiring. Construct it, add the service's own options
// to app(), then return run(argc, argv, body).
class ServiceMain {
 public:
  // `service`: "scheduler", "acquisition", "solver", "historian". The app is ncqual-<service>,
  // set up as every ncqual executable's (command_line::configure), with the options every service
  // takes (command_line::add_service_options).
  ServiceMain(std::string service, const std::string& description);

  CLI::App& app() { return app_; }

  // Parses the command line (0 after --help/--version, 2 for bad usage), sets up logging as the
  // service, loads the plant (--plant or NCQUAL_PLANT) and runs `body` with it. This is the
  // services' one error boundary (docs/architecture.md, "Errors"): an exception from any of it is
  // reported on stderr as "<app>: <what>" and the process exits 2.
  int run(int argc, char** argv, const std::function<int(PlantConfig)>& body);

  // The Service of this service (serving `served`, for an acquisition) in `plant`: the domain
  // from --domain, else NCQUAL_DOMAIN, else the plant's; the plant's QoS profiles.
  ServiceOptions service_options(const PlantConfig& plant, const std::string& served = "") const;

 private:
  std::string service_;
  CLI::App app_;
  command_line::ServiceOptions options_;
};

}  // namespace ncqual::dds
