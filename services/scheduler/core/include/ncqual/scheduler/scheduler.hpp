// SPDX-License-Identifier: Apache-2.0
// The scheduler's decisions, apart from DDS: the qualification flowchart per machine.
//
// With a calendar (plant config scheduler.calendar), per machine:
//   - at the start of each shift: the checks of every period that is due (calendar.hpp), period
//     by period in the configured order (default: monthly, weekly, daily), each period's checks in
//     order; then, when calendar.parts.cycle_min > 0, per part its checks (the set points), the
//     next part cycle_min after the part's checks passed, until the end of the shift;
//   - gating: a FAIL or INVALID holds the machine (NEEDS_INTERVENTION, with the failed check, its
//     first likely cause and what to do next) and stops the checks after it; an Intervention for
//     the held check re-arms it: it runs again at once and the sequence resumes from there;
//   - the fixture loop: a pre-calibration that fails with zero offsets is followed by a
//     post-calibration of the same configuration that verifies them; its PASS satisfies the
//     weekly check, its FAIL holds the machine (an intervention re-arms the loop from the
//     pre-calibration: the physical fix is checked like a new week);
//   - the weekly configuration rotation: each fixture's next configuration (0..2n-1) is kept
//     in the durable state and advances when a pre-calibration is first issued, not on re-arms;
//   - timeouts: a check with no result after calendar.check_timeout_min is issued again under a
//     new request id (<id>-r2, -r3, ...) at most calendar.retries times, then it holds the
//     machine ("no result ..."): reported in the status (and so in the historian), never dropped.
//     A late result of an earlier attempt still completes the check;
//   - status: NEEDS_INTERVENTION when held, CHECKING while a check runs, OVERDUE when a period's
//     check is overdue (calendar.hpp), UNKNOWN before every period has passed once, else
//     QUALIFIED.
// Without a calendar: start() runs the given checks once per machine, in order (the first
// failure holds the machine, interventions re-arm it), then the machine is QUALIFIED.
// Operator orders (CheckCommand) run at once beside the sequence; their verdicts count like any.
// While a machine is held, an order is taken only for the held check (or what its intervention
// re-runs) and for the checks before it in the plant's sequence (diagnostics); a later check, and
// any part check unless a part check is what holds it, is refused naming the hold: its PASS would
// look like a release of production. Every request names who ordered it (requested_by).
//
// Durable state: every decision is written to the state file (storage::StateFile), with the
// outbox entries of the requests and statuses it produced, before any of them leaves; so a kill at
// any point either loses the decision (it is taken again after the restart) or keeps it and what
// it sends (the outbox sends it until the historian acknowledged it; pending requests are sent
// again at start: the acquisition ignores a request id it has already performed). Request ids are
// <machine>-<kind>-<UTC time of issue>-<n> with n counted per machine in the state, so a restarted
// scheduler issues the same ids as one that was never stopped.
//
// Time: with the wall clock, now is the clock's. With a simulated clock (PlantConfig::
// simulated_clock) each machine has its own time: the later of the shared clock and the time of
// its newest result (the instrument's work takes simulated time), so one machine's sequence does
// not depend on when another machine's results arrive; the service moves the shared clock to
// next_event_ns() whenever idle().
#pragma once

#include "ncqual/common/calendar.hpp"
#include "ncqual/common/clock.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/storage/state_file.hpp"

#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::scheduler {

// A check that was issued and has no result yet.
struct PendingCheck {
  std::vector<std::string> request_ids;  // every attempt's id; back() is the current attempt
  CheckKind kind = CheckKind::MonumentPositioning;
  std::string requested_by;
  std::int64_t issued_ns = 0;  // of the current attempt
  std::vector<NamedValue> parameters;
  std::string verifies_correction_of;
  bool in_sequence = true;  // false for an operator's order
  bool rearmed = false;     // issued again after an intervention
};

// What holds a machine out of production until an intervention.
struct Hold {
  CheckKind kind = CheckKind::MonumentPositioning;  // the check an intervention must name
  std::string request_id;
  std::string detail;  // the failed check, its verdict, first likely cause, next step
  CheckKind rerun = CheckKind::MonumentPositioning;  // what runs when it is re-armed
  std::vector<NamedValue> parameters;                // with these parameters
  bool in_sequence = true;
};

// A check whose result the scheduler applied: kept (the newest 64) so that a conflict found later
// (two different measurement sets or results for its request) holds the machine for it.
struct JudgedCheck {
  std::string request_id;
  CheckKind kind = CheckKind::MonumentPositioning;
  std::vector<NamedValue> parameters;
  bool in_sequence = true;
};

// A conflict the historian raised (ncqual/Alarm of kind CONFLICT): its alarm id is
// conflict/<topic>/<sample id>/<content hash>; of a MeasurementSet or a CheckResult, the sample
// id is the request id.
struct ConflictAlarm {
  std::string topic;  // "ncqual/MeasurementSet"
  std::string request_id;
  std::string alarm_id;
};
// The conflict of a check's measurement set or result that `alarm` raises, if it is one (an
// active CONFLICT alarm of those topics); nothing for any other alarm.
std::optional<ConflictAlarm> check_conflict_of(const Alarm& alarm);

// Everything the scheduler knows about one machine; persisted as one document.
struct MachineRun {
  std::map<CheckKind, std::int64_t> last_pass_ns;  // newest PASS of each kind (result time)
  std::deque<CheckKind> queue;                     // the rest of this shift's period checks
  std::vector<PendingCheck> pending;
  std::optional<Hold> hold;
  std::optional<std::int64_t> planned_shift_ns;  // start of the shift already planned
  std::optional<std::int64_t> next_part_ns;      // when the next part's checks start
  std::size_t part_step = 0;                     // next of calendar.parts.checks in a part
  std::int64_t local_time_ns = 0;                // simulated clock: newest result time
  std::uint64_t sequence = 0;                    // request ids issued
  std::vector<std::string> interventions;        // ids applied (newest 64)
  std::vector<std::string> orders;               // operator orders issued (newest 64)
  std::vector<JudgedCheck> judged;               // results applied (newest 64)
  std::vector<std::string> conflicts;            // conflict alarm ids acted on (newest 64)
  MachineState state = MachineState::Unknown;
  std::string detail;
};

class Scheduler {
 public:
  struct Outputs {
    // Called for every request and status a decision produced, once the decision is saved (each
    // optional).
    std::function<void(const CheckRequest&)> request;
    std::function<void(const MachineStatus&)> status;
    // Optional: the outbox entries of a decision's requests and statuses, saved in the same
    // transaction as the decision, so that a kill keeps both or neither (the service's Outbox),
    // and handed to `written` once saved.
    std::function<std::vector<storage::OutboxEntry>(const std::vector<CheckRequest>&,
                                                    const std::vector<MachineStatus>&)>
        queue;
    std::function<void(const std::vector<storage::OutboxEntry>&)> written;
  };

  // Loads the machines' state from `state` when given (nullptr: in memory only). Machines in the
  // state file that the plant no longer configures are kept in the file, not scheduled.
  Scheduler(const PlantConfig& plant, const Clock& clock, Outputs outputs,
            storage::StateFile* state = nullptr);

  // Sends again what the state says is pending, publishes every machine's status, queues
  // `cycle` (without a calendar; with one, only when not empty: an explicit extra sequence) and
  // takes the first decisions.
  void start(const std::vector<CheckKind>& cycle);
  // Takes the decisions the time calls for: shift starts, parts, timeouts and retries.
  void tick();

  // An operator's order. Returns an empty string, or why it was refused (naming the field, and
  // the hold when the machine is held).
  std::string command(const CheckCommand& cmd);
  // A result from the solver. Results of requests this scheduler did not issue are ignored.
  void result(const CheckResult& res);
  // A conflict of a check's measurement set or result (the historian's alarm, whose `text` names
  // the request and both writers): the record of that check is in doubt, so the machine is held
  // (NEEDS_INTERVENTION, the text as its cause) until a person decides and records an
  // intervention for the check, which runs it again under a new request id. A check still
  // pending is taken off (its result will not count); a machine already held keeps its hold,
  // with the conflict added to its detail. Returns an empty string, or why it changed nothing (a
  // request this scheduler did not issue or no longer remembers; an alarm already acted on).
  std::string conflict(const std::string& machine_id, const ConflictAlarm& conflict,
                       const std::string& text);
  // A recorded intervention: re-arms the machine's held check when it names it. Returns an
  // empty string, or why it changed nothing (naming the field).
  std::string intervention(const Intervention& iv);

  // True when no check of any machine is waiting for a result.
  bool idle() const;
  // The earliest time a decision falls due (a shift start, a part, a timeout); nothing when
  // nothing ever will (no calendar, nothing pending).
  std::optional<std::int64_t> next_event_ns() const;
  // The simulated clock's value to keep (the shared clock, persisted with every decision).
  void persist_clock();
  // False when the last decision could not be saved (the state file failed): then nothing it
  // decided was sent, and nothing received should be acknowledged.
  bool saved() const { return saved_; }

  MachineState state(const std::string& machine_id) const;
  const MachineRun* run(const std::string& machine_id) const;
  // Each fixture's next pre-calibration configuration (by fixture_id).
  const std::map<std::string, int>& fixture_rotation() const { return rotation_; }

 private:
  struct Machine {
    const MachineConfig* config = nullptr;
    MachineRun run;
  };

  std::int64_t now(const Machine& m) const;
  void advance(Machine& m);
  void issue(Machine& m, CheckKind kind, const std::string& requested_by,
             std::vector<NamedValue> parameters, std::string verifies_correction_of,
             bool in_sequence, bool rearmed = false, std::string request_id = "");
  // A pre-calibration without an explicit configuration takes its fixture's next one.
  void add_fixture_configuration(Machine& m, CheckKind kind, std::vector<NamedValue>& parameters);
  // Queues a request for sending with the decision.
  void send(Machine& m, CheckRequest request);
  void retry_or_hold(Machine& m, PendingCheck& p);
  void hold(Machine& m, Hold h);
  void update_state(Machine& m, const std::string& request_id, std::optional<CheckKind> kind,
                    std::optional<Verdict> verdict, const std::string& detail_if_changed = "");
  std::string request_id_for(Machine& m, CheckKind kind);
  // The place of `kind` in the plant's qualification sequence (smaller runs first): the
  // calendar's periods in their order, then its part checks; without a calendar the cycle given
  // to start(); kinds in neither after them, by cadence. A check that verifies a correction
  // stands where the kind it satisfies does.
  std::size_t sequence_rank(CheckKind kind) const;
  // Why an order of `kind` is refused while `m` is held; empty when it is allowed.
  std::string refusal_while_held(const Machine& m, CheckKind kind) const;
  // Writes the state, then sends what the decision produced.
  void commit(Machine& m);
  // After a decision that could not be saved: the machine's run and the fixture rotation go back
  // to what the state file holds, so that the sample behind the decision, sent again because it
  // was not acknowledged, is decided again rather than taken for one already handled.
  void restore(Machine& m);

  const PlantConfig& plant_;
  const Clock& clock_;
  Outputs out_;
  storage::StateFile* state_file_;
  std::optional<Calendar> calendar_;
  std::map<std::string, Machine> machines_;
  std::map<std::string, int> rotation_;
  std::vector<CheckRequest> outbox_requests_;
  std::vector<MachineStatus> outbox_statuses_;
  std::vector<CheckKind> cycle_;  // start()'s, for sequence_rank without a calendar
  // The calendar's (or the default's) timeout and retries.
  double check_timeout_min_ = 0;
  std::int64_t check_timeout_ns_ = 0;
  int retries_ = 0;
  bool saved_ = true;
};

// The simulated clock a previous run kept in the state file, if any.
std::optional<std::int64_t> saved_clock_ns(storage::StateFile& file);

// The state documents, for the state file and for tests (round trip).
std::string to_json(const MachineRun& run);
MachineRun machine_run_from_json(const std::string& text);

}  // namespace ncqual::scheduler
