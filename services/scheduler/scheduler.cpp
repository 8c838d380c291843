#include "scheduler.hpp"

#include <spdlog/spdlog.h>

#include <chrono>

namespace ncqual::scheduler {

Scheduler::Scheduler(const PlantConfig& plant, const Clock& clock, Outputs outputs)
    : plant_(plant), clock_(clock), out_(std::move(outputs)) {
  for (const auto& m : plant_.machines) machines_[m.machine_id];
}

std::string Scheduler::next_request_id(const std::string& machine_id, CheckKind kind) {
  // Unique across scheduler restarts: the clock's nanoseconds plus a per-process sequence.
  return "sched-" + machine_id + "-" + std::string(to_string(kind)) + "-" +
         std::to_string(clock_.now_ns()) + "-" + std::to_string(++sequence_);
}

void Scheduler::start_cycle(const std::vector<CheckKind>& kinds) {
  for (auto& [id, run] : machines_) {
    run.queue.assign(kinds.begin(), kinds.end());
    if (run.queue.empty()) continue;
    const CheckKind first = run.queue.front();
    run.queue.pop_front();
    issue(id, first, next_request_id(id, first), "scheduler");
  }
}

int Scheduler::fixture_configuration_for(std::int64_t time_ns) {
  constexpr std::int64_t kWeekNs = std::chrono::nanoseconds(std::chrono::hours(24 * 7)).count();
  const std::int64_t week = time_ns >= 0 ? time_ns / kWeekNs : (time_ns + 1) / kWeekNs - 1;
  return static_cast<int>(((week % 10) + 10) % 10);
}

std::string Scheduler::command(const CheckCommand& cmd) {
  auto it = machines_.find(cmd.machine_id);
  if (it == machines_.end()) {
    return "CheckCommand.machine_id '" + cmd.machine_id + "' is not configured in plant '" +
           plant_.plant + "'";
  }
  if (cmd.request_id.empty()) return "CheckCommand.request_id is empty";
  if (it->second.pending.count(cmd.request_id)) return "";  // a resent order: already issued
  issue(cmd.machine_id, cmd.kind, cmd.request_id,
        cmd.requested_by.empty() ? "operator" : cmd.requested_by, cmd.parameters);
  return "";
}

void Scheduler::issue(const std::string& machine_id, CheckKind kind, const std::string& request_id,
                      const std::string& requested_by, std::vector<NamedValue> parameters,
                      std::string verifies_correction_of) {
  auto& run = machines_[machine_id];
  const std::int64_t now = clock_.now_ns();
  if (kind == CheckKind::FixturePreCalibration &&
      !find_value(parameters, "fixture_configuration")) {
    parameters.push_back(
        {"fixture_configuration", static_cast<double>(fixture_configuration_for(now)), ""});
  }
  CheckRequest req{machine_id, request_id, kind, requested_by, now, 1, std::move(parameters),
                   std::move(verifies_correction_of)};
  run.pending[request_id] = req;
  spdlog::info("{}: requesting {} ({})", machine_id, to_string(kind), request_id);
  out_.request(req);
  publish(machine_id, request_id, MachineState::Checking, kind, std::nullopt,
          std::string(to_string(kind)) + " requested by " + requested_by);
}

void Scheduler::result(const CheckResult& res) {
  auto it = machines_.find(res.machine_id);
  if (it == machines_.end()) return;
  auto& run = it->second;
  auto p = run.pending.find(res.request_id);
  if (p == run.pending.end()) return;  // not ours, or already handled
  const CheckRequest issued = p->second;
  run.pending.erase(p);
  if (res.verdict == Verdict::Pass) {
    issue_next(res.machine_id, res);
    return;
  }
  // The fixture loop: a pre-calibration out of tolerance issues zero offsets (the solver
  // publishes them as a Compensation for the fixture's control unit); a post-calibration over
  // several configurations then decides whether software correction was enough.
  if (res.kind == CheckKind::FixturePreCalibration && res.verdict == Verdict::Fail &&
      res.correction) {
    const CheckKind post = CheckKind::FixturePostCalibration;
    spdlog::info("{}: {} issued zero offsets for {}; verifying them", res.machine_id,
                 res.request_id, res.correction->target);
    // The post-calibration probes the rows of the pre-calibration's configuration.
    issue(res.machine_id, post, next_request_id(res.machine_id, post), "scheduler",
          issued.parameters, res.request_id);
    return;
  }
  // A failed or invalid check stops the checks after it and holds the machine.
  run.queue.clear();
  std::string detail = std::string(to_string(res.kind)) + " " + std::string(to_string(res.verdict));
  if (!res.likely_causes.empty()) detail += "; first likely cause: " + res.likely_causes.front();
  if (!res.reason.empty()) detail += "; " + res.reason;
  publish(res.machine_id, res.request_id, MachineState::NeedsIntervention, res.kind, res.verdict,
          detail);
}

void Scheduler::issue_next(const std::string& machine_id, const CheckResult& passed) {
  auto& run = machines_[machine_id];
  if (!run.queue.empty()) {
    const CheckKind next = run.queue.front();
    run.queue.pop_front();
    issue(machine_id, next, next_request_id(machine_id, next), "scheduler");
    return;
  }
  publish(machine_id, passed.request_id, MachineState::Qualified, passed.kind, passed.verdict,
          std::string(to_string(passed.kind)) + " passed");
}

void Scheduler::publish(const std::string& machine_id, const std::string& request_id,
                        MachineState state, std::optional<CheckKind> kind,
                        std::optional<Verdict> verdict, std::string detail) {
  machines_[machine_id].state = state;
  out_.status(MachineStatus{machine_id, request_id, state, kind, verdict, std::move(detail),
                            clock_.now_ns()});
}

MachineState Scheduler::state(const std::string& machine_id) const {
  auto it = machines_.find(machine_id);
  return it == machines_.end() ? MachineState::Unknown : it->second.state;
}

}  // namespace ncqual::scheduler
