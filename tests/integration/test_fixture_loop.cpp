// SPDX-License-Identifier: Apache-2.0
// The weekly fixture loop across real processes: the scheduler's pre-calibration fails, the
// solver publishes the deltas as zero offsets (Compensation), the acquisition service (standing
// for the fixture's control unit) applies them before it measures the post-calibration the
// scheduler orders to verify them. A fixture whose zeros drifted is then back in tolerance; a
// fixture whose pogos lean is not, and the machine is held with the misalignment named.
#include "harness.hpp"

#include <gtest/gtest.h>

namespace ncqual::testing {
namespace {

std::string fixture_scenario(const std::string& machine_id, const std::string& fixture_errors) {
  return "extends: " + std::string(NCQUAL_SOURCE_DIR) + "/deploy/machines/pm1.yaml\n" +
         "machine_id: " + machine_id + "\n" + "simulator:\n  fixture:\n" + fixture_errors;
}

std::optional<storage::CheckRecord> newest(storage::Database& db, const std::string& machine,
                                           CheckKind kind) {
  storage::HistoryQuery q;
  q.machine_id = machine;
  q.kind = kind;
  auto records = db.history(q);
  if (records.empty()) return std::nullopt;
  return records.front();
}

bool complete(const std::optional<storage::CheckRecord>& r) {
  return r && r->request && r->measurement && r->result;
}

TEST(FixtureLoop, ZeroOffsetsFixADriftedFixtureButNotALeaningOne) {
  Plant plant("fixture", TestDomain::FixtureLoop);
  plant.add_machine("pm-drift",
                    fixture_scenario("pm-drift",
                                     "    column_x: {offset_mm: 0.040}\n"
                                     "    pogo_offsets_mm: {C2R2: [0, 0.03, -0.03]}\n"));
  plant.add_machine("pm-lean", fixture_scenario("pm-lean",
                                                "    column_x: {offset_mm: 0.040}\n"
                                                "    pogo_z: {misalignment_x_arcsec: 40}\n"));
  plant.write_plant("[fixture_precal]");
  plant.start("historian");
  plant.start("solver");
  plant.start("acquisition", {"--machine", "pm-drift"});
  plant.start("acquisition", {"--machine", "pm-lean"});
  plant.start("scheduler");

  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) {
    for (const char* id : {"pm-drift", "pm-lean"}) {
      if (!complete(newest(db, id, CheckKind::FixturePostCalibration))) return false;
      const auto status = db.latest_status(id);
      if (!status || status->state == MachineState::Checking) return false;
    }
    return true;
  })) << plant.log("acquisition")
      << plant.log("scheduler") << plant.log("solver");

  auto db = storage::Database::open_readonly(plant.db_path());
  for (const char* id : {"pm-drift", "pm-lean"}) {
    SCOPED_TRACE(id);
    const auto pre = newest(db, id, CheckKind::FixturePreCalibration);
    ASSERT_TRUE(complete(pre));
    EXPECT_EQ(pre->result->verdict, Verdict::Fail);
    ASSERT_TRUE(pre->result->correction.has_value());
    EXPECT_EQ(pre->result->correction->target, "fixture:UHF1");
    EXPECT_FALSE(pre->result->correction->offsets.empty());
    ASSERT_NE(find_value(pre->request->parameters, "fixture_configuration"), nullptr);
    // The zero offsets went out as a Compensation and were stored.
    const auto compensations = db.compensations(id);
    ASSERT_EQ(compensations.size(), 1u);
    EXPECT_EQ(compensations.front().request_id, pre->request_id);

    const auto post = newest(db, id, CheckKind::FixturePostCalibration);
    ASSERT_TRUE(complete(post));
    EXPECT_EQ(post->request->verifies_correction_of, pre->request_id);
    EXPECT_EQ(post->request->requested_by, "scheduler");
  }
  const auto drift = newest(db, "pm-drift", CheckKind::FixturePostCalibration);
  EXPECT_EQ(drift->result->verdict, Verdict::Pass) << drift->result->reason;
  EXPECT_EQ(db.latest_status("pm-drift")->state, MachineState::Qualified);

  const auto lean = newest(db, "pm-lean", CheckKind::FixturePostCalibration);
  EXPECT_EQ(lean->result->verdict, Verdict::Fail);
  ASSERT_FALSE(lean->result->likely_causes.empty());
  EXPECT_EQ(lean->result->likely_causes.front(), "fixture axes misaligned with the machine axes");
  const auto held = db.latest_status("pm-lean");
  EXPECT_EQ(held->state, MachineState::NeedsIntervention);
  EXPECT_NE(held->detail.find("misaligned"), std::string::npos) << held->detail;
}

}  // namespace
}  // namespace ncqual::testing
