// SPDX-License-Identifier: Apache-2.0
// The qualification process of scheduler.hpp. One file on purpose, though over 700 lines: it is
// one state machine per machine (what is due, pending, held, retried; the fixture loop; conflicts),
// and each decision ends in the same commit(); its parts do not stand alone.
#include "ncqual/scheduler/scheduler.hpp"

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/json.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace ncqual::scheduler {

namespace {

// Interventions applied and operator orders issued are remembered per machine, the newest 64,
// so that one delivered or sent again is taken once.
constexpr std::size_t kRememberedIds = 64;
void remember(std::vector<std::string>& ids, const std::string& id) {
  ids.push_back(id);
  if (ids.size() > kRememberedIds) ids.erase(ids.begin());
}
constexpr std::int64_t kNsPerMinute = 60'000'000'000LL;

std::string kind_list(const std::vector<CheckKind>& kinds) {
  std::string out;
  for (CheckKind k : kinds) out += (out.empty() ? "" : ", ") + std::string(to_string(k));
  return out;
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

// "20260105T060000Z": the UTC time of issue inside request ids.
std::optional<std::int64_t> last_pass(const MachineRun& run, CheckKind kind) {
  const auto it = run.last_pass_ns.find(kind);
  return it == run.last_pass_ns.end() ? std::nullopt : std::optional(it->second);
}

std::string compact_time(std::int64_t t_ns) {
  char buffer[32];
  const std::string_view iso = format_iso8601(t_ns, buffer);
  std::string out;
  for (char c : iso.substr(0, 19)) {
    if (c != '-' && c != ':') out += c;
  }
  return out + "Z";
}

}  // namespace

// ------------------------------------------------------------------------------------------------
// State documents: one JSON document per machine ("machine/<id>"), per fixture ("fixture/<id>"),
// and the simulated clock ("clock"). An older version's "recent" and "readers" are ignored. Fields
// missing in a document read as their defaults, so a state written by an older version still loads.

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(PendingCheck, request_ids, kind, requested_by,
                                                issued_ns, parameters, verifies_correction_of,
                                                in_sequence, rearmed)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(Hold, kind, request_id, detail, rerun, parameters,
                                                in_sequence)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(JudgedCheck, request_id, kind, parameters,
                                                in_sequence)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(MachineRun, last_pass_ns, queue, pending, hold,
                                                planned_shift_ns, next_part_ns, part_step,
                                                local_time_ns, sequence, interventions, orders,
                                                judged, conflicts, state, detail)

namespace {

struct FixtureDocument {
  int next_configuration = 0;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(FixtureDocument, next_configuration)

struct ClockDocument {
  std::int64_t now_ns = 0;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ClockDocument, now_ns)

template <typename Document>
std::string dumped(const Document& document) {
  return nlohmann::json(document).dump();
}

template <typename Document>
Document parsed(const std::string& text) {
  return nlohmann::json::parse(text).get<Document>();
}

}  // namespace

std::string to_json(const MachineRun& run) { return dumped(run); }

MachineRun machine_run_from_json(const std::string& text) {
  auto run = parsed<MachineRun>(text);
  for (const auto& p : run.pending) {
    if (p.request_ids.empty())
      throw std::invalid_argument("scheduler state: a pending check without request id");
  }
  return run;
}

std::optional<std::int64_t> saved_clock_ns(storage::StateFile& file) {
  const auto docs = file.load();
  const auto it = docs.find("clock");
  if (it == docs.end()) return std::nullopt;
  return parsed<ClockDocument>(it->second).now_ns;
}

// ------------------------------------------------------------------------------------------------

Scheduler::Scheduler(const PlantConfig& plant, const Clock& clock, Outputs outputs,
                     storage::StateFile* state)
    : plant_(plant), clock_(clock), out_(std::move(outputs)), state_file_(state) {
  if (plant_.calendar) calendar_.emplace(*plant_.calendar);
  const CalendarConfig& limits = calendar_ ? calendar_->config() : default_calendar_config();
  check_timeout_min_ = limits.check_timeout_min;
  check_timeout_ns_ =
      static_cast<std::int64_t>(std::llround(limits.check_timeout_min * kNsPerMinute));
  retries_ = limits.retries;
  for (const auto& m : plant_.machines) machines_[m.machine_id].config = &m;
  if (!state_file_) return;
  for (const auto& [key, doc] : state_file_->load()) {
    try {
      if (key.rfind("machine/", 0) == 0) {
        auto it = machines_.find(key.substr(8));
        if (it != machines_.end()) it->second.run = machine_run_from_json(doc);
      } else if (key.rfind("fixture/", 0) == 0) {
        rotation_[key.substr(8)] = parsed<FixtureDocument>(doc).next_configuration;
      }
    } catch (const std::exception& e) {
      // A document this version cannot read: say so and start that part afresh, never stop.
      spdlog::error("scheduler state '{}' in {} ignored: {}", key, state_file_->path(), e.what());
    }
  }
}

std::int64_t Scheduler::now(const Machine& m) const {
  const std::int64_t t = clock_.now_ns();
  return plant_.simulated_clock ? std::max(t, m.run.local_time_ns) : t;
}

std::string Scheduler::request_id_for(Machine& m, CheckKind kind) {
  return m.config->machine_id + "-" + std::string(to_string(kind)) + "-" + compact_time(now(m)) +
         "-" + std::to_string(++m.run.sequence);
}

void Scheduler::start(const std::vector<CheckKind>& cycle) {
  cycle_ = cycle;
  for (auto& [id, m] : machines_) {
    // Whatever was pending when the last run stopped goes out again under the same id: an
    // acquisition that already measured it ignores it, one that never got it measures now.
    // (What the historian has not acknowledged is in the outbox and goes out anyway.)
    for (const auto& p : m.run.pending) {
      outbox_requests_.push_back(CheckRequest{
          id, p.request_ids.back(), p.kind, p.requested_by, p.issued_ns,
          static_cast<std::int32_t>(p.request_ids.size()), p.parameters, p.verifies_correction_of});
    }
    if (!cycle.empty() && !m.run.hold) {
      for (CheckKind k : cycle) {
        if (std::find(m.run.queue.begin(), m.run.queue.end(), k) == m.run.queue.end())
          m.run.queue.push_back(k);
      }
    }
    // The state as stored is not published again: it is no change, and the last change is in the
    // outbox until the historian has it (a restart would otherwise add a status "change" to the
    // history every time).
    advance(m);
    update_state(m, "", std::nullopt, std::nullopt);
    commit(m);
  }
}

void Scheduler::tick() {
  for (auto& [id, m] : machines_) {
    bool changed = false;
    for (std::size_t i = 0; i < m.run.pending.size();) {
      PendingCheck& p = m.run.pending[i];
      if (now(m) >= p.issued_ns + check_timeout_ns_) {
        const std::size_t before = m.run.pending.size();
        retry_or_hold(m, p);
        changed = true;
        if (m.run.pending.size() < before) continue;  // removed: same index holds the next one
      }
      ++i;
    }
    const auto before = std::make_pair(m.run.pending.size(), m.run.planned_shift_ns);
    advance(m);
    update_state(m, "", std::nullopt, std::nullopt);
    if (changed || before != std::make_pair(m.run.pending.size(), m.run.planned_shift_ns) ||
        !outbox_statuses_.empty() || !outbox_requests_.empty()) {
      commit(m);
    }
  }
}

void Scheduler::advance(Machine& m) {
  MachineRun& run = m.run;
  if (run.hold) return;
  if (std::any_of(run.pending.begin(), run.pending.end(),
                  [](const PendingCheck& p) { return p.in_sequence; })) {
    return;
  }
  const std::int64_t t = now(m);
  std::optional<ShiftSlot> shift;
  if (calendar_) {
    shift = calendar_->shift_at(t);
    if (shift && run.planned_shift_ns != shift->start_ns) {
      // A new shift: every period's due checks, in the configured order.
      run.planned_shift_ns = shift->start_ns;
      std::vector<CheckKind> planned;
      for (const auto& period : calendar_->config().periods) {
        for (CheckKind k : period.checks) {
          if (has_sections_for(*m.config, k) && calendar_->due(period, last_pass(run, k), t) &&
              std::find(run.queue.begin(), run.queue.end(), k) == run.queue.end()) {
            run.queue.push_back(k);
            planned.push_back(k);
          }
        }
      }
      run.part_step = 0;
      run.next_part_ns.reset();
      if (calendar_->config().parts.cycle_min > 0 && !calendar_->config().parts.checks.empty()) {
        run.next_part_ns = t;
      }
      spdlog::info("{}: shift '{}' from {} planned: {}", m.config->machine_id, shift->name,
                   calendar_->local_text(shift->start_ns),
                   planned.empty() ? "no period check due" : kind_list(planned));
    }
  }
  if (!run.queue.empty()) {
    const CheckKind next = run.queue.front();
    run.queue.pop_front();
    issue(m, next, "scheduler", {}, "", true);
    return;
  }
  if (shift && run.next_part_ns && *run.next_part_ns <= t && t < shift->end_ns) {
    const auto& parts = calendar_->config().parts.checks;
    const CheckKind next = parts[std::min(run.part_step, parts.size() - 1)];
    issue(m, next, "scheduler: part", {}, "", true);
  }
}

void Scheduler::send(Machine& /*m*/, CheckRequest request) {
  outbox_requests_.push_back(std::move(request));
}

void Scheduler::add_fixture_configuration(Machine& m, CheckKind kind,
                                          std::vector<NamedValue>& parameters) {
  if (kind != CheckKind::FixturePreCalibration || !m.config->fixture ||
      find_value(parameters, "fixture_configuration")) {
    return;
  }
  // This week's configuration: the fixture's next in its rotation.
  const FixtureConfig& f = *m.config->fixture;
  const int count = std::max(1, f.precalibration_configuration_count());
  int& next = rotation_[f.fixture_id];
  const int k = ((next % count) + count) % count;
  parameters.push_back({"fixture_configuration", static_cast<double>(k), ""});
  next = (k + 1) % count;
}

void Scheduler::issue(Machine& m, CheckKind kind, const std::string& requested_by,
                      std::vector<NamedValue> parameters, std::string verifies_correction_of,
                      bool in_sequence, bool rearmed, std::string request_id) {
  const std::int64_t t = now(m);
  add_fixture_configuration(m, kind, parameters);
  const std::string id = request_id.empty() ? request_id_for(m, kind) : std::move(request_id);
  PendingCheck p{{id},        kind,   requested_by, t, parameters, verifies_correction_of,
                 in_sequence, rearmed};
  m.run.pending.push_back(p);
  send(m, CheckRequest{m.config->machine_id, id, kind, requested_by, t, 1, std::move(parameters),
                       std::move(verifies_correction_of)});
  spdlog::info("{}: requesting {} ({}) for {}", m.config->machine_id, to_string(kind), id,
               requested_by);
  update_state(m, id, kind, std::nullopt,
               std::string(to_string(kind)) + " requested by " + requested_by);
}

void Scheduler::retry_or_hold(Machine& m, PendingCheck& p) {
  const int attempts = static_cast<int>(p.request_ids.size());
  const std::string late = p.request_ids.back();
  if (attempts <= retries_) {
    const std::string id = p.request_ids.front() + "-r" + std::to_string(attempts + 1);
    p.request_ids.push_back(id);
    p.issued_ns = now(m);
    send(m, CheckRequest{m.config->machine_id, id, p.kind, p.requested_by, p.issued_ns,
                         attempts + 1, p.parameters, p.verifies_correction_of});
    spdlog::warn("{}: no result for {} ({}) after {} min; attempt {} as {}", m.config->machine_id,
                 to_string(p.kind), late, check_timeout_min_, attempts + 1, id);
    update_state(m, id, p.kind, std::nullopt,
                 std::string(to_string(p.kind)) + ": no result for " + late + " after " +
                     std::to_string(static_cast<int>(check_timeout_min_)) + " min; attempt " +
                     std::to_string(attempts + 1) + " of " + std::to_string(retries_ + 1));
    return;
  }
  const PendingCheck lost = p;
  m.run.pending.erase(
      std::find_if(m.run.pending.begin(), m.run.pending.end(),
                   [&](const PendingCheck& q) { return q.request_ids == lost.request_ids; }));
  std::string ids;
  for (const auto& id : lost.request_ids) ids += (ids.empty() ? "" : ", ") + id;
  spdlog::error("{}: {} got no result after {} attempts ({})", m.config->machine_id,
                to_string(lost.kind), attempts, ids);
  hold(m, Hold{lost.kind, lost.request_ids.back(),
               std::string(to_string(lost.kind)) + " MISSED: no measurement or result after " +
                   std::to_string(attempts) + " attempts (" + ids +
                   "); first likely cause: the acquisition service or the instrument of " +
                   m.config->machine_id +
                   " is down; next: restore it, then ncqual intervene --machine " +
                   m.config->machine_id + " --check " + std::string(to_string(lost.kind)) +
                   " --note \"...\"",
               lost.kind, lost.parameters, lost.in_sequence});
}

void Scheduler::hold(Machine& m, Hold h) {
  const std::string id = h.request_id;
  const CheckKind kind = h.kind;
  m.run.hold = std::move(h);
  update_state(m, id, kind, Verdict::Fail);
}

std::string Scheduler::command(const CheckCommand& cmd) {
  auto it = machines_.find(cmd.machine_id);
  if (it == machines_.end()) {
    return "CheckCommand.machine_id '" + cmd.machine_id + "' is not configured in plant '" +
           plant_.plant + "'";
  }
  if (cmd.request_id.empty()) return "CheckCommand.request_id is empty";
  Machine& m = it->second;
  for (const auto& p : m.run.pending) {
    if (contains(p.request_ids, cmd.request_id)) return "";  // a resent order: already issued
  }
  // A sender writes its order again until the scheduler's acknowledgement reaches it
  // (dds::send_acknowledged); the check may be done by then: it is not run a second time under
  // the same request id (the historian would keep the second request as a conflict).
  if (contains(m.run.orders, cmd.request_id)) return "";
  if (std::string why = refusal_while_held(m, cmd.kind); !why.empty()) {
    spdlog::warn("{}: order {} of {} by {} refused: {}", cmd.machine_id, cmd.request_id,
                 to_string(cmd.kind), cmd.requested_by, why);
    return why;
  }
  // Beside the sequence: an operator's order neither waits for it nor holds it up.
  issue(m, cmd.kind, cmd.requested_by.empty() ? "operator" : cmd.requested_by, cmd.parameters, "",
        false, false, cmd.request_id);
  remember(m.run.orders, cmd.request_id);
  commit(m);
  return "";
}

std::size_t Scheduler::sequence_rank(CheckKind kind) const {
  const CheckKindInfo& info = check_kind_info(kind);
  if (info.cadence == Cadence::AfterCorrection && info.satisfies) kind = *info.satisfies;
  std::vector<CheckKind> plan;
  if (calendar_) {
    for (const auto& period : calendar_->config().periods) {
      plan.insert(plan.end(), period.checks.begin(), period.checks.end());
    }
    const auto& parts = calendar_->config().parts.checks;
    plan.insert(plan.end(), parts.begin(), parts.end());
  } else {
    plan = cycle_;
  }
  const auto at = std::find(plan.begin(), plan.end(), kind);
  if (at != plan.end()) return static_cast<std::size_t>(at - plan.begin());
  return plan.size() + static_cast<std::size_t>(check_kind_info(kind).cadence) * kCheckKindCount +
         static_cast<std::size_t>(kind);
}

std::string Scheduler::refusal_while_held(const Machine& m, CheckKind kind) const {
  if (!m.run.hold) return "";
  const Hold& h = *m.run.hold;
  const std::size_t held_rank = sequence_rank(h.kind);
  const auto allowed_while_held = [&](CheckKind k) {
    return k == h.rerun || intervention_matches(k, h.kind) ||
           (check_kind_info(k).cadence != Cadence::PerPart && sequence_rank(k) < held_rank);
  };
  if (allowed_while_held(kind)) return "";
  std::vector<CheckKind> allowed;
  for (const auto& info : check_kinds()) {
    if (has_sections_for(*m.config, info.kind) && allowed_while_held(info.kind)) {
      allowed.push_back(info.kind);
    }
  }
  return "CheckCommand.kind '" + std::string(to_string(kind)) + "': machine '" +
         m.config->machine_id + "' is held (NEEDS_INTERVENTION) by " +
         std::string(to_string(h.kind)) + " (request " + h.request_id +
         "); a PASS of this check would look like a release of production. While held, only " +
         "the held check and the checks before it may be ordered (" + kind_list(allowed) +
         "); the hold: " + h.detail;
}

void Scheduler::result(const CheckResult& res) {
  auto it = machines_.find(res.machine_id);
  if (it == machines_.end()) return;
  Machine& m = it->second;
  auto p = std::find_if(m.run.pending.begin(), m.run.pending.end(), [&](const PendingCheck& q) {
    return contains(q.request_ids, res.request_id);
  });
  if (p == m.run.pending.end()) return;  // not ours, or already handled
  const PendingCheck done = *p;
  m.run.pending.erase(p);
  m.run.judged.push_back(JudgedCheck{res.request_id, res.kind, done.parameters, done.in_sequence});
  if (m.run.judged.size() > kRememberedIds) m.run.judged.erase(m.run.judged.begin());
  if (plant_.simulated_clock) m.run.local_time_ns = std::max(m.run.local_time_ns, res.time_ns);
  const std::int64_t t = now(m);
  if (res.verdict == Verdict::Pass) {
    const std::int64_t when = res.time_ns > 0 ? res.time_ns : t;
    m.run.last_pass_ns[res.kind] = when;
    // A pass that also satisfies another kind (a post-calibration ends the week's fixture loop)
    // counts for it too.
    if (const auto satisfied = check_kind_info(res.kind).satisfies) {
      m.run.last_pass_ns[*satisfied] = when;
    }
    if (calendar_ && done.in_sequence) {
      const auto& parts = calendar_->config().parts.checks;
      if (std::find(parts.begin(), parts.end(), res.kind) != parts.end() && m.run.next_part_ns) {
        if (++m.run.part_step >= parts.size()) {
          m.run.part_step = 0;
          m.run.next_part_ns = t + static_cast<std::int64_t>(std::llround(
                                       calendar_->config().parts.cycle_min * kNsPerMinute));
        }
      }
    }
    update_state(m, res.request_id, res.kind, res.verdict,
                 std::string(to_string(res.kind)) + " passed");
    advance(m);
    commit(m);
    return;
  }
  // The fixture loop: a pre-calibration out of tolerance issues zero offsets (the solver
  // publishes them as a Compensation for the fixture's control unit); a post-calibration of the
  // same configuration then decides whether software correction was enough.
  const std::optional<CheckKind> verification = verified_by(res.kind);
  if (verification && res.verdict == Verdict::Fail && res.correction) {
    spdlog::info("{}: {} issued zero offsets for {}; verifying them", res.machine_id,
                 res.request_id, res.correction->target);
    issue(m, *verification, "scheduler", done.parameters, res.request_id, done.in_sequence);
    commit(m);
    return;
  }
  // A failed or invalid check stops the checks after it and holds the machine.
  std::string detail = std::string(to_string(res.kind)) + " " + std::string(to_string(res.verdict));
  if (!res.likely_causes.empty()) detail += "; first likely cause: " + res.likely_causes.front();
  if (!res.reason.empty()) detail += "; " + res.reason;
  const CheckKind rerun = rerun_after_intervention(res.kind);
  detail +=
      "; next: " +
      std::string(res.likely_causes.empty() ? "investigate" : "investigate the causes in order") +
      ", then ncqual intervene --machine " + res.machine_id + " --check " +
      std::string(to_string(res.kind)) + " --note \"...\"" +
      (rerun != res.kind ? " (re-runs " + std::string(to_string(rerun)) + ")"
                         : std::string(" (re-runs the check)"));
  std::vector<NamedValue> parameters = done.parameters;
  hold(m, Hold{res.kind, res.request_id, detail, rerun, parameters, done.in_sequence});
  commit(m);
}

std::optional<ConflictAlarm> check_conflict_of(const Alarm& alarm) {
  if (alarm.kind != AlarmKind::Conflict || !alarm.active) return std::nullopt;
  // conflict/<topic>/<sample id>/<content hash>, the topic itself "ncqual/<Type>".
  for (const char* topic : {"ncqual/MeasurementSet", "ncqual/CheckResult"}) {
    const std::string head = "conflict/" + std::string(topic) + "/";
    if (alarm.alarm_id.rfind(head, 0) != 0) continue;
    const std::size_t hash_at = alarm.alarm_id.rfind('/');
    if (hash_at < head.size()) return std::nullopt;
    const std::string request_id = alarm.alarm_id.substr(head.size(), hash_at - head.size());
    if (request_id.empty()) return std::nullopt;
    return ConflictAlarm{topic, request_id, alarm.alarm_id};
  }
  return std::nullopt;
}

std::string Scheduler::conflict(const std::string& machine_id, const ConflictAlarm& conflict,
                                const std::string& text) {
  auto it = machines_.find(machine_id);
  if (it == machines_.end()) return "machine '" + machine_id + "' is not served here";
  Machine& m = it->second;
  if (contains(m.run.conflicts, conflict.alarm_id)) return "";  // delivered again
  std::optional<JudgedCheck> check;
  for (const auto& j : m.run.judged) {
    if (j.request_id == conflict.request_id) check = j;
  }
  const auto pending = std::find_if(m.run.pending.begin(), m.run.pending.end(), [&](const auto& p) {
    return contains(p.request_ids, conflict.request_id);
  });
  if (!check && pending != m.run.pending.end()) {
    check =
        JudgedCheck{conflict.request_id, pending->kind, pending->parameters, pending->in_sequence};
    m.run.pending.erase(pending);  // its result, whichever set it came from, does not count
  }
  if (!check) {
    return "request " + conflict.request_id +
           " is not a check this scheduler issued (an import?) or remembers: the machine's state "
           "is unchanged";
  }
  remember(m.run.conflicts, conflict.alarm_id);
  spdlog::error("{}: {}; held until a person decides", machine_id, text);
  if (m.run.hold) {
    m.run.hold->detail += "; also: " + text;
    update_state(m, conflict.request_id, check->kind, Verdict::Fail);
    commit(m);
    return "";
  }
  const std::string kind(to_string(check->kind));
  hold(m, Hold{check->kind, conflict.request_id,
               text + "; next: compare the two (ncqual history --writers --machine " + machine_id +
                   "), stop the writer that should not have written, then ncqual intervene "
                   "--machine " +
                   machine_id + " --check " + kind + " --note \"...\" (re-runs the check)",
               check->kind, check->parameters, check->in_sequence});
  commit(m);
  return "";
}

std::string Scheduler::intervention(const Intervention& iv) {
  auto it = machines_.find(iv.machine_id);
  if (it == machines_.end()) {
    return "Intervention.machine_id '" + iv.machine_id + "' is not configured in plant '" +
           plant_.plant + "'";
  }
  Machine& m = it->second;
  if (iv.intervention_id.empty()) return "Intervention.intervention_id is empty";
  if (contains(m.run.interventions, iv.intervention_id)) return "";  // redelivered
  if (!m.run.hold) {
    return "Intervention.kind '" + std::string(to_string(iv.kind)) + "': machine '" +
           iv.machine_id +
           "' is not held; nothing to re-arm (the intervention is recorded by the historian)";
  }
  const Hold h = *m.run.hold;
  if (!intervention_matches(iv.kind, h.kind)) {
    return "Intervention.kind '" + std::string(to_string(iv.kind)) +
           "' does not match the held check '" + std::string(to_string(h.kind)) + "' of machine '" +
           iv.machine_id + "'";
  }
  remember(m.run.interventions, iv.intervention_id);
  m.run.hold.reset();
  spdlog::info("{}: intervention {} re-arms {}: {}", iv.machine_id, iv.intervention_id,
               to_string(h.rerun), iv.note);
  issue(m, h.rerun, "intervention:" + iv.intervention_id, h.parameters, "", h.in_sequence, true);
  commit(m);
  return "";
}

void Scheduler::update_state(Machine& m, const std::string& request_id,
                             std::optional<CheckKind> kind, std::optional<Verdict> verdict,
                             const std::string& detail_if_changed) {
  MachineRun& run = m.run;
  MachineState state = MachineState::Qualified;
  std::string detail;
  const std::int64_t t = now(m);
  if (run.hold) {
    state = MachineState::NeedsIntervention;
    detail = run.hold->detail;
  } else if (!run.pending.empty()) {
    state = MachineState::Checking;
    detail = detail_if_changed.empty() ? run.detail : detail_if_changed;
  } else if (calendar_) {
    std::vector<CheckKind> overdue, never;
    for (const auto& period : calendar_->config().periods) {
      for (CheckKind k : period.checks) {
        if (!has_sections_for(*m.config, k)) continue;
        const std::optional<std::int64_t> last_pass = scheduler::last_pass(run, k);
        if (calendar_->overdue(period, last_pass, t)) {
          overdue.push_back(k);
        } else if (!last_pass) {
          never.push_back(k);
        }
      }
    }
    if (!overdue.empty()) {
      state = MachineState::Overdue;
      detail = "overdue: " + kind_list(overdue);
    } else if (!never.empty()) {
      state = MachineState::Unknown;
      detail = "not yet checked: " + kind_list(never);
    } else {
      detail = "every period's checks current";
    }
  } else if (run.last_pass_ns.empty()) {
    state = MachineState::Unknown;
    detail = "no check yet";
  } else {
    detail = detail_if_changed.empty() ? run.detail : detail_if_changed;
  }
  if (state == run.state && detail == run.detail) return;
  run.state = state;
  run.detail = detail;
  outbox_statuses_.push_back(
      MachineStatus{m.config->machine_id, request_id, state, kind, verdict, detail, t});
}

void Scheduler::commit(Machine& m) {
  auto requests = std::move(outbox_requests_);
  auto statuses = std::move(outbox_statuses_);
  outbox_requests_.clear();
  outbox_statuses_.clear();
  saved_ = true;
  const std::vector<storage::OutboxEntry> entries =
      out_.queue ? out_.queue(requests, statuses) : std::vector<storage::OutboxEntry>{};
  if (state_file_) {
    std::map<std::string, std::string> docs;
    docs["machine/" + m.config->machine_id] = to_json(m.run);
    for (const auto& [fixture, next] : rotation_) {
      docs["fixture/" + fixture] = dumped(FixtureDocument{next});
    }
    if (plant_.simulated_clock) docs["clock"] = dumped(ClockDocument{clock_.now_ns()});
    try {
      state_file_->save(docs, {}, entries);
    } catch (const std::exception& e) {
      // The plant keeps running; nothing of the decision leaves (what it would send is not in
      // the outbox), and a restart takes it again.
      spdlog::error("{}: scheduler state not saved to {}: {}", m.config->machine_id,
                    state_file_->path(), e.what());
      saved_ = false;
      restore(m);
      return;
    }
  }
  if (out_.written) out_.written(entries);
  if (out_.request) {
    for (const auto& r : requests) out_.request(r);
  }
  if (out_.status) {
    for (const auto& s : statuses) out_.status(s);
  }
}

void Scheduler::restore(Machine& m) {
  const std::string key = "machine/" + m.config->machine_id;
  try {
    const auto docs = state_file_->load();
    const auto it = docs.find(key);
    m.run = it == docs.end() ? MachineRun{} : machine_run_from_json(it->second);
    for (auto& [fixture, next] : rotation_) {
      const auto doc = docs.find("fixture/" + fixture);
      if (doc != docs.end()) next = parsed<FixtureDocument>(doc->second).next_configuration;
    }
  } catch (const std::exception& e) {
    spdlog::error(
        "{}: the state before the unsaved decision could not be read back from {} ({}); "
        "the decision stays in memory until a restart",
        m.config->machine_id, state_file_->path(), e.what());
  }
}

void Scheduler::persist_clock() {
  if (!state_file_ || !plant_.simulated_clock) return;
  try {
    state_file_->save({{"clock", dumped(ClockDocument{clock_.now_ns()})}});
  } catch (const std::exception& e) {
    spdlog::error("scheduler clock not saved to {}: {}", state_file_->path(), e.what());
  }
}

bool Scheduler::idle() const {
  return std::all_of(machines_.begin(), machines_.end(),
                     [](const auto& kv) { return kv.second.run.pending.empty(); });
}

std::optional<std::int64_t> Scheduler::next_event_ns() const {
  std::optional<std::int64_t> best;
  const auto consider = [&](std::int64_t t) {
    if (!best || t < *best) best = t;
  };
  for (const auto& [id, m] : machines_) {
    const MachineRun& run = m.run;
    for (const auto& p : run.pending) consider(p.issued_ns + check_timeout_ns_);
    if (run.hold) continue;
    if (std::any_of(run.pending.begin(), run.pending.end(),
                    [](const PendingCheck& p) { return p.in_sequence; })) {
      continue;
    }
    const std::int64_t t = now(m);
    if (!run.queue.empty()) {
      consider(t);
      continue;
    }
    if (!calendar_) continue;
    const auto shift = calendar_->shift_at(t);
    if (shift && run.planned_shift_ns != shift->start_ns) {
      consider(t);
      continue;
    }
    if (shift && run.next_part_ns && *run.next_part_ns < shift->end_ns) {
      consider(std::max(t, *run.next_part_ns));
    }
    if (const auto next = calendar_->next_shift_after(t)) consider(next->start_ns);
  }
  return best;
}

MachineState Scheduler::state(const std::string& machine_id) const {
  auto it = machines_.find(machine_id);
  return it == machines_.end() ? MachineState::Unknown : it->second.run.state;
}

const MachineRun* Scheduler::run(const std::string& machine_id) const {
  auto it = machines_.find(machine_id);
  return it == machines_.end() ? nullptr : &it->second.run;
}

}  // namespace ncqual::scheduler
