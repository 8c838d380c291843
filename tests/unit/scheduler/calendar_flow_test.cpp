// SPDX-License-Identifier: Apache-2.0
// The scheduler running the plant calendar on a simulated clock: which checks each shift runs
// (monthly, weekly, daily; parts), across month ends, DST and missed shifts; gating and re-arming
// by an intervention; the fixture loop; the configuration rotation across restarts; timeouts and
// retries; and restarts at random points that end with exactly the checks of an uninterrupted
// run. The driver below answers requests the way the acquisition and solver do (a result some
// simulated minutes after the request); the clock moves by ncqual-scheduler's own run_simulated.
#include "ncqual/scheduler/driver.hpp"
#include "ncqual/scheduler/scheduler.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <random>
#include <set>

namespace ncqual::scheduler {
namespace {

constexpr std::int64_t kMinute = 60'000'000'000LL;
constexpr std::int64_t kHour = 60 * kMinute;
constexpr std::int64_t kDay = 24 * kHour;

std::int64_t utc(const char* text) { return parse_iso8601(text).value(); }

FixtureConfig fixture(const std::string& id) {
  FixtureConfig f;
  f.fixture_id = id;
  f.z_planes_mm = {0, 152.4, 304.8, 457.2, 609.6};  // ten configurations
  return f;
}

MachineConfig machine(const std::string& id, const std::string& fixture_id = "") {
  MachineConfig m;
  m.machine_id = id;
  m.global_check = GlobalCheckConfig{};
  if (!fixture_id.empty()) m.fixture = fixture(fixture_id);
  return m;
}

PlantConfig plant(std::vector<MachineConfig> machines, const char* zone = "UTC") {
  PlantConfig p;
  p.plant = "test";
  p.machines = std::move(machines);
  CalendarConfig c = default_calendar_config();
  c.time_zone = zone;
  c.check_timeout_min = 60;
  c.retries = 2;
  p.calendar = c;
  p.simulated_clock = true;
  return p;
}

const std::vector<CheckKind> kMonthly = default_calendar_config().periods[0].checks;
const std::vector<CheckKind> kDaily = default_calendar_config().periods[2].checks;

// What one check answers: a verdict (optionally a correction), or nothing at all (lost).
struct Answer {
  Verdict verdict = Verdict::Pass;
  std::vector<std::string> causes;
  bool with_correction = false;
  bool lost = false;
};

// Plays acquisition + solver against a Scheduler and drives the simulated clock.
struct Driver {
  SimulatedClock clock;
  std::vector<CheckRequest> requests;  // every request the scheduler issued, in order (a request
                                       // sent again after a restart counts once)
  int resent = 0;                      // requests sent again under an id already issued
  std::set<std::string> issued_ids;
  std::vector<MachineStatus> statuses;
  std::deque<CheckRequest> inbox;
  std::set<std::string> performed;  // request ids already answered (the acquisition dedupes)
  std::function<Answer(const CheckRequest&)> answer = [](const CheckRequest&) { return Answer{}; };
  std::int64_t duration = 10 * kMinute;

  explicit Driver(std::int64_t start) : clock(start) {}

  Scheduler::Outputs outputs() {
    Scheduler::Outputs out;
    out.request = [this](const CheckRequest& r) {
      if (issued_ids.insert(r.request_id).second) {
        requests.push_back(r);
      } else {
        ++resent;
      }
      inbox.push_back(r);
    };
    out.status = [this](const MachineStatus& s) { statuses.push_back(s); };
    return out;
  }

  // Answers one request from the inbox; false when the inbox is empty.
  bool deliver_one(Scheduler& s) {
    if (inbox.empty()) return false;
    const CheckRequest r = inbox.front();
    inbox.pop_front();
    if (!performed.insert(r.request_id).second) return true;
    const Answer a = answer(r);
    if (a.lost) return true;
    CheckResult res;
    res.machine_id = r.machine_id;
    res.request_id = r.request_id;
    res.kind = r.kind;
    res.verdict = a.verdict;
    res.likely_causes = a.causes;
    res.time_ns = r.time_ns + duration;
    if (a.with_correction) res.correction = Correction{"fixture:F", {{"C1R1.dz_mm", 0.02, "mm"}}};
    s.result(res);
    return true;
  }

  // ncqual-scheduler's own simulated run (driver.hpp), with this driver as its events: each wait
  // answers one request at once, and an empty inbox is a stall (the clock runs on to the next
  // deadline). It ends when nothing is due before `until`.
  void run(Scheduler& s, std::int64_t until) { run_for(s, until, -1); }

  // As run, but the process is killed after `waits` waits for events (-1: never). True when it
  // was killed before the run was over.
  bool run_for(Scheduler& s, std::int64_t until, int waits) {
    SimulatedRunOptions options;
    options.until_ns = until;
    options.stall = std::chrono::milliseconds(0);
    options.operator_patience = std::chrono::milliseconds(0);
    options.give_up_after_idle_waits = 3;
    bool killed = false;
    run_simulated(s, clock,
                  {[&](std::chrono::milliseconds) {
                     killed = waits >= 0 && --waits < 0;
                     return !killed && deliver_one(s);
                   },
                   [&] { return killed; }},
                  options);
    return killed;
  }

  std::vector<CheckKind> kinds_between(std::int64_t from, std::int64_t to,
                                       const std::string& machine_id = "m1") const {
    std::vector<CheckKind> out;
    for (const auto& r : requests) {
      if (r.machine_id == machine_id && r.time_ns >= from && r.time_ns < to) out.push_back(r.kind);
    }
    return out;
  }
};

std::vector<CheckKind> concat(std::initializer_list<std::vector<CheckKind>> parts) {
  std::vector<CheckKind> out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

TEST(CalendarFlow, FirstShiftRunsMonthlyWeeklyDailyThenOnlyWhatIsDue) {
  const PlantConfig p = plant({machine("m1", "F")});
  Driver d(utc("2026-01-05T00:00:00Z"));  // Monday
  Scheduler s(p, d.clock, d.outputs());
  s.start({});
  d.run(s, utc("2026-02-03T00:00:00Z"));
  // Monday 5 January, early shift: everything, in the process order, one after the other.
  const auto monday = d.kinds_between(utc("2026-01-05T06:00:00Z"), utc("2026-01-05T14:00:00Z"));
  EXPECT_EQ(monday, concat({kMonthly, {CheckKind::FixturePreCalibration}, kDaily}));
  // Its late shift: nothing is due (daily means once per day).
  EXPECT_TRUE(d.kinds_between(utc("2026-01-05T14:00:00Z"), utc("2026-01-06T00:00:00Z")).empty());
  // Tuesday: the daily checks only; next Monday: weekly then daily.
  EXPECT_EQ(d.kinds_between(utc("2026-01-06T00:00:00Z"), utc("2026-01-07T00:00:00Z")), kDaily);
  EXPECT_EQ(d.kinds_between(utc("2026-01-12T00:00:00Z"), utc("2026-01-13T00:00:00Z")),
            concat({{CheckKind::FixturePreCalibration}, kDaily}));
  // No checks at the weekend.
  EXPECT_TRUE(d.kinds_between(utc("2026-01-10T00:00:00Z"), utc("2026-01-12T00:00:00Z")).empty());
  // The month ends: the first shift of February (Monday 2 February) runs the monthly checks again.
  EXPECT_EQ(d.kinds_between(utc("2026-02-02T00:00:00Z"), utc("2026-02-03T00:00:00Z")),
            concat({kMonthly, {CheckKind::FixturePreCalibration}, kDaily}));
  // Within January the monthly ran once: 9 kinds once each.
  EXPECT_EQ(d.kinds_between(utc("2026-01-05T00:00:00Z"), utc("2026-02-01T00:00:00Z")).size(),
            kMonthly.size() + 4 * 1 + 20 * 4);  // 4 weeks of precal, 20 working days of daily
  EXPECT_EQ(s.state("m1"), MachineState::Qualified);
  // Each request starts when the previous check's result came back (10 simulated minutes).
  const auto& r = d.requests;
  ASSERT_GE(r.size(), 2u);
  EXPECT_EQ(r[0].time_ns, utc("2026-01-05T06:00:00Z"));
  EXPECT_EQ(r[1].time_ns - r[0].time_ns, d.duration);
}

TEST(CalendarFlow, ShiftsFollowTheLocalClockAcrossDst) {
  PlantConfig p = plant({machine("m1")}, "Europe/Berlin");
  p.calendar->periods = {default_calendar_config().periods[2]};  // daily only
  Driver d(utc("2026-03-26T00:00:00Z"));
  Scheduler s(p, d.clock, d.outputs());
  s.start({});
  d.run(s, utc("2026-03-31T12:00:00Z"));
  std::vector<std::int64_t> first_of_day;
  for (const auto& r : d.requests) {
    if (r.kind == CheckKind::MonumentCAlignment) first_of_day.push_back(r.time_ns);
  }
  // Thursday 26, Friday 27 March at 06:00 CET (05:00Z); Monday 30 and Tuesday 31 at 06:00 CEST
  // (04:00Z): the clocks sprang forward on Sunday 29 March.
  ASSERT_EQ(first_of_day.size(), 4u);
  EXPECT_EQ(first_of_day[0], utc("2026-03-26T05:00:00Z"));
  EXPECT_EQ(first_of_day[1], utc("2026-03-27T05:00:00Z"));
  EXPECT_EQ(first_of_day[2], utc("2026-03-30T04:00:00Z"));
  EXPECT_EQ(first_of_day[3], utc("2026-03-31T04:00:00Z"));
}

TEST(CalendarFlow, MissedShiftsRunWhatIsDueOnceWhenTheMachineIsBack) {
  const PlantConfig p = plant({machine("m1", "F")});
  const std::string file = ::testing::TempDir() + "ncqual-sched-missed.db";
  std::filesystem::remove(file);
  auto state = storage::StateFile::open(file);
  Driver d(utc("2026-01-05T00:00:00Z"));
  {
    Scheduler s(p, d.clock, d.outputs(), &state);
    s.start({});
    d.run(s, utc("2026-01-05T20:00:00Z"));
  }
  // The scheduler is down for twelve days (two weekly periods and nine working days missed).
  d.clock.set_ns(utc("2026-01-19T09:30:00Z"));
  const std::size_t before = d.requests.size();
  Scheduler s(p, d.clock, d.outputs(), &state);
  s.start({});
  d.run(s, utc("2026-01-19T20:00:00Z"));
  const std::vector<CheckRequest> after(d.requests.begin() + static_cast<long>(before),
                                        d.requests.end());
  std::vector<CheckKind> kinds;
  for (const auto& r : after) kinds.push_back(r.kind);
  // Back in the middle of Monday's early shift: the weekly and daily checks once, not once per
  // missed period; the monthly is still current (January).
  EXPECT_EQ(kinds, concat({{CheckKind::FixturePreCalibration}, kDaily}));
  ASSERT_FALSE(after.empty());
  EXPECT_EQ(after.front().time_ns, utc("2026-01-19T09:30:00Z"));
}

TEST(CalendarFlow, AFailureHoldsTheMachineUntilAnInterventionReArmsTheCheck) {
  PlantConfig p = plant({machine("m1")});
  p.calendar->periods = {default_calendar_config().periods[2]};
  Driver d(utc("2026-01-05T00:00:00Z"));
  int tool_length_runs = 0;
  d.answer = [&](const CheckRequest& r) {
    if (r.kind == CheckKind::MonumentToolLength && ++tool_length_runs == 1) {
      return Answer{Verdict::Fail, {"tool length offset wrong", "monument moved"}};
    }
    return Answer{};
  };
  Scheduler s(p, d.clock, d.outputs());
  s.start({});
  d.run(s, utc("2026-01-07T00:00:00Z"));  // through Tuesday
  // Monday: check 1 passed, check 2 failed; nothing after it, not even on Tuesday.
  EXPECT_EQ(d.kinds_between(0, utc("2026-01-07T00:00:00Z")),
            (std::vector<CheckKind>{CheckKind::MonumentCAlignment, CheckKind::MonumentToolLength}));
  EXPECT_EQ(s.state("m1"), MachineState::NeedsIntervention);
  const std::string detail = d.statuses.back().detail;
  EXPECT_NE(detail.find("monument_tool_length FAIL"), std::string::npos) << detail;
  EXPECT_NE(detail.find("first likely cause: tool length offset wrong"), std::string::npos)
      << detail;
  EXPECT_NE(detail.find("ncqual intervene --machine m1 --check monument_tool_length"),
            std::string::npos)
      << detail;
  EXPECT_EQ(d.statuses.back().last_kind, CheckKind::MonumentToolLength);

  // An intervention for another check, or another machine, re-arms nothing.
  EXPECT_NE(s.intervention({"m1", "iv-0", CheckKind::MonumentPositioning, "wrong one", "ann", 0})
                .find("does not match the held check 'monument_tool_length'"),
            std::string::npos);
  EXPECT_NE(
      s.intervention({"m9", "iv-0", CheckKind::MonumentToolLength, "", "ann", 0}).find("'m9'"),
      std::string::npos);
  EXPECT_EQ(s.state("m1"), MachineState::NeedsIntervention);

  // Wednesday 08:00: the operator reset the tool length offset. The check runs again at once and
  // the sequence resumes from there; the same intervention delivered twice does it once.
  d.clock.set_ns(utc("2026-01-07T08:00:00Z"));
  const std::size_t before = d.requests.size();
  EXPECT_EQ(s.intervention({"m1", "iv-1", CheckKind::MonumentToolLength, "offset reset", "ann", 0}),
            "");
  EXPECT_EQ(s.intervention({"m1", "iv-1", CheckKind::MonumentToolLength, "offset reset", "ann", 0}),
            "");
  ASSERT_EQ(d.requests.size(), before + 1);
  EXPECT_EQ(d.requests.back().kind, CheckKind::MonumentToolLength);
  EXPECT_EQ(d.requests.back().requested_by, "intervention:iv-1");
  d.run(s, utc("2026-01-07T13:00:00Z"));
  // Re-armed check 2, then 3 and 4. The plan of Wednesday's shift (made at the re-arm: the whole
  // daily set is due again on a new day) puts check 1 after them.
  std::vector<CheckKind> wednesday =
      d.kinds_between(utc("2026-01-07T08:00:00Z"), utc("2026-01-08T00:00:00Z"));
  ASSERT_GE(wednesday.size(), 3u);
  EXPECT_EQ(std::vector<CheckKind>(wednesday.begin(), wednesday.begin() + 3),
            (std::vector<CheckKind>{CheckKind::MonumentToolLength, CheckKind::MonumentPositioning,
                                    CheckKind::MonumentCRotation}));
  EXPECT_EQ(s.state("m1"), MachineState::Qualified);
}

// Issue 14: a part check ordered on a held machine passed and released nothing on paper, but
// looked like production had resumed. Orders on a held machine: the held check and the checks
// before it run (diagnostics, the machine stays held); later checks and part checks are refused
// naming the hold; every request names who ordered it.
TEST(CalendarFlow, OrdersThatWouldReleaseAHeldMachineAreRefusedNamingTheHold) {
  PlantConfig p = plant({machine("m1")});
  p.calendar->periods = {default_calendar_config().periods[2]};
  p.calendar->parts.checks = {CheckKind::PartSetPoints};
  Driver d(utc("2026-01-05T00:00:00Z"));
  d.answer = [&](const CheckRequest& r) {
    if (r.kind == CheckKind::MonumentToolLength && r.requested_by == "scheduler") {
      return Answer{Verdict::Fail, {"bent stylus"}};
    }
    return Answer{};
  };
  Scheduler s(p, d.clock, d.outputs());
  s.start({});
  d.run(s, utc("2026-01-05T12:00:00Z"));
  ASSERT_EQ(s.state("m1"), MachineState::NeedsIntervention);
  const std::string held_request = d.requests.back().request_id;
  const std::size_t before = d.requests.size();

  for (CheckKind later :
       {CheckKind::PartSetPoints, CheckKind::MonumentPositioning, CheckKind::MonumentCRotation}) {
    const std::string why =
        s.command({"m1", "order-" + std::string(to_string(later)), later, "operator:ann", 0, {}});
    EXPECT_NE(why.find("CheckCommand.kind '" + std::string(to_string(later)) + "'"),
              std::string::npos)
        << why;
    EXPECT_NE(why.find("held (NEEDS_INTERVENTION) by monument_tool_length (request " +
                       held_request + ")"),
              std::string::npos)
        << why;
    EXPECT_NE(why.find("bent stylus"), std::string::npos) << why;
    EXPECT_NE(why.find("(monument_c_alignment, monument_tool_length)"), std::string::npos) << why;
  }
  EXPECT_EQ(d.requests.size(), before);

  // The held check and the one before it may be ordered; their PASS leaves the machine held.
  EXPECT_EQ(s.command({"m1", "diag-1", CheckKind::MonumentToolLength, "operator:ann", 0, {}}), "");
  EXPECT_EQ(s.command({"m1", "diag-2", CheckKind::MonumentCAlignment, "operator:bob", 0, {}}), "");
  ASSERT_EQ(d.requests.size(), before + 2);
  EXPECT_EQ(d.requests[before].requested_by, "operator:ann");
  EXPECT_EQ(d.requests[before + 1].requested_by, "operator:bob");
  d.run(s, utc("2026-01-05T13:00:00Z"));
  EXPECT_EQ(s.state("m1"), MachineState::NeedsIntervention);

  // After the intervention the part check may be ordered again.
  EXPECT_EQ(s.intervention({"m1", "iv-1", CheckKind::MonumentToolLength, "stylus", "ann", 0}), "");
  EXPECT_EQ(s.command({"m1", "part-1", CheckKind::PartSetPoints, "operator:ann", 0, {}}), "");
}

// Without a calendar the order of the cycle given to start() is the sequence.
TEST(CalendarFlow, WithoutACalendarTheCycleOrdersTheChecksAHoldAllows) {
  PlantConfig p = plant({machine("m1")});
  p.calendar.reset();
  Driver d(utc("2026-01-05T00:00:00Z"));
  d.answer = [&](const CheckRequest& r) {
    return r.kind == CheckKind::MonumentToolLength ? Answer{Verdict::Invalid, {}} : Answer{};
  };
  Scheduler s(p, d.clock, d.outputs());
  s.start({CheckKind::MonumentCAlignment, CheckKind::MonumentToolLength,
           CheckKind::MonumentPositioning});
  while (d.deliver_one(s)) {}
  ASSERT_EQ(s.state("m1"), MachineState::NeedsIntervention);
  EXPECT_EQ(s.command({"m1", "a", CheckKind::MonumentCAlignment, "operator:ann", 0, {}}), "");
  EXPECT_NE(
      s.command({"m1", "b", CheckKind::MonumentPositioning, "operator:ann", 0, {}}).find("is held"),
      std::string::npos);
  EXPECT_NE(s.command({"m1", "c", CheckKind::PartSetPoints, "operator:ann", 0, {}}).find("is held"),
            std::string::npos);
}

TEST(CalendarFlow, FixtureLoopCorrectsAndTheWeekIsDone) {
  PlantConfig p = plant({machine("m1", "F")});
  p.calendar->periods = {default_calendar_config().periods[1],
                         default_calendar_config().periods[2]};
  Driver d(utc("2026-01-05T00:00:00Z"));
  d.answer = [&](const CheckRequest& r) {
    if (r.kind == CheckKind::FixturePreCalibration)
      return Answer{Verdict::Fail, {"zero drift"}, true};
    return Answer{};
  };
  Scheduler s(p, d.clock, d.outputs());
  s.start({});
  d.run(s, utc("2026-01-07T00:00:00Z"));
  const auto monday = d.kinds_between(0, utc("2026-01-06T00:00:00Z"));
  EXPECT_EQ(monday, concat({{CheckKind::FixturePreCalibration, CheckKind::FixturePostCalibration},
                            kDaily}));
  const CheckRequest* pre = nullptr;
  const CheckRequest* post = nullptr;
  for (const auto& r : d.requests) {
    if (r.kind == CheckKind::FixturePreCalibration && !pre) pre = &r;
    if (r.kind == CheckKind::FixturePostCalibration && !post) post = &r;
  }
  ASSERT_TRUE(pre && post);
  EXPECT_EQ(post->verifies_correction_of, pre->request_id);
  EXPECT_EQ(find_value(post->parameters, "fixture_configuration")->value,
            find_value(pre->parameters, "fixture_configuration")->value);
  // The post-calibration's pass satisfied the week: Tuesday runs only the daily checks.
  EXPECT_EQ(d.kinds_between(utc("2026-01-06T00:00:00Z"), utc("2026-01-07T00:00:00Z")), kDaily);
}

TEST(CalendarFlow, ConfigurationRotationIsPerFixtureAndSurvivesRestarts) {
  PlantConfig p = plant({machine("m1", "F1"), machine("m2", "F2")});
  p.calendar->periods = {default_calendar_config().periods[1]};  // weekly only
  const std::string file = ::testing::TempDir() + "ncqual-sched-rotation.db";
  std::filesystem::remove(file);
  Driver d(utc("2026-01-05T00:00:00Z"));
  std::map<std::string, std::vector<int>> used;
  const auto record = [&]() {
    used.clear();
    for (const auto& r : d.requests) {
      if (r.kind == CheckKind::FixturePreCalibration) {
        used[r.machine_id].push_back(
            static_cast<int>(find_value(r.parameters, "fixture_configuration")->value));
      }
    }
  };
  // m2's fixture is checked once more by an operator in week 1, so the two rotations part.
  {
    auto state = storage::StateFile::open(file);
    Scheduler s(p, d.clock, d.outputs(), &state);
    s.start({});
    d.run(s, utc("2026-01-06T00:00:00Z"));
    EXPECT_EQ(s.command({"m2", "op-1", CheckKind::FixturePreCalibration, "operator:ann", 0, {}}),
              "");
    d.run(s, utc("2026-01-20T00:00:00Z"));
  }
  // Restarted three times over ten more weeks, each time from the file.
  for (const char* until :
       {"2026-02-10T00:00:00Z", "2026-03-03T00:00:00Z", "2026-03-31T00:00:00Z"}) {
    auto state = storage::StateFile::open(file);
    Scheduler s(p, d.clock, d.outputs(), &state);
    s.start({});
    d.run(s, utc(until));
  }
  record();
  // Mondays 5 January .. 30 March: 13 weeks; m2 once more.
  ASSERT_EQ(used["m1"].size(), 13u);
  ASSERT_EQ(used["m2"].size(), 14u);
  for (std::size_t i = 0; i < used["m1"].size(); ++i)
    EXPECT_EQ(used["m1"][i], static_cast<int>(i % 10)) << i;
  for (std::size_t i = 0; i < used["m2"].size(); ++i)
    EXPECT_EQ(used["m2"][i], static_cast<int>(i % 10)) << i;
}

TEST(CalendarFlow, ACheckWithoutResultIsRetriedThenReportedNeverDropped) {
  PlantConfig p = plant({machine("m1")});
  p.calendar->periods = {default_calendar_config().periods[2]};
  Driver d(utc("2026-01-05T00:00:00Z"));
  d.answer = [&](const CheckRequest& r) {
    Answer a;
    a.lost = r.kind == CheckKind::MonumentPositioning;  // the acquisition never answers check 3
    return a;
  };
  Scheduler s(p, d.clock, d.outputs());
  s.start({});
  d.run(s, utc("2026-01-05T20:00:00Z"));
  std::vector<CheckRequest> check3;
  for (const auto& r : d.requests) {
    if (r.kind == CheckKind::MonumentPositioning) check3.push_back(r);
  }
  // Three attempts (retries: 2), an hour apart (check_timeout_min: 60), each under its own id.
  ASSERT_EQ(check3.size(), 3u);
  EXPECT_EQ(check3[1].request_id, check3[0].request_id + "-r2");
  EXPECT_EQ(check3[2].request_id, check3[0].request_id + "-r3");
  EXPECT_EQ(check3[1].attempt, 2);
  EXPECT_EQ(check3[1].time_ns - check3[0].time_ns, kHour);
  EXPECT_EQ(check3[2].time_ns - check3[1].time_ns, kHour);
  EXPECT_EQ(s.state("m1"), MachineState::NeedsIntervention);
  const std::string detail = d.statuses.back().detail;
  EXPECT_NE(detail.find("monument_positioning MISSED"), std::string::npos) << detail;
  EXPECT_NE(detail.find(check3[2].request_id), std::string::npos) << detail;
  // Check 4 never ran: the missed check holds the machine.
  EXPECT_TRUE(std::none_of(d.requests.begin(), d.requests.end(), [](const CheckRequest& r) {
    return r.kind == CheckKind::MonumentCRotation;
  }));
}

TEST(CalendarFlow, ALateAnswerToAnEarlierAttemptCompletesTheCheck) {
  PlantConfig p = plant({machine("m1")});
  p.calendar->periods = {default_calendar_config().periods[2]};
  Driver d(utc("2026-01-05T00:00:00Z"));
  std::optional<CheckRequest> first_attempt;
  d.answer = [&](const CheckRequest& r) {
    Answer a;
    if (r.kind == CheckKind::MonumentPositioning && r.attempt == 1) {
      first_attempt = r;
      a.lost = true;
    }
    return a;
  };
  Scheduler s(p, d.clock, d.outputs());
  s.start({});
  d.run(s, utc("2026-01-05T09:00:00Z"));  // the retry went out at about 07:20 and was answered
  ASSERT_TRUE(first_attempt);
  // The first attempt's result arrives after all: a duplicate of a completed check, ignored.
  CheckResult late;
  late.machine_id = "m1";
  late.request_id = first_attempt->request_id;
  late.kind = first_attempt->kind;
  late.verdict = Verdict::Fail;
  late.time_ns = d.clock.now_ns();
  s.result(late);
  EXPECT_NE(s.state("m1"), MachineState::NeedsIntervention);
  EXPECT_EQ(d.kinds_between(0, utc("2026-01-06T00:00:00Z")).back(), CheckKind::MonumentCRotation);
}

TEST(CalendarFlow, PartsRunUntilTheEndOfTheShiftAfterThePeriodChecks) {
  PlantConfig p = plant({machine("m1")});
  p.calendar->periods = {default_calendar_config().periods[2]};
  p.calendar->parts.cycle_min = 110;  // 10 min set points (the driver) + 100 min machining
  Driver d(utc("2026-01-05T00:00:00Z"));
  Scheduler s(p, d.clock, d.outputs());
  s.start({});
  d.run(s, utc("2026-01-05T23:00:00Z"));
  std::vector<std::int64_t> parts;
  for (const auto& r : d.requests) {
    if (r.kind == CheckKind::PartSetPoints) parts.push_back(r.time_ns);
  }
  // Early shift: daily checks 06:00-06:40, parts at 06:40, then every 120 min (set points 10 min
  // + cycle 110) while the shift lasts: 06:40 08:40 10:40 12:40; late shift: 14:00 16:00 18:00
  // 20:00 (no daily checks: already done today).
  const std::vector<std::int64_t> expected = {
      utc("2026-01-05T06:40:00Z"), utc("2026-01-05T08:40:00Z"), utc("2026-01-05T10:40:00Z"),
      utc("2026-01-05T12:40:00Z"), utc("2026-01-05T14:00:00Z"), utc("2026-01-05T16:00:00Z"),
      utc("2026-01-05T18:00:00Z"), utc("2026-01-05T20:00:00Z")};
  EXPECT_EQ(parts, expected);
}

// Restarts at random points (after a random number of deliveries) end with exactly the requests
// of an uninterrupted run: same ids, kinds, times and parameters.
TEST(CalendarFlow, RestartsAtRandomPointsChangeNothing) {
  const PlantConfig p = plant({machine("m1", "F1"), machine("m2", "F2")});
  const std::int64_t start = utc("2026-01-26T00:00:00Z");
  const std::int64_t until = utc("2026-02-17T00:00:00Z");
  const auto answer = [](const CheckRequest& r) {
    Answer a;
    if (r.kind == CheckKind::FixturePreCalibration) a = Answer{Verdict::Fail, {"drift"}, true};
    return a;
  };
  const auto signature = [](const std::vector<CheckRequest>& requests) {
    std::vector<std::string> out;
    std::set<std::string> seen;
    for (const auto& r : requests) {
      if (!seen.insert(r.request_id).second) continue;  // a resend after a restart
      std::string params;
      for (const auto& v : r.parameters) params += v.name + "=" + std::to_string(v.value) + ";";
      out.push_back(r.request_id + "|" + std::string(to_string(r.kind)) + "|" +
                    std::to_string(r.time_ns) + "|" + params + "|" + r.verifies_correction_of);
    }
    // Each machine's sequence is fixed; how two machines' requests interleave is not.
    std::sort(out.begin(), out.end());
    return out;
  };

  Driver plain(start);
  plain.answer = answer;
  {
    Scheduler s(p, plain.clock, plain.outputs());
    s.start({});
    plain.run(s, until);
  }
  ASSERT_GT(plain.requests.size(), 100u);

  for (int seed = 1; seed <= 3; ++seed) {
    const std::string file =
        ::testing::TempDir() + "ncqual-sched-restarts-" + std::to_string(seed) + ".db";
    std::filesystem::remove(file);
    std::mt19937 rng(static_cast<unsigned>(seed));
    Driver d(start);
    d.answer = answer;
    int restarts = 0;
    bool more = true;
    while (more) {
      auto state = storage::StateFile::open(file);
      // Like the process: the clock comes back from the state file.
      if (const auto saved = saved_clock_ns(state)) d.clock.set_ns(*saved);
      // Whatever the dead scheduler's outputs still had on the wire is lost with it.
      d.inbox.clear();
      Scheduler s(p, d.clock, d.outputs(), &state);
      s.start({});
      more = d.run_for(s, until, std::uniform_int_distribution<int>(1, 30)(rng));
      ++restarts;
    }
    EXPECT_GT(restarts, 5);
    EXPECT_EQ(signature(d.requests), signature(plain.requests)) << "seed " << seed;
  }
}

// With a speed, the clock never runs ahead of it: whenever a request is issued, the simulated
// clock is no further from the start than the wall time (here a fake clock that moves only by
// what the run waits) allows; checks that follow each other directly run as fast as they come
// back. The run makes exactly the decisions of an unpaced one.
TEST(CalendarFlow, ASpeedPacesTheClockWithoutChangingAnyDecision) {
  const PlantConfig p = plant({machine("m1", "F")});
  const std::int64_t start = utc("2026-01-05T00:00:00Z");
  const std::int64_t until = utc("2026-01-08T00:00:00Z");
  Driver unpaced(start);
  {
    Scheduler s(p, unpaced.clock, unpaced.outputs());
    s.start({});
    unpaced.run(s, until);
  }

  constexpr double kSpeed = 3600;  // a simulated hour per wall second
  Driver d(start);
  std::chrono::steady_clock::time_point wall{};
  std::vector<std::pair<std::int64_t, double>> issued;  // simulated clock, wall seconds
  Scheduler::Outputs out = d.outputs();
  out.request = [&, inner = out.request](const CheckRequest& r) {
    issued.emplace_back(d.clock.now_ns(),
                        std::chrono::duration<double>(wall.time_since_epoch()).count());
    inner(r);
  };
  Scheduler s(p, d.clock, out);
  s.start({});
  SimulatedRunOptions options;
  options.until_ns = until;
  options.stall = std::chrono::milliseconds(0);
  options.operator_patience = std::chrono::milliseconds(0);
  options.give_up_after_idle_waits = 3;
  options.speed = kSpeed;
  options.wall_now = [&] { return wall; };
  std::chrono::milliseconds waited{0};
  run_simulated(s, d.clock,
                {[&](std::chrono::milliseconds patience) {
                   wall += patience;  // the fake wall clock moves by what is waited
                   waited += patience;
                   return d.deliver_one(s);
                 },
                 [] { return false; }},
                options);

  ASSERT_EQ(d.requests.size(), unpaced.requests.size());
  for (std::size_t k = 0; k < d.requests.size(); ++k) {
    EXPECT_EQ(d.requests[k].request_id, unpaced.requests[k].request_id);
    EXPECT_EQ(d.requests[k].time_ns, unpaced.requests[k].time_ns);
  }
  ASSERT_FALSE(issued.empty());
  for (const auto& [t, wall_s] : issued) {
    EXPECT_GE(wall_s + 1e-3, static_cast<double>(t - start) / 1e9 / kSpeed)
        << "the clock at " << (t - start) / kMinute << " simulated min ran ahead";
  }
  // The last jump is on the third day: about 60 wall seconds at an hour per second, all waited.
  const double last_s = static_cast<double>(d.clock.now_ns() - start) / 1e9 / kSpeed;
  EXPECT_GT(last_s, 48.0);
  EXPECT_NEAR(std::chrono::duration<double>(waited).count(), last_s, 2.0);
}

}  // namespace
}  // namespace ncqual::scheduler
