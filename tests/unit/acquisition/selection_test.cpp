// SPDX-License-Identifier: Apache-2.0
// Which machines one acquisition process serves (services/acquisition/core/include/ncqual/
// acquisition/selection.hpp): exactly one way names them, every refusal says what was wrong, and
// the state file follows the selection so that two processes never share one.
#include "ncqual/acquisition/selection.hpp"

#include <gtest/gtest.h>

namespace ncqual::acquisition {
namespace {

PlantConfig plant_of(std::initializer_list<const char*> ids) {
  PlantConfig plant;
  plant.source_path = "/etc/ncqual/plant.yaml";
  plant.historian_database = "/var/lib/ncqual/historian.db";
  for (const char* id : ids) {
    MachineConfig m;
    m.machine_id = id;
    plant.machines.push_back(m);
  }
  return plant;
}

std::string refusal(const MachineSelection& selection, const PlantConfig& plant) {
  try {
    served_machines(selection, plant);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(MachineSelection, MachinesNamedByIdAreServedInTheOrderGiven) {
  const PlantConfig plant = plant_of({"pm1", "pm2", "pm3"});
  MachineSelection s;
  s.machine = "pm3,pm1";
  const auto machines = served_machines(s, plant);
  EXPECT_EQ(ids_of(machines), (std::vector<std::string>{"pm3", "pm1"}));
  EXPECT_EQ(served_ids(machines), "pm3,pm1");
  EXPECT_EQ(default_state_file(s, machines, plant), "/var/lib/ncqual/acquisition-pm3+pm1.db");
}

TEST(MachineSelection, AllServesEveryMachineWithItsOwnStateFile) {
  const PlantConfig plant = plant_of({"pm1", "pm2"});
  MachineSelection s;
  s.all = true;
  const auto machines = served_machines(s, plant);
  EXPECT_EQ(ids_of(machines), (std::vector<std::string>{"pm1", "pm2"}));
  EXPECT_EQ(default_state_file(s, machines, plant), "/var/lib/ncqual/acquisition-all.db");
}

TEST(MachineSelection, NoneOrTwoWaysAndUnknownOrRepeatedIdsAreRefusedSayingWhy) {
  const PlantConfig plant = plant_of({"pm1"});
  const std::string exactly_one =
      "name the machines to serve with exactly one of --machine ID[,ID...], --all or "
      "--machine-config FILE";
  EXPECT_EQ(refusal({}, plant), exactly_one);
  MachineSelection both;
  both.all = true;
  both.machine = "pm1";
  EXPECT_EQ(refusal(both, plant), exactly_one);
  MachineSelection unknown;
  unknown.machine = "pm1,pm9";
  EXPECT_EQ(refusal(unknown, plant), "--machine 'pm9' is not configured in /etc/ncqual/plant.yaml");
  MachineSelection twice;
  twice.machine = "pm1,pm1";
  EXPECT_EQ(refusal(twice, plant), "--machine 'pm1' is named twice");
  MachineSelection all;
  all.all = true;
  EXPECT_EQ(refusal(all, plant_of({})), "--all: /etc/ncqual/plant.yaml configures no machine");
}

}  // namespace
}  // namespace ncqual::acquisition
