// SPDX-License-Identifier: Apache-2.0
// What the scheduler acknowledges for each sample of its machines, once it has decided
// (docs/architecture.md, "Acknowledged storage"), with no DDS:
//
//   unreadable, or refused by the scheduler      -> REFUSED with the reason (the sender drops it)
//   decided and the decision saved               -> ACCEPTED (an intervention: once relayed)
//   the decision not saved (the state file failed) -> nothing: the sender keeps it, sends it again
//
// A conflict alarm is not acknowledged (alarms are not kept by their sender); it only holds a
// machine. Each function logs what it refused or changed nothing for.
#pragma once

#include "ncqual/scheduler/scheduler.hpp"

#include "ncqual/common/model.hpp"

#include <optional>
#include <string>

namespace ncqual::scheduler {

struct Answer {
  std::optional<AckOutcome> ack;  // nothing: not acknowledged (sent again)
  std::string detail;             // the refusal, or why an accepted sample changed nothing
};

Answer answer_result(Scheduler& scheduler, const CheckResult& result, const std::string& error);
Answer answer_command(Scheduler& scheduler, const CheckCommand& command, const std::string& error);
// ACCEPTED means: relay the intervention to the historian (its own outbox entry), then
// acknowledge it; not acknowledged when the relay could not be kept.
Answer answer_intervention(Scheduler& scheduler, const Intervention& intervention,
                           const std::string& error);
// The historian's conflict alarm of a check of one of its machines; false when it was none, or
// unreadable (logged), and the scheduler was not told.
bool answer_alarm(Scheduler& scheduler, const Alarm& alarm, const std::string& error);

}  // namespace ncqual::scheduler
