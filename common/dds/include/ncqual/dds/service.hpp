// What every ncqual service shares: its plant config, one participant, the receive loop,
// periodic heartbeats, and a clean stop on SIGINT/SIGTERM. Executables only parse their
// arguments, wire their readers and writers to a library, and call run().
#pragma once

#include "ncqual/clock.hpp"
#include "ncqual/config.hpp"
#include "ncqual/dds/dispatcher.hpp"
#include "ncqual/dds/topics.hpp"

#include <memory>
#include <string>

namespace ncqual::dds {

struct ServiceOptions {
  std::string service;     // "scheduler", "acquisition", "solver", "historian"
  std::string machine_id;  // for an acquisition service: its machine, or its machines joined by commas
  int domain_id = 0;
  std::string qos_profiles_file;
  std::chrono::milliseconds heartbeat_period{2000};
};

class Service {
 public:
  explicit Service(const ServiceOptions& options);
  ~Service();

  Participant& participant() { return *participant_; }
  Dispatcher& dispatcher() { return dispatcher_; }
  const Clock& clock() const { return clock_; }
  const std::string& instance() const { return instance_; }

  // Runs the receive loop until SIGINT/SIGTERM or stop(); announces itself by heartbeat.
  int run();
  void stop() { dispatcher_.stop(); }

 private:
  void beat(const std::string& state);

  ServiceOptions options_;
  std::string instance_;
  WallClock clock_;
  std::unique_ptr<Participant> participant_;
  Dispatcher dispatcher_;
  std::unique_ptr<Writer<HeartbeatTopic>> heartbeat_;
};

// The plant config a service runs with: --plant FILE, else NCQUAL_PLANT; a service cannot run
// without one, so this throws ConfigError when neither is given.
std::string plant_file_from(const std::string& flag_value);

}  // namespace ncqual::dds
