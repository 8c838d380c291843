// SPDX-License-Identifier: Apache-2.0
// What several commands share: their common options, the plant and machine they name, and the
// ids of the samples they publish. See commands.hpp.
#include "commands.hpp"

#include "ncqual/recording/recording.hpp"

#include "ncqual/common/check_kinds.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/common/text.hpp"
#include "ncqual/solver/circular_test.hpp"
#include "ncqual/solver/instrument_files.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace ncqual::cli {

CLI::Option* add_plant_option(CLI::App* command, std::string& plant) {
  return command->add_option("--plant", plant, "the plant config (default: $NCQUAL_PLANT)")
      ->type_name("FILE");
}

CLI::Option* add_db_option(CLI::App* command, std::optional<std::string>& db) {
  return command->add_option("--db", db, "the historian database, read only (default: the plant's)")
      ->type_name("FILE");
}

CLI::Option* add_machine_option(CLI::App* command, std::optional<std::string>& machine,
                                const std::string& description) {
  return command->add_option("--machine", machine, description)->type_name("M");
}

CLI::Option* add_machine_option(CLI::App* command, std::string& machine,
                                const std::string& description) {
  return command->add_option("--machine", machine, description)->type_name("M")->required();
}

CLI::Option* add_domain_option(CLI::App* command, int& domain) {
  return command
      ->add_option("--domain", domain,
                   "the DDS domain (default: $NCQUAL_DOMAIN, else the plant's domain_id)")
      ->type_name("N");
}

void add_historian_options(CLI::App* command, std::string& plant, std::optional<std::string>& db) {
  add_plant_option(command, plant);
  add_db_option(command, db);
}

void add_dds_options(CLI::App* command, DdsOptions& options) {
  add_plant_option(command, options.plant);
  add_domain_option(command, options.domain);
  command
      ->add_option("--secure", options.secure,
                   "run secured with this ncqual-pki directory (default: the plant's security.dir)")
      ->type_name("DIR");
  command
      ->add_option("--identity", options.identity,
                   "the identity to run as on a secured plant (default: $NCQUAL_IDENTITY)")
      ->type_name("NAME");
}

dds::ParticipantOptions command_participant(const PlantConfig& plant, const DdsOptions& options,
                                            const std::string& name,
                                            const std::string& default_identity) {
  dds::ParticipantOptions p = dds::participant_options(
      plant, dds::resolve_domain_id(options.domain, plant.domain_id), name);
  const char* env = std::getenv("NCQUAL_IDENTITY");
  apply_security_flags(p, options.secure, options.identity,
                       env && *env ? std::string(env) : default_identity);
  return p;
}

std::string operator_identity() {
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  return std::string("operator-") + host;
}

CLI::Option* add_json_flag(CLI::App* command, bool& json) {
  return command->add_flag("--json", json, "print one JSON document instead of the table");
}

CLI::Option* add_kind_option(CLI::App* command, const std::string& name,
                             std::optional<CheckKind>& kind, const std::string& description) {
  return command
      ->add_option_function<std::string>(
          name,
          [name, &kind](const std::string& text) {
            kind = parse_check_kind(text);
            if (!kind) {
              std::string names;
              for (const auto& row : check_kinds())
                names += (names.empty() ? "" : ", ") + std::string(row.name);
              throw CLI::ValidationError(name,
                                         "'" + text + "' is not a check kind (" + names + ")");
            }
          },
          description)
      ->type_name("KIND");
}

PlantConfig plant_from(const std::string& plant_flag) {
  const std::string file = plant_config_path(plant_flag);
  if (file.empty()) throw UsageError("pass --plant FILE (or set NCQUAL_PLANT)");
  return load_plant_config(file);
}

namespace {

// " (it configures pm1, pm2); did you mean 'pm1'?": what there is instead of `name`.
std::string instead_of(const std::string& name, const std::vector<std::string>& known,
                       const std::string& verb) {
  if (known.empty()) return " (it " + verb + " none)";
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  const auto best = closest_word(name, {known.begin(), known.end()});
  return " (it " + verb + " " + list + ")" +
         (best ? "; did you mean '" + std::string(*best) + "'?" : "");
}

}  // namespace

const MachineConfig& configured_machine(const PlantConfig& plant, const std::string& machine_id) {
  const MachineConfig* m = plant.find_machine(machine_id);
  if (!m) {
    std::vector<std::string> known;
    for (const auto& machine : plant.machines) known.push_back(machine.machine_id);
    throw UsageError("--machine '" + machine_id + "' is not configured in " + plant.source_path +
                     instead_of(machine_id, known, "configures"));
  }
  return *m;
}

bool check_machines_configured(const std::vector<std::string>& machines,
                               const std::string& plant_flag) {
  const std::string plant_file = plant_config_path(plant_flag);
  if (plant_file.empty()) return false;
  const PlantConfig plant = load_plant_config(plant_file);
  for (const std::string& m : machines) (void)configured_machine(plant, m);
  return true;
}

void check_machines_held(const std::vector<std::string>& machines, storage::Database& db,
                         const std::string& db_path) {
  if (machines.empty()) return;
  const std::vector<std::string> known = db.machines();
  for (const std::string& m : machines) {
    if (std::find(known.begin(), known.end(), m) != known.end()) continue;
    throw UsageError("--machine '" + m + "': the historian " + db_path + " holds no such machine" +
                     instead_of(m, known, "holds"));
  }
}

Calendar plant_calendar(const std::string& plant_flag) {
  const std::string plant = plant_config_path(plant_flag);
  if (plant.empty()) return Calendar(default_calendar_config());
  return Calendar(load_plant_config(plant).calendar.value_or(default_calendar_config()));
}

std::string database_path(const std::optional<std::string>& db, const std::string& plant_flag) {
  if (db) return *db;
  const std::string plant = plant_config_path(plant_flag);
  if (!plant.empty()) return load_plant_config(plant).historian_database;
  const char* var = std::getenv("NCQUAL_VAR");
  std::string fallback = std::string(var && *var ? var : "var") + "/historian.db";
  if (std::filesystem::exists(fallback)) return fallback;
  throw UsageError("pass --db FILE or --plant FILE (or set NCQUAL_PLANT); no " + fallback +
                   " here");
}

std::optional<storage::Database> open_historian(const std::string& path,
                                                const std::string& command) {
  if (!std::filesystem::exists(path)) {
    std::cerr << "ncqual " << command << ": no historian database at " << path << "\n";
    return std::nullopt;
  }
  return storage::Database::open_readonly(path);
}

std::optional<solver::Plane> plane_option(const std::optional<std::string>& text) {
  if (!text) return std::nullopt;
  const auto plane = solver::parse_plane(*text);
  if (!plane) throw UsageError("--plane '" + *text + "': expected XY, YZ or XZ");
  return plane;
}

std::pair<double, double> centre_option(const std::string& text) {
  const auto refuse = [&] {
    return UsageError("--centre-mm '" + text + "': expected two numbers U,V (mm)");
  };
  const auto number = [&](const std::string& part) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(part, &used);
    } catch (const std::logic_error&) {
      used = 0;
    }
    while (used < part.size() && part[used] == ' ') ++used;
    if (used == 0 || used != part.size() || !std::isfinite(v)) throw refuse();
    return v;
  };
  const auto comma = text.find(',');
  if (comma == std::string::npos || text.find(',', comma + 1) != std::string::npos) throw refuse();
  return {number(text.substr(0, comma)), number(text.substr(comma + 1))};
}

std::int64_t plant_time_option(const std::string& flag, const std::string& text,
                               const Calendar& calendar) {
  if (const auto t = calendar.parse_time(text)) return *t;
  throw UsageError(flag + " '" + text + "': expected a date or time in the plant's time zone (" +
                   calendar.zone_name() +
                   ") such as 2027-01-15 or 2027-01-15T06:00, or a time with Z or an offset such "
                   "as 2027-01-15T06:00Z or 2027-01-15T06:00+01:00");
}

std::string operator_name() {
  if (const char* user = std::getenv("USER")) return user;
  char host[128] = {};
  gethostname(host, sizeof host - 1);
  return host;
}

std::string new_sample_id(const std::string& prefix, const std::string& machine_id) {
  return prefix + "-" + machine_id + "-" + std::to_string(WallClock().now_ns()) + "-" +
         std::to_string(getpid());
}

void warn_unused(const std::string& file, const std::vector<solver::TrackerExportPoint>& unused,
                 const std::string& what) {
  if (unused.empty()) return;
  std::cerr << "warning: " << file << ": " << unused.size() << " point"
            << (unused.size() == 1 ? " is" : "s are") << " not " << what << " and not used:";
  const std::size_t shown = std::min<std::size_t>(unused.size(), 5);
  for (std::size_t k = 0; k < shown; ++k) {
    std::cerr << (k ? ", " : " ") << "'" << unused[k].name << "' (line " << unused[k].line << ")";
  }
  std::cerr << (shown < unused.size() ? ", ...\n" : "\n");
}

std::vector<solver::GridFilePoint> read_grid_part(const CsvTable& table, const std::string& prefix,
                                                  const MachineConfig* machine) {
  if (!solver::is_tracker_point_export(table)) return solver::read_grid_csv(table);
  if (!machine || !machine->global_check) {
    throw UsageError(table.file +
                     " is a tracker's point export (a name and x, y, z, no commanded "
                     "positions): pass --machine M, whose monthly program gives them");
  }
  const solver::GridFromExport part =
      solver::grid_points_from_export(table, prefix, *machine->global_check);
  warn_unused(
      table.file, part.ignored,
      prefix + " points of " + machine->machine_id + "'s program (or not of its reflector 0)");
  return part.points;
}

GridPart read_grid_file(const std::string& path, const std::string& prefix,
                        const MachineConfig* machine) {
  const CsvTable table = read_csv_file(path);
  GridPart part;
  part.points = read_grid_part(table, prefix, machine);
  if (machine && machine->global_check) {
    solver::check_grid_envelope(table, part.points,
                                solver::machine_envelope(*machine->global_check));
  }
  part.last_line = table.rows.empty() ? table.header_line : table.rows.back().line;
  return part;
}

void add_sample_filter_options(CLI::App* command, std::vector<std::string>& topics,
                               std::vector<std::string>& machines) {
  command->add_option("--topics", topics, "only these topics (CheckResult,MeasurementSet,...)")
      ->delimiter(',')
      ->type_name("T,...");
  command->add_option("--machine", machines, "only these machines' samples")
      ->delimiter(',')
      ->type_name("M,...");
}

std::vector<const dds::TopicInfo*> topics_option(const std::vector<std::string>& names) {
  try {
    return recording::topics_named(names);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--topics: ") + e.what());
  }
}

}  // namespace ncqual::cli
