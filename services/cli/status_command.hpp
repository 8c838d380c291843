// `ncqual status` and `ncqual intervene`: the plant's machines as the qualification process sees
// them, and the record of a physical intervention that re-arms a held check.
//
//   ncqual status [--plant F] [--db F] [--machine M] [--json]
//     Per configured machine: its newest status from the historian (state, detail, time), and per
//     period of the plant calendar (scheduler.calendar, else the default process) its checks,
//     when the period last passed (the oldest of its checks' newest PASS: a period is current only
//     when all its checks are), whether it is due or overdue now, and when it falls due next.
//     "Now" is the wall clock, or with a simulated clock the time of the machine's newest status
//     (heartbeats carry wall time). Read only; the scheduler need not run.
//     --json names (stable): {"plant", "now_ns", "machines": [{"machine_id", "state", "detail",
//       "status_time_ns", "periods": [{"name", "every", "checks": [{"kind", "last_pass_ns"}],
//       "last_pass_ns", "due", "overdue", "next_due_ns"}]}]}; times are ns since the Unix epoch
//       UTC or null; the text form prints them in the plant's time zone.
//
//   ncqual intervene --machine M --check KIND --note TEXT [--operator NAME] [--plant F]
//                    [--domain N]
//     Publishes an Intervention (the scheduler re-arms the held check when KIND names it; the
//     historian stores it) and waits until both have acknowledged it. Prints its id.
//
//   ncqual trend --machine M [--kind K] [--every day|week|month] [--metrics N] [--plant F]
//                [--db F]
//     Per check kind and per calendar day, week or month (in the plant's time zone): how many
//     checks passed, failed or were invalid, and for the N metrics (default 3) that came nearest
//     their tolerance over the whole history, the value in each period nearest its tolerance.
//     A drift shows as a column creeping towards (!).
//
// Exit codes as the rest of ncqual: 0 ok, 1 error (no historian, nobody listening), 2 usage.
#pragma once

#include <string>
#include <vector>

namespace ncqual {

int run_status(const std::vector<std::string>& args);
int run_intervene(const std::vector<std::string>& args);
int run_trend(const std::vector<std::string>& args);

}  // namespace ncqual
