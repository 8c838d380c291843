// SPDX-License-Identifier: Apache-2.0
// Wire contracts across real processes (docs/architecture.md, "Changing the wire contract"): a
// service of the previous contract in a plant of the current one. It is stood in for by a
// participant that writes contract 1's layout of a result on its topic with the durable QoS, as
// ncqual's solver did before contract 2: the same type name, topic name and bytes.
#include "harness.hpp"
#include "test_participant.hpp"

#include "ncqual/dds/acknowledged_send.hpp"
#include "ncqual/dds/convert.hpp"
#include "ncqual/dds/endpoint.hpp"
#include "ncqual/dds/serialized.hpp"
#include "ncqual/dds/topics.hpp"

#include <gtest/gtest.h>

namespace ncqual::testing {
namespace {

// The last heartbeat of `service` in the historian, if any.
std::optional<Heartbeat> last_beat(storage::Database& db, const std::string& service) {
  std::optional<Heartbeat> found;
  for (const auto& h : db.services()) {
    if (h.service == service && h.state == "running") found = h;
  }
  return found;
}

TEST(WireContract, AnOlderSolversResultIsStoredAndEveryServiceNamesItsContract) {
  Plant plant("wire-contract", TestDomain::WireContract);
  plant.add_machine("pm1", machine_yaml("pm1", "    machine_shift_mm: [0, 0, 0]\n"));
  plant.write_plant("[]");
  plant.start("historian");
  plant.start("solver");

  CheckResult result;
  result.machine_id = "pm1";
  result.request_id = "pm1-monument_positioning-older";
  result.kind = CheckKind::MonumentPositioning;
  result.verdict = Verdict::Pass;
  result.metrics = {{"center_dx_mm", 0.004, "mm", -0.025, 0.025, true}};
  result.time_ns = WallClock().now_ns();
  result.produced_by = "ncqual-solver 0.1.0 (before wire contract 2)";
  {
    ncqual::dds::Participant older(test_participant(plant, "ncqual-solver-contract-1"));
    ncqual::dds::Writer<ncqual::dds::CheckResultContract1Topic> results(older);
    const auto answer = ncqual::dds::send_acknowledged(older, results, result, {roles::kHistorian},
                                                       std::chrono::seconds(30));
    // The historian answers for the bytes the older solver sent (their hash is what its outbox
    // awaits), so that its outbox lets the result go.
    ASSERT_TRUE(answer.silent.empty()) << plant.log("historian");
    const auto ack = answer.answers.at(roles::kHistorian);
    EXPECT_TRUE(ack.outcome == AckOutcome::Stored || ack.outcome == AckOutcome::Duplicate)
        << to_string(ack.outcome);
    EXPECT_EQ(ack.topic, "ncqual/CheckResult");
    EXPECT_EQ(ack.content_hash, ncqual::dds::sha256_hex(
                                    ncqual::dds::serialize<ncqual::dds::CheckResultContract1Topic>(
                                        ncqual::dds::to_wire_contract1(result))));

    // Stored as it was judged.
    ASSERT_TRUE(plant.wait_for_db([&](storage::Database& db) {
      const auto record = db.find_check(result.request_id);
      return record && record->result.has_value();
    })) << plant.log("historian");
    auto db = storage::Database::open_readonly(plant.db_path());
    const auto record = db.find_check(result.request_id);
    EXPECT_EQ(record->result->verdict, Verdict::Pass);
    EXPECT_EQ(record->result->produced_by, result.produced_by);
    EXPECT_EQ(record->result->origin, DataOrigin::Unknown);

    // The plant says it speaks two contracts, naming both, in the heartbeats `ncqual status`
    // shows: the historian's, which stores what the older one writes, and the solver's, which
    // shares no changed topic with it but hears it in discovery.
    for (const std::string service : {"historian", "solver"}) {
      std::string detail;
      EXPECT_TRUE(plant.wait_for_db([&](storage::Database& db) {
        const auto beat = last_beat(db, service);
        if (beat) detail = beat->health_detail;
        return beat && beat->health == "degraded" &&
               beat->health_detail.find("ncqual-solver-contract-1") != std::string::npos;
      })) << service
          << ": " << detail << "\n"
          << plant.log(service);
      EXPECT_NE(
          detail.find("writes ncqual/CheckResult as ncqual::msg::CheckResult (wire contract 1)"),
          std::string::npos)
          << detail;
      EXPECT_NE(detail.find("this process (ncqual-" + service +
                            ") speaks wire contract 2 (ncqual::msg::v2::CheckResult)"),
                std::string::npos)
          << detail;
      // Logged once, by the participant that reads the current layout only.
      const std::string log = plant.log(service);
      const std::string line = "wire contract: participant 'ncqual-solver-contract-1'";
      const auto first = log.find(line);
      EXPECT_NE(first, std::string::npos) << log;
      EXPECT_EQ(log.find(line, first + 1), std::string::npos) << log;
    }
  }
  // Gone: the plant speaks one contract again. The historian's own readers of contract 1 (its
  // second participant) are never taken for an older service.
  for (const std::string service : {"historian", "solver"}) {
    std::string detail;
    EXPECT_TRUE(plant.wait_for_db([&](storage::Database& db) {
      const auto beat = last_beat(db, service);
      if (beat) detail = beat->health + ": " + beat->health_detail;
      return beat && beat->health == "ok";
    })) << service
        << ": " << detail;
  }
}

}  // namespace
}  // namespace ncqual::testing
