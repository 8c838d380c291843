// SPDX-License-Identifier: Apache-2.0
// The scheduler's restart handshake with the readers of its writers, and its command-line
// choices, without DDS: a restarted scheduler waits for the readers its last run had, learns a
// changed plant, and remembers readers that join later (through a real state file).
#include "driver.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace ncqual::scheduler {
namespace {

// A writer whose matched readers the test sets; `wait` succeeds when enough are matched.
struct FakeWriter {
  int matched = 0;
  int waits = 0;
  ReaderHandshake::Writer writer() {
    return {[this] { return matched; },
            [this](int readers, std::chrono::milliseconds) {
              ++waits;
              return matched >= readers;
            }};
  }
};

TEST(ReaderHandshake, ARestartWaitsForTheReadersOfTheLastRunAndLearnsAChangedPlant) {
  const std::string file = ::testing::TempDir() + "ncqual-handshake.db";
  std::filesystem::remove(file);
  auto state = storage::StateFile::open(file);
  FakeWriter requests, statuses;
  {
    // First run: nothing known, nothing to wait for; readers join and are remembered.
    ReaderHandshake h(state, requests.writer(), statuses.writer());
    EXPECT_TRUE(h.wait(std::chrono::milliseconds(10)));
    EXPECT_EQ(requests.waits, 0);
    requests.matched = 3;  // historian and two acquisitions
    statuses.matched = 1;  // historian
    h.learn();
    requests.matched = 2;  // one acquisition goes: the count stays the largest seen
    h.learn();
  }
  EXPECT_EQ(saved_reader_counts(state), (ReaderCounts{3, 1}));
  {
    // Restart with every reader back: waits for them.
    requests.matched = 3;
    ReaderHandshake h(state, requests.writer(), statuses.writer());
    EXPECT_TRUE(h.wait(std::chrono::milliseconds(10)));
    EXPECT_GT(requests.waits, 0);
  }
  {
    // Restart after an acquisition left the plant: it says so and learns the smaller count.
    requests.matched = 2;
    ReaderHandshake h(state, requests.writer(), statuses.writer());
    EXPECT_FALSE(h.wait(std::chrono::milliseconds(10)));
    EXPECT_EQ(saved_reader_counts(state), (ReaderCounts{2, 1}));
  }
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
