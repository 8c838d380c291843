// SPDX-License-Identifier: Apache-2.0
// The scheduler's state documents (scheduler.hpp to_json / machine_run_from_json): a document as
// the previous version wrote it still loads, every field survives a round trip, and what cannot
// be read is refused by name.
#include "ncqual/scheduler/scheduler.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual::scheduler {
namespace {

// Written by ncqual before the documents were declared with nlohmann's macros (no "hold" key
// when there is none, and a "recent" list that this version no longer keeps: ignored).
constexpr const char* kOlderDocument = R"({"detail":"","interventions":["iv-1"],
  "last_pass_ns":{"monument_positioning":1700000000000000000,"fixture_precal":1690000000000000000},
  "local_time_ns":1700000000500000000,"part_step":2,
  "pending":[{"in_sequence":true,"issued_ns":1700000001000000000,"kind":"monument_c_rotation",
    "parameters":[{"name":"fixture_configuration","unit":"","value":3.0}],"rearmed":false,
    "request_ids":["pm1-a1","pm1-a2"],"requested_by":"scheduler",
    "verifies_correction_of":""}],
  "queue":["monument_tool_length","monument_positioning"],
  "recent":[{"attempt":2,"kind":"monument_c_rotation","parameters":[],"request_id":"pm1-a2",
    "requested_by":"scheduler","time_ns":1700000001000000000,"verifies_correction_of":""}],
  "sequence":41,"state":"QUALIFIED"})";

TEST(StateDocument, ADocumentOfThePreviousVersionLoads) {
  const MachineRun run = machine_run_from_json(kOlderDocument);
  ASSERT_EQ(run.last_pass_ns.size(), 2u);
  EXPECT_EQ(run.last_pass_ns.at(CheckKind::MonumentPositioning), 1700000000000000000);
  EXPECT_EQ(run.last_pass_ns.at(CheckKind::FixturePreCalibration), 1690000000000000000);
  ASSERT_EQ(run.queue.size(), 2u);
  EXPECT_EQ(run.queue[0], CheckKind::MonumentToolLength);
  ASSERT_EQ(run.pending.size(), 1u);
  EXPECT_EQ(run.pending[0].request_ids.back(), "pm1-a2");
  EXPECT_EQ(run.pending[0].kind, CheckKind::MonumentCRotation);
  ASSERT_EQ(run.pending[0].parameters.size(), 1u);
  EXPECT_EQ(run.pending[0].parameters[0].value, 3.0);
  EXPECT_FALSE(run.hold.has_value());
  EXPECT_FALSE(run.planned_shift_ns.has_value());
  EXPECT_EQ(run.part_step, 2u);
  EXPECT_EQ(run.sequence, 41u);
  EXPECT_EQ(run.state, MachineState::Qualified);
  EXPECT_TRUE(run.orders.empty());  // no "orders" key before they were remembered
}

TEST(StateDocument, EveryFieldSurvivesARoundTrip) {
  MachineRun run;
  run.last_pass_ns[CheckKind::GlobalGrid] = 5;
  run.queue = {CheckKind::CircleXY};
  run.pending.push_back({{"r1"},
                         CheckKind::FixturePostCalibration,
                         "operator:ann",
                         7,
                         {{"offset", -0.25, "mm"}},
                         "pre-1",
                         false,
                         true});
  run.hold = Hold{CheckKind::FixturePostCalibration,
                  "r1",
                  "FAIL: fixture_dx_mm",
                  CheckKind::FixturePreCalibration,
                  {{"fixture_configuration", 1, ""}},
                  false};
  run.planned_shift_ns = 11;
  run.next_part_ns = 13;
  run.part_step = 1;
  run.local_time_ns = 17;
  run.sequence = 19;
  run.interventions = {"iv-9"};
  run.orders = {"op-pm1-1"};
  run.judged = {{"r0", CheckKind::MonumentPositioning, {{"part", 3, ""}}, false}};
  run.conflicts = {"conflict/ncqual/MeasurementSet/r0/ab12"};
  run.state = MachineState::NeedsIntervention;
  run.detail = "held";

  const MachineRun back = machine_run_from_json(to_json(run));
  EXPECT_EQ(to_json(back), to_json(run));
  ASSERT_TRUE(back.hold.has_value());
  EXPECT_EQ(back.hold->rerun, CheckKind::FixturePreCalibration);
  EXPECT_EQ(back.hold->parameters.at(0).name, "fixture_configuration");
  EXPECT_EQ(back.next_part_ns, 13);
  EXPECT_TRUE(back.pending.at(0).rearmed);
  EXPECT_EQ(back.state, MachineState::NeedsIntervention);
  EXPECT_EQ(back.orders, std::vector<std::string>{"op-pm1-1"});
  ASSERT_EQ(back.judged.size(), 1u);
  EXPECT_EQ(back.judged[0].kind, CheckKind::MonumentPositioning);
  EXPECT_FALSE(back.judged[0].in_sequence);
  EXPECT_EQ(back.conflicts, run.conflicts);
}

std::string refusal(const std::string& text) {
  try {
    machine_run_from_json(text);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(StateDocument, WhatCannotBeReadIsRefusedByName) {
  EXPECT_NE(refusal(R"({"queue":["monument_positoning"]})").find("'monument_positoning'"),
            std::string::npos);
  EXPECT_NE(refusal(R"({"state":"HAPPY"})").find("'HAPPY'"), std::string::npos);
  EXPECT_NE(refusal(R"({"pending":[{"kind":"global_grid","request_ids":[]}]})")
                .find("a pending check without request id"),
            std::string::npos);
}

}  // namespace
}  // namespace ncqual::scheduler
