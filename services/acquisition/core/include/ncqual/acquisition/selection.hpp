// SPDX-License-Identifier: Apache-2.0
// Which machines one acquisition process serves (--machine ID[,ID...], --all or --machine-config
// FILE: exactly one), and its state file's default name, which follows them.
#pragma once

#include "ncqual/common/config.hpp"

#include <optional>
#include <string>
#include <vector>

namespace ncqual::acquisition {

struct MachineSelection {
  std::optional<std::string> machine;         // --machine: comma-separated ids of the plant
  std::optional<std::string> machine_config;  // --machine-config: a machine file
  bool all = false;                           // --all: every machine of the plant
};

// The machines selected. Throws ConfigError when none or more than one way names them, when
// --all finds none, or for an id the plant does not configure.
std::vector<MachineConfig> served_machines(const MachineSelection& selection,
                                           const PlantConfig& plant);

// The ids of the machines, in order.
std::vector<std::string> ids_of(const std::vector<MachineConfig>& machines);

// The ids served, joined by commas ("pm1,pm2"): the heartbeat's instance detail.
std::string served_ids(const std::vector<MachineConfig>& machines);

// "acquisition-<id>+<id>.db" (or "acquisition-all.db" for --all) beside the historian's
// database: one state file per selection, so two processes never share one.
std::string default_state_file(const MachineSelection& selection,
                               const std::vector<MachineConfig>& machines,
                               const PlantConfig& plant);

}  // namespace ncqual::acquisition
