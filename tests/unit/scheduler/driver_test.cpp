// SPDX-License-Identifier: Apache-2.0
// The scheduler's durable sending and its command-line choices, without DDS (through a real
// state file).
#include "ncqual/scheduler/driver.hpp"

#include "scheduler_test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

namespace ncqual::scheduler {
namespace {

using test_support::one_machine;

// What a decision sends is in the state file's outbox before it leaves, in the transaction of
// the decision: when the request reaches the writer, the file already holds it (and the state
// that issued it), so a kill can never keep the one and lose the other.
TEST(SchedulerOutbox, WhatADecisionSendsIsSavedWithItBeforeItLeaves) {
  const std::string file = ::testing::TempDir() + "ncqual-scheduler-outbox.db";
  std::filesystem::remove(file);
  auto state = storage::StateFile::open(file);
  const PlantConfig plant = one_machine();
  SimulatedClock clock(1'000'000'000);
  std::vector<std::string> in_file_when_sent;
  std::vector<std::string> pending_when_sent;
  Scheduler::Outputs outputs;
  outputs.queue = [](const std::vector<CheckRequest>& requests,
                     const std::vector<MachineStatus>& statuses) {
    std::vector<storage::OutboxEntry> entries;
    for (const auto& r : requests) {
      entries.push_back({"ncqual/CheckRequest",
                         r.request_id,
                         "h-" + r.request_id,
                         r.machine_id,
                         {1, 2, 3},
                         {"historian"},
                         r.time_ns});
    }
    for (const auto& st : statuses) {
      entries.push_back({"ncqual/MachineStatus",
                         sample_id_of(st),
                         "h",
                         st.machine_id,
                         {4},
                         {"historian"},
                         st.time_ns});
    }
    return entries;
  };
  outputs.request = [&](const CheckRequest& r) {
    for (const auto& e : state.outbox_index()) {
      if (e.sample_id == r.request_id) in_file_when_sent.push_back(e.sample_id);
    }
    const auto docs = state.load();
    const auto run = machine_run_from_json(docs.at("machine/m1"));
    for (const auto& p : run.pending) pending_when_sent.push_back(p.request_ids.back());
  };
  outputs.status = [](const MachineStatus&) {};
  // The entries the decision saved, handed on for writing once saved: each already in the file.
  std::size_t written_in_file = 0;
  outputs.written = [&](const std::vector<storage::OutboxEntry>& saved) {
    const auto index = state.outbox_index();
    for (const auto& e : saved) {
      written_in_file += static_cast<std::size_t>(
          std::count_if(index.begin(), index.end(), [&](const storage::OutboxEntry& f) {
            return f.topic == e.topic && f.sample_id == e.sample_id &&
                   f.content_hash == e.content_hash;
          }));
    }
  };
  Scheduler s(plant, clock, outputs, &state);
  s.start({CheckKind::MonumentCAlignment, CheckKind::MonumentToolLength});
  ASSERT_TRUE(s.saved());
  ASSERT_EQ(in_file_when_sent.size(), 1u);
  EXPECT_EQ(pending_when_sent, in_file_when_sent);
  // The first request and at least one status (CHECKING) wait in the outbox for the historian.
  const auto index = state.outbox_index();
  EXPECT_EQ(std::count_if(index.begin(), index.end(),
                          [](const auto& e) { return e.topic == "ncqual/CheckRequest"; }),
            1);
  EXPECT_GE(std::count_if(index.begin(), index.end(),
                          [](const auto& e) { return e.topic == "ncqual/MachineStatus"; }),
            1);
  EXPECT_EQ(written_in_file, index.size());
  // The historian's acknowledgement empties the entry; the same entry queued again is kept once.
  const auto& first = index.front();
  EXPECT_EQ(state.acknowledge(first.topic, first.sample_id, first.content_hash, "historian"),
            std::vector<std::string>{});
  EXPECT_FALSE(state.acknowledge(first.topic, first.sample_id, first.content_hash, "historian"));
  EXPECT_EQ(state.outbox_summary().depth, static_cast<std::int64_t>(index.size()) - 1);
}

TEST(SchedulerCommandLine, CycleListsAndRunEndsAreReadOrRefusedByName) {
  EXPECT_EQ(
      check_kind_list("monument_c_alignment,fixture_precal"),
      (std::vector<CheckKind>{CheckKind::MonumentCAlignment, CheckKind::FixturePreCalibration}));
  EXPECT_TRUE(check_kind_list("").empty());
  try {
    check_kind_list("monument_c_alignment,grid");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "--cycle: 'grid' is not a check kind");
  }
  PlantConfig plant;
  EXPECT_THROW(simulated_run_end(plant, 3.0, std::nullopt), std::invalid_argument);  // wall clock
  plant.simulated_clock = true;
  plant.simulated_start_ns = 1'000;
  EXPECT_EQ(simulated_run_end(plant, 2.0, std::nullopt), 1'000 + 2 * 86'400'000'000'000LL);
  EXPECT_EQ(simulated_run_end(plant, std::nullopt, std::string("1970-01-02T00:00:00Z")),
            86'400'000'000'000LL);
  EXPECT_EQ(simulated_run_end(plant, std::nullopt, std::nullopt), std::nullopt);
  EXPECT_THROW(simulated_run_end(plant, -1.0, std::nullopt), std::invalid_argument);
}

TEST(SchedulerCommandLine, ServingSomeMachinesKeepsAStateFileOfItsOwn) {
  PlantConfig plant;
  plant.source_path = "plant.yaml";
  plant.scheduler_state_database = "/var/ncqual/scheduler.db";
  for (const char* id : {"a", "b", "c"}) {
    MachineConfig m;
    m.machine_id = id;
    plant.machines.push_back(m);
  }
  const ServedPlant all = serve_only(plant, std::nullopt);
  EXPECT_EQ(all.plant.machines.size(), 3u);
  EXPECT_TRUE(all.others.empty());
  EXPECT_EQ(all.plant.scheduler_state_database, "/var/ncqual/scheduler.db");
  const ServedPlant some = serve_only(plant, std::string("c,a"));
  ASSERT_EQ(some.plant.machines.size(), 2u);
  EXPECT_EQ(some.plant.machines[0].machine_id, "c");
  EXPECT_EQ(some.others, (std::set<std::string>{"b"}));
  EXPECT_EQ(some.plant.scheduler_state_database, "/var/ncqual/scheduler-c+a.db");
  EXPECT_THROW(serve_only(plant, std::string("a,x")), ConfigError);
}

}  // namespace
}  // namespace ncqual::scheduler
