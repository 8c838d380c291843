// SPDX-License-Identifier: Apache-2.0
// `ncqual config check [--plant F] [--print] [--json]`: loads the whole plant (the plant file and
// every machine file it names) and prints every problem with its file, key and value, not only
// the first; with --print, every value as it was resolved (in mm and rad, with what was written
// when that was another unit, and the defaults taken). A plant that loads is summed up with
// whether it is a simulation (`simulated: true`, a demo or test bench) and which of its machines
// the simulator measures. Exit 0 when the plant loads, 4 when the files were refused. --json
// prints ConfigCheckDocument (below).
#include "commands.hpp"

#include "ncqual/common/json.hpp"

#include <iostream>

namespace ncqual {

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ResolvedValue, file, key, value, defaulted)

namespace cli {
namespace {

// The --json document. Without a plant (problems found) plant, domain_id, simulated and machines
// are null; values is null without --print. A machine is `simulated` when the simulator measures
// it (only a plant that is `simulated` has such machines).
struct MachineFileDocument {
  std::string machine_id, file;
  bool simulated = false;
};
struct ConfigCheckDocument {
  std::string plant_file;
  bool ok = false;
  std::vector<std::string> problems;
  std::optional<std::string> plant;
  std::optional<int> domain_id;
  std::optional<bool> simulated;
  std::optional<std::vector<MachineFileDocument>> machines;
  std::optional<std::vector<ResolvedValue>> values;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(MachineFileDocument, machine_id, file, simulated)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ConfigCheckDocument, plant_file, ok, problems, plant, domain_id,
                                   simulated, machines, values)

struct Options {
  std::string plant;
  bool print = false;
  bool json = false;
};

// Where the plant file comes from: --plant, else NCQUAL_PLANT.
std::string plant_file(const std::string& flag) {
  std::string path = plant_config_path(flag);
  if (path.empty()) throw UsageError("pass --plant FILE (or set NCQUAL_PLANT)");
  return path;
}

void print_values(const std::vector<ResolvedValue>& values) {
  std::string file;
  for (const auto& v : values) {
    if (v.file != file) {
      file = v.file;
      std::cout << file << "\n";
    }
    std::cout << "  " << v.key << " = " << v.value << (v.defaulted ? "  (default)" : "") << "\n";
  }
}

// Whether the plant is a simulation and which machines the simulator measures, e.g.
// "  simulated: true (a demo or test bench): measured by the simulator: pm1, pm2; by their
// instruments: pm3".
std::string simulation_line(const PlantConfig& plant) {
  std::string simulated, measured;
  for (const auto& m : plant.machines) {
    std::string& list = is_simulated(m) ? simulated : measured;
    list += (list.empty() ? "" : ", ") + m.machine_id;
  }
  if (!plant.simulated) {
    return "  simulated: false: every machine is measured by its instrument" +
           (measured.empty() ? std::string() : ": " + measured);
  }
  return "  simulated: true (a demo or test bench): measured by the simulator: " +
         (simulated.empty() ? std::string("none") : simulated) +
         (measured.empty() ? std::string() : "; by their instruments: " + measured);
}

int run_check(const Options& o) {
  const std::string path = plant_file(o.plant);
  const ConfigReport report = check_plant_config(path);
  if (o.json) {
    ConfigCheckDocument doc;
    doc.plant_file = path;
    doc.ok = report.problems.empty();
    doc.problems = report.problems;
    if (report.plant) {
      doc.plant = report.plant->plant;
      doc.domain_id = report.plant->domain_id;
      doc.simulated = report.plant->simulated;
      doc.machines.emplace();
      for (const auto& m : report.plant->machines) {
        doc.machines->push_back({m.machine_id, m.source_path, is_simulated(m)});
      }
    }
    if (o.print) doc.values = report.values;
    std::cout << nlohmann::json(doc).dump(2) << "\n";
    return report.problems.empty() ? kExitOk : kExitInvalid;
  }
  if (o.print) print_values(report.values);
  if (!report.problems.empty() || !report.plant) {
    for (const auto& p : report.problems) std::cout << p << "\n";
    std::cout << path << ": " << report.problems.size() << " problem"
              << (report.problems.size() == 1 ? "" : "s") << "; nothing of this plant was used\n";
    return kExitInvalid;
  }
  const PlantConfig& plant = *report.plant;
  std::cout << path << ": OK, plant '" << plant.plant << "' on domain " << plant.domain_id << ", "
            << plant.machines.size() << " machine" << (plant.machines.size() == 1 ? "" : "s");
  for (std::size_t i = 0; i < plant.machines.size(); ++i) {
    std::cout << (i ? ", " : ": ") << plant.machines[i].machine_id;
  }
  std::cout << "\n" << simulation_line(plant) << "\n";
  return kExitOk;
}

}  // namespace

void add_config(CLI::App& app, Commands& commands) {
  CLI::App* config = app.add_subcommand("config", "the plant's configuration files");
  config->require_subcommand(1);
  const auto [check, o] = add_command(*config, commands, "check",
                                      "load the whole plant and print every problem (file, key, "
                                      "value), not only the first; exit 4 when there is any",
                                      run_check);
  add_plant_option(check, o->plant);
  check->add_flag("--print", o->print,
                  "also print every value as resolved: mm and rad, as written, defaults taken");
  add_json_flag(check, o->json);
}

}  // namespace cli
}  // namespace ncqual
