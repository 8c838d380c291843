// SPDX-License-Identifier: Apache-2.0
// The solver service's decisions (services/solver/core/include/ncqual/solver_service/
// solved_sets.hpp) on real state files: a set is solved once, a resend is answered from the
// record across a restart, other content under a solved request is a conflict naming both writers,
// a set written for another machine is refused, and a save that fails (writes beyond a file size
// limit, as on a full disk) leaves the set unsolved, so the resend that follows solves it.
#include "ncqual/solver_service/solved_sets.hpp"

#include "storage_test_support.hpp"

#include <gtest/gtest.h>

namespace ncqual::solver_service {
namespace {

using storage::testing::make_measurement_set;
using storage::testing::TempDir;

// The outbox entry of an answer, as the executable would queue it (payload bytes are opaque
// here).
storage::OutboxEntry answer_entry(const std::string& request_id, const std::string& hash) {
  storage::OutboxEntry e;
  e.topic = "ncqual/CheckResult";
  e.sample_id = request_id;
  e.content_hash = hash;
  e.machine_id = "M1";
  e.payload = {1, 2, 3};
  e.awaiting = {"historian", "scheduler"};
  e.queued_ns = 5;
  return e;
}

// A set received in its own machine's partition.
ReceivedSet received(const MeasurementSet& set, const std::string& hash,
                     const std::string& writer) {
  return {set, hash, writer, false, ""};
}

// A solver's state file in a fresh directory and the solved sets kept in it, as the service opens
// them.
struct SolverState {
  TempDir dir;
  storage::StateFile file = storage::StateFile::open(dir.file("solver.db"));
  SolvedSets solved{file};
};

bool queued(storage::StateFile& file, const std::string& sample_id) {
  for (const auto& e : file.outbox_index()) {
    if (e.sample_id == sample_id) return true;
  }
  return false;
}

TEST(SolvedSets, ASetIsSolvedOnceAndAResendIsAnsweredFromTheRecordAfterARestart) {
  TempDir dir;
  const MeasurementSet set = make_measurement_set("R1");
  {
    auto file = storage::StateFile::open(dir.file("solver.db"));
    SolvedSets solved(file);
    EXPECT_EQ(decide(solved, received(set, "hash-a", "guid-1")).action, SetAction::Solve);
    solved.save(set, "hash-a", "guid-1", {answer_entry("R1", "res-1")});
    const auto again = decide(solved, received(set, "hash-a", "guid-1"));
    EXPECT_EQ(again.action, SetAction::AcknowledgeAgain);
    EXPECT_EQ(again.detail, "already solved");
  }
  // The solver killed and started again: the record and the queued answer are both there.
  auto file = storage::StateFile::open(dir.file("solver.db"));
  SolvedSets solved(file);
  ASSERT_NE(solved.find("R1"), nullptr);
  EXPECT_EQ(solved.find("R1")->content_hash, "hash-a");
  EXPECT_EQ(solved.find("R1")->writer, "guid-1");
  EXPECT_EQ(solved.find("R1")->time_ns, set.time_ns);
  EXPECT_TRUE(queued(file, "R1"));
  // From another writer with the same content (a redundant acquisition): still the same set.
  EXPECT_EQ(decide(solved, received(set, "hash-a", "guid-2")).action, SetAction::AcknowledgeAgain);
  EXPECT_EQ(decide(solved, received(make_measurement_set("R2"), "hash-b", "guid-1")).action,
            SetAction::Solve);
}

TEST(SolvedSets, OtherContentUnderASolvedRequestIsAConflictNamingBothWritersAndContents) {
  SolverState state;
  const MeasurementSet set = make_measurement_set("R7");
  state.solved.save(set, "aaaaaaaaaaaaXXXX", "guid-first", {});
  const auto decision = decide(state.solved, received(set, "bbbbbbbbbbbbYYYY", "guid-second"));
  EXPECT_EQ(decision.action, SetAction::Conflict);
  EXPECT_EQ(decision.detail,
            "conflicting measurements of R7: solved from writer guid-first's set (content "
            "aaaaaaaaaaaa), this one from writer guid-second (content bbbbbbbbbbbb) differs; not "
            "solved again");
  // Not solved again: the record still names the first.
  EXPECT_EQ(state.solved.find("R7")->writer, "guid-first");
}

TEST(SolvedSets, ASetSolvedByAVersionThatKeptNoHashIsNotSolvedAgain) {
  TempDir dir;
  auto file = storage::StateFile::open(dir.file("solver.db"));
  file.save({{"solved/R3", R"({"time_ns": 42})"}, {"solved/bad", "{not json"}, {"other", "{}"}});
  SolvedSets solved(file);
  EXPECT_EQ(solved.size(), 1u) << "the unreadable document and the foreign key are ignored";
  EXPECT_EQ(decide(solved, received(make_measurement_set("R3"), "any", "guid")).action,
            SetAction::AcknowledgeAgain);
}

TEST(SolvedSets, ASetWrittenForAnotherMachineIsRefusedWithItsReasonEvenIfSolved) {
  SolverState state;
  const MeasurementSet set = make_measurement_set("R1");
  state.solved.save(set, "h", "g", {});
  const auto decision = decide(
      state.solved, {set, "h", "g", true, "names machine 'M1' but came in partition of 'M2'"});
  EXPECT_EQ(decision.action, SetAction::Refuse);
  EXPECT_EQ(decision.detail, "names machine 'M1' but came in partition of 'M2'");
}

// A full disk (storage::testing::FullDisk: writes past a file size limit fail).
TEST(SolvedSets, ASaveThatFailsLeavesTheSetUnsolvedAndItsAnswerUnqueued) {
  SolverState state;
  const MeasurementSet set = make_measurement_set("R9");
  bool threw = false;
  {
    const storage::testing::FullDisk full;
    try {
      state.solved.save(set, "hash-9", "guid", {answer_entry("R9", "res-9")});
    } catch (const storage::StorageError&) {
      threw = true;
    }
  }

  EXPECT_TRUE(threw);
  EXPECT_EQ(state.solved.find("R9"), nullptr);
  EXPECT_EQ(decide(state.solved, received(set, "hash-9", "guid")).action, SetAction::Solve)
      << "the resend is solved";
  EXPECT_FALSE(queued(state.file, "R9"));
  // Once the disk takes writes again, the resend is solved and saved.
  state.solved.save(set, "hash-9", "guid", {answer_entry("R9", "res-9")});
  EXPECT_TRUE(queued(state.file, "R9"));
  auto reopened = storage::StateFile::open(state.dir.file("solver.db"));
  EXPECT_NE(SolvedSets(reopened).find("R9"), nullptr);
}

TEST(SolvedSets, TheOldestBeyondTheBoundAreForgottenInTheSameTransaction) {
  TempDir dir;
  {
    auto file = storage::StateFile::open(dir.file("solver.db"));
    SolvedSets solved(file, 3);
    for (int i = 0; i < 5; ++i) {
      solved.save(make_measurement_set("R" + std::to_string(i), "M1", 100 + i), "h", "g", {});
    }
    EXPECT_EQ(solved.size(), 3u);
    EXPECT_EQ(solved.find("R1"), nullptr);
    EXPECT_NE(solved.find("R2"), nullptr);
  }
  auto file = storage::StateFile::open(dir.file("solver.db"));
  std::size_t documents = 0;
  for (const auto& [key, doc] : file.load()) documents += key.rfind("solved/", 0) == 0 ? 1 : 0;
  EXPECT_EQ(documents, 3u);
  SolvedSets solved(file, 3);
  EXPECT_EQ(solved.find("R0"), nullptr);
  EXPECT_NE(solved.find("R4"), nullptr);
}

TEST(Answer, AMalformedSetIsAnsweredInvalidWithItsReasonAndTheSoftwareThatSaidSo) {
  const MeasurementSet set = make_measurement_set("R1");
  const PlantConfig plant;
  const CheckResult r = answer(set, "touches[2].axes: not a number", plant, 77, "ncqual x");
  EXPECT_EQ(r.verdict, Verdict::Invalid);
  EXPECT_EQ(r.reason, "touches[2].axes: not a number");
  EXPECT_EQ(r.request_id, "R1");
  EXPECT_EQ(r.machine_id, "M1");
  EXPECT_EQ(r.kind, set.kind);
  EXPECT_EQ(r.time_ns, 77);
  EXPECT_EQ(r.produced_by, "ncqual x");
  EXPECT_FALSE(compensation_of(r).has_value());
  EXPECT_EQ(r.origin, DataOrigin::Unknown);  // the set did not say
  // A malformed simulated set stays simulated in its INVALID result, a measured one measured.
  for (const DataOrigin origin : {DataOrigin::Simulated, DataOrigin::Measured}) {
    MeasurementSet said = set;
    said.origin = origin;
    EXPECT_EQ(answer(said, "touches[2].axes: not a number", plant, 77, "ncqual x").origin, origin);
    EXPECT_EQ(answer(said, "", plant, 77, "ncqual x").origin, origin);  // the solver's INVALID
  }
}

TEST(Answer, AWellFormedSetIsTheSolversVerdictStampedWithTheSoftware) {
  // A machine the plant does not configure: the solver's INVALID, with its reason.
  const PlantConfig plant;
  const CheckResult r = answer(make_measurement_set("R1", "M9"), "", plant, 5, "ncqual y");
  EXPECT_EQ(r.verdict, Verdict::Invalid);
  EXPECT_NE(r.reason.find("M9"), std::string::npos) << r.reason;
  EXPECT_EQ(r.produced_by, "ncqual y");
}

TEST(Answer, ACorrectionIsPublishedAsTheMachinesCompensation) {
  CheckResult r;
  r.machine_id = "M1";
  r.request_id = "R1";
  r.time_ns = 9;
  r.correction = Correction{"machine:work_offset", {NamedValue{"dx_mm", -0.01, "mm"}}};
  const auto c = compensation_of(r);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->machine_id, "M1");
  EXPECT_EQ(c->request_id, "R1");
  EXPECT_EQ(c->time_ns, 9);
  EXPECT_EQ(c->correction.target, "machine:work_offset");
}

}  // namespace
}  // namespace ncqual::solver_service
