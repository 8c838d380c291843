// The scheduler's decisions, apart from DDS: which CheckRequest to issue next for each
// machine, and what a result means for the machine's status. For now: a sequence of checks per
// machine at start-up (a failure stops the checks after it), operator orders, and the fixture
// loop (a pre-calibration that fails with zero offsets is followed by a post-calibration that
// verifies them). The full calendar (shifts, periods, interventions) builds on this.
#pragma once

#include "ncqual/clock.hpp"
#include "ncqual/config.hpp"
#include "ncqual/model.hpp"

#include <deque>
#include <functional>
#include <map>
#include <string>

namespace ncqual::scheduler {

class Scheduler {
 public:
  struct Outputs {
    std::function<void(const CheckRequest&)> request;
    std::function<void(const MachineStatus&)> status;
  };

  Scheduler(const PlantConfig& plant, const Clock& clock, Outputs outputs);

  // Queues `kinds` for every configured machine, in order, and issues the first of each.
  void start_cycle(const std::vector<CheckKind>& kinds);
  // An operator's order. Returns an empty string, or why it was refused (naming the field).
  std::string command(const CheckCommand& cmd);
  // A result from the solver. Results of requests this scheduler did not issue are ignored.
  void result(const CheckResult& res);

  MachineState state(const std::string& machine_id) const;

  // Which of the ten weekly fixture configurations a pre-calibration at `time_ns` probes: the
  // week number since the Unix epoch, modulo 10. (Until the scheduler keeps durable state, the
  // rotation follows the calendar, so a restart does not repeat a configuration.)
  static int fixture_configuration_for(std::int64_t time_ns);

 private:
  struct MachineRun {
    std::deque<CheckKind> queue;        // checks still to run in this cycle
    std::map<std::string, CheckRequest> pending;  // request id -> the request issued
    MachineState state = MachineState::Unknown;
  };
  void issue(const std::string& machine_id, CheckKind kind, const std::string& request_id,
             const std::string& requested_by, std::vector<NamedValue> parameters = {},
             std::string verifies_correction_of = "");
  void issue_next(const std::string& machine_id, const CheckResult& passed);
  void publish(const std::string& machine_id, const std::string& request_id, MachineState state,
               std::optional<CheckKind> kind, std::optional<Verdict> verdict, std::string detail);
  std::string next_request_id(const std::string& machine_id, CheckKind kind);

  const PlantConfig& plant_;
  const Clock& clock_;
  Outputs out_;
  std::map<std::string, MachineRun> machines_;
  std::uint64_t sequence_ = 0;
};

}  // namespace ncqual::scheduler
