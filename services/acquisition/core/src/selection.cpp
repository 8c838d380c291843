// SPDX-License-Identifier: Apache-2.0
// The machines one acquisition process serves, and its state file (selection.hpp).
#include "ncqual/acquisition/selection.hpp"

#include <algorithm>
#include <filesystem>

namespace ncqual::acquisition {

std::vector<MachineConfig> served_machines(const MachineSelection& selection,
                                           const PlantConfig& plant) {
  const int ways =
      (selection.all ? 1 : 0) + (selection.machine ? 1 : 0) + (selection.machine_config ? 1 : 0);
  if (ways != 1) {
    throw ConfigError(
        "name the machines to serve with exactly one of --machine ID[,ID...], --all "
        "or --machine-config FILE");
  }
  if (selection.machine_config) return {load_machine_config(*selection.machine_config)};
  if (selection.all) {
    if (plant.machines.empty()) {
      throw ConfigError("--all: " + plant.source_path + " configures no machine");
    }
    return plant.machines;
  }
  return plant.machines_named(*selection.machine, "--machine");
}

std::vector<std::string> ids_of(const std::vector<MachineConfig>& machines) {
  std::vector<std::string> ids;
  ids.reserve(machines.size());
  for (const auto& m : machines) ids.push_back(m.machine_id);
  return ids;
}

std::string served_ids(const std::vector<MachineConfig>& machines) {
  std::string ids;
  for (const auto& m : machines) ids += (ids.empty() ? "" : ",") + m.machine_id;
  return ids;
}

std::string default_state_file(const MachineSelection& selection,
                               const std::vector<MachineConfig>& machines,
                               const PlantConfig& plant) {
  std::string ids = selection.all ? "all" : served_ids(machines);
  std::replace(ids.begin(), ids.end(), ',', '+');
  return (std::filesystem::path(plant.historian_database).parent_path() /
          ("acquisition-" + ids + ".db"))
      .string();
}

}  // namespace ncqual::acquisition
