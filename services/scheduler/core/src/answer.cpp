// SPDX-License-Identifier: Apache-2.0
// What the scheduler acknowledges for each sample it received (answer.hpp).
#include "ncqual/scheduler/answer.hpp"

#include <spdlog/spdlog.h>

namespace ncqual::scheduler {

Answer answer_result(Scheduler& scheduler, const CheckResult& result, const std::string& error) {
  if (!error.empty()) {
    spdlog::error("result {} of '{}' refused: {}", result.request_id, result.machine_id, error);
    return {AckOutcome::Refused, error};
  }
  scheduler.result(result);
  if (!scheduler.saved()) return {};
  return {AckOutcome::Accepted, ""};
}

Answer answer_command(Scheduler& scheduler, const CheckCommand& command, const std::string& error) {
  const std::string refused = error.empty() ? scheduler.command(command) : error;
  if (!refused.empty()) {
    spdlog::error("check command {} refused: {}", command.request_id, refused);
    return {AckOutcome::Refused, refused};
  }
  if (!scheduler.saved()) return {};
  return {AckOutcome::Accepted, ""};
}

Answer answer_intervention(Scheduler& scheduler, const Intervention& intervention,
                           const std::string& error) {
  if (!error.empty()) {
    spdlog::warn("intervention {} refused: {}", intervention.intervention_id, error);
    return {AckOutcome::Refused, error};
  }
  const std::string unchanged = scheduler.intervention(intervention);
  if (!unchanged.empty())
    spdlog::warn("intervention {}: {}", intervention.intervention_id, unchanged);
  if (!scheduler.saved()) return {};
  return {AckOutcome::Accepted, unchanged};
}

bool answer_alarm(Scheduler& scheduler, const Alarm& alarm, const std::string& error) {
  const auto conflict = check_conflict_of(alarm);
  if (!conflict) return false;
  if (!error.empty()) {
    spdlog::error("alarm {} not read: {}", alarm.alarm_id, error);
    return false;
  }
  const std::string unchanged = scheduler.conflict(alarm.machine_id, *conflict, alarm.text);
  if (!unchanged.empty()) spdlog::warn("conflict {}: {}", alarm.alarm_id, unchanged);
  return true;
}

}  // namespace ncqual::scheduler
