#include "scheduler.hpp"

#include <gtest/gtest.h>

namespace ncqual::scheduler {
namespace {

struct Recorder {
  std::vector<CheckRequest> requests;
  std::vector<MachineStatus> statuses;
  Scheduler::Outputs outputs() {
    return {[this](const CheckRequest& r) { requests.push_back(r); },
            [this](const MachineStatus& s) { statuses.push_back(s); }};
  }
};

PlantConfig two_machines() {
  PlantConfig p;
  p.plant = "t";
  p.machines.resize(2);
  p.machines[0].machine_id = "m1";
  p.machines[1].machine_id = "m2";
  return p;
}

CheckResult result_of(const CheckRequest& r, Verdict v, std::vector<std::string> causes = {}) {
  CheckResult res;
  res.machine_id = r.machine_id;
  res.request_id = r.request_id;
  res.kind = r.kind;
  res.verdict = v;
  res.likely_causes = std::move(causes);
  return res;
}

TEST(Scheduler, RunsTheCycleInOrderAndAFailureStopsTheRest) {
  const PlantConfig plant = two_machines();
  SimulatedClock clock(1'000'000'000);
  Recorder rec;
  Scheduler s(plant, clock, rec.outputs());
  s.start_cycle({CheckKind::MonumentCAlignment, CheckKind::MonumentToolLength,
                 CheckKind::MonumentPositioning});
  ASSERT_EQ(rec.requests.size(), 2u);  // the first check of each machine, nothing more yet
  EXPECT_EQ(rec.requests[0].kind, CheckKind::MonumentCAlignment);
  EXPECT_NE(rec.requests[0].request_id, rec.requests[1].request_id);

  // m1 passes check 1: check 2 follows. m2 fails check 1: nothing follows, intervention needed.
  const CheckRequest m1_first = rec.requests[0].machine_id == "m1" ? rec.requests[0] : rec.requests[1];
  const CheckRequest m2_first = rec.requests[0].machine_id == "m2" ? rec.requests[0] : rec.requests[1];
  s.result(result_of(m1_first, Verdict::Pass));
  ASSERT_EQ(rec.requests.size(), 3u);
  EXPECT_EQ(rec.requests[2].kind, CheckKind::MonumentToolLength);
  s.result(result_of(m2_first, Verdict::Fail, {"bent stylus"}));
  EXPECT_EQ(rec.requests.size(), 3u);
  EXPECT_EQ(s.state("m2"), MachineState::NeedsIntervention);
  EXPECT_NE(rec.statuses.back().detail.find("bent stylus"), std::string::npos);

  // A duplicate result (DDS redelivery) changes nothing.
  s.result(result_of(m1_first, Verdict::Pass));
  EXPECT_EQ(rec.requests.size(), 3u);

  s.result(result_of(rec.requests[2], Verdict::Pass));
  s.result(result_of(rec.requests[3], Verdict::Pass));
  EXPECT_EQ(s.state("m1"), MachineState::Qualified);
  EXPECT_EQ(rec.requests.size(), 4u);
}

TEST(Scheduler, OperatorCommandsAreValidated) {
  const PlantConfig plant = two_machines();
  SimulatedClock clock;
  Recorder rec;
  Scheduler s(plant, clock, rec.outputs());
  EXPECT_NE(s.command({"nope", "r1", CheckKind::MonumentPositioning, "op", 0}).find("'nope'"),
            std::string::npos);
  EXPECT_NE(s.command({"m1", "", CheckKind::MonumentPositioning, "op", 0}).find("request_id"),
            std::string::npos);
  EXPECT_TRUE(rec.requests.empty());
  EXPECT_EQ(s.command({"m1", "r1", CheckKind::MonumentPositioning, "operator:ann", 0}), "");
  EXPECT_EQ(s.command({"m1", "r1", CheckKind::MonumentPositioning, "operator:ann", 0}), "");
  ASSERT_EQ(rec.requests.size(), 1u);  // the resent order is not a second request
  EXPECT_EQ(rec.requests[0].request_id, "r1");
  EXPECT_EQ(rec.requests[0].requested_by, "operator:ann");
  EXPECT_EQ(s.state("m1"), MachineState::Checking);
}

}  // namespace
}  // namespace ncqual::scheduler
