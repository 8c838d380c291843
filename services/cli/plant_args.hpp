// What most ncqual commands start with: the plant config (--plant FILE, else NCQUAL_PLANT) and a
// machine it configures (--machine M). Bad usage throws ArgError (the caller exits 2).
#pragma once

#include "ncqual/args.hpp"
#include "ncqual/config.hpp"

#include <string>

namespace ncqual {

inline PlantConfig plant_from_args(const Args& args) {
  const std::string file = plant_config_path(args.get_or("plant", ""));
  if (file.empty()) throw ArgError("pass --plant FILE (or set NCQUAL_PLANT)");
  return load_plant_config(file);
}

inline const MachineConfig& configured_machine(const PlantConfig& plant, const std::string& machine_id) {
  const MachineConfig* m = plant.find_machine(machine_id);
  if (!m) throw ArgError("--machine '" + machine_id + "' is not configured in " + plant.source_path);
  return *m;
}

}  // namespace ncqual
