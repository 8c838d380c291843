// SPDX-License-Identifier: Apache-2.0
// `ncqual program`: the probing program of a check for a real control, and the reading of the
// touch log that control writes back (for `analyze touches` and `import touches`).
//
//   ncqual program --machine M --check KIND --dialect linuxcnc|fanuc|generic-csv
//                  [--parameters k=v,...] [--out FILE] [--plant F]
//       writes the program (ncqual/probing/program.hpp; docs/connecting-a-machine.md) of the
//       check's touch plan from the machine config (its probing: section), under a new request
//       id, to FILE or stdout; says on stderr where the control will write its results.
//   ncqual program --machine M --check TRACKER-KIND [--out FILE] [--plant F]
//       a laser-tracker check has no control dialect: writes its nominal point list for the
//       tracker's software (ncqual/probing/tracker_nominals.hpp).
//
// Exit codes: 0 written; 1 the check has no program on this machine (a missing section or
// parameter; the reason on stderr) or FILE cannot be written; 2 bad usage (--dialect missing for
// a probe check, given for a tracker check).
#include "commands.hpp"

#include "ncqual/probing/program.hpp"
#include "ncqual/probing/tracker_nominals.hpp"

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/csv.hpp"
#include "ncqual/solver/instrument_files.hpp"
#include "ncqual/common/clock.hpp"
#include "ncqual/common/text.hpp"
#include "ncqual/common/version.hpp"

#include <fstream>
#include <iostream>
#include <sstream>

namespace ncqual::cli {
namespace {

struct Options {
  std::string plant, machine, dialect, parameters, out;
  std::optional<CheckKind> kind;
};

// "k=v,k2=v2" -> parameters; UsageError naming the bad one.
std::vector<NamedValue> parameters_option(const std::string& text) {
  std::vector<NamedValue> out;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto eq = item.find('=');
    double value = 0;
    std::size_t used = 0;
    try {
      if (eq != std::string::npos) value = std::stod(item.substr(eq + 1), &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (eq == std::string::npos || eq == 0 || used == 0 || used != item.size() - eq - 1) {
      throw UsageError("--parameters '" + item + "': expected name=number");
    }
    NamedValue v;
    v.name = item.substr(0, eq);
    v.value = value;
    out.push_back(v);
  }
  return out;
}

int run(const Options& o) {
  const PlantConfig plant = plant_from(o.plant);
  const MachineConfig& machine = configured_machine(plant, o.machine);
  const bool tracker = is_tracker_check(*o.kind);
  if (tracker && !o.dialect.empty()) {
    throw UsageError("--dialect '" + o.dialect + "': " + std::string(to_string(*o.kind)) +
                     " is measured by the laser tracker, not programmed in a control's "
                     "language: leave out --dialect to write its nominal point list");
  }
  if (!tracker && o.dialect.empty()) {
    throw UsageError("--dialect is required for " + std::string(to_string(*o.kind)) + ": one of " +
                     probing::dialect_names());
  }
  const auto dialect =
      tracker ? std::optional<probing::Dialect>() : probing::dialect_from(o.dialect);
  if (!tracker && !dialect) {
    throw UsageError("--dialect '" + o.dialect + "': expected one of " + probing::dialect_names());
  }
  CheckRequest request;
  request.machine_id = machine.machine_id;
  request.request_id = new_sample_id("program", machine.machine_id);
  request.kind = *o.kind;
  request.requested_by = "operator:" + operator_name();
  request.time_ns = WallClock().now_ns();
  request.parameters = parameters_option(o.parameters);
  std::string text;
  try {
    text = tracker ? probing::write_tracker_nominals(request, machine, version_line("ncqual"))
                   : probing::write_program(request, machine, *dialect, version_line("ncqual"));
  } catch (const std::invalid_argument& e) {
    std::cerr << "ncqual program: no " << (tracker ? "tracker nominals" : "probing program")
              << " for " << to_string(request.kind) << " on " << machine.machine_id << ": "
              << e.what() << "\n";
    return kExitError;
  }
  if (o.out.empty()) {
    std::cout << text;
  } else {
    std::ofstream file(o.out, std::ios::binary);
    file << text;
    if (!file.flush()) {
      std::cerr << "ncqual program: cannot write " << o.out << "\n";
      return kExitError;
    }
  }
  if (tracker) {
    std::cerr << "nominal points of " << to_string(request.kind) << " on " << machine.machine_id
              << " (request " << request.request_id
              << ") for the tracker's software; export the measured points under the same names "
                 "for ncqual analyze|import points EXPORT --nominals "
              << (o.out.empty() ? "<this list>" : o.out) << " --machine " << machine.machine_id
              << "\n";
    return kExitOk;
  }
  std::cerr << "program of " << to_string(request.kind) << " on " << machine.machine_id
            << " (request " << request.request_id << ") for " << o.dialect
            << "; the control writes its touches to "
            << probing::results_file_name(request.request_id, *dialect) << "\n";
  return kExitOk;
}

std::string program_text(const std::string& path) {
  std::string why;
  std::optional<std::string> text = read_text_file(path, &why);
  if (!text) throw probing::ProgramError(path, 0, "cannot read: " + why);
  return std::move(*text);
}

}  // namespace

MeasurementSet touches_from_files(const std::string& log_file, const std::string& program_file,
                                  const MachineConfig& machine, std::int64_t time_ns) {
  const probing::ProgramDescription program =
      probing::read_program(program_text(program_file), program_file);
  const probing::TouchLog log =
      probing::read_touch_log(program_text(log_file), log_file, program.dialect);
  return probing::measurement_set_from_log(program, log, log_file, machine, time_ns);
}

MeasurementSet points_from_files(const std::string& export_file, const std::string& nominals_file,
                                 const MachineConfig& machine, std::int64_t time_ns) {
  const std::string text = program_text(nominals_file);
  const probing::TrackerNominalsDescription list =
      probing::read_tracker_nominals(text, nominals_file);
  if (list.machine_id != machine.machine_id) {
    throw probing::ProgramError(nominals_file, 1,
                                "the nominal list was written for machine '" + list.machine_id +
                                    "', not '" + machine.machine_id + "'");
  }
  if (!machine.global_check) {
    throw probing::ProgramError(nominals_file, 1,
                                "machine " + machine.machine_id +
                                    " has no global_check section: its tracker checks cannot be "
                                    "judged (" +
                                    machine.source_path + ")");
  }
  const GlobalCheckConfig& gc = *machine.global_check;
  const std::string kind = std::string(to_string(list.kind));
  // Still the machine's program: every point listed, where the program now puts it.
  const CsvTable listed = read_csv(text, nominals_file);
  const solver::TrackerPointsFromExport nominal =
      solver::tracker_points_from_export(listed, list.kind, gc);
  const auto changed = [&](const std::string& why) {
    return probing::ProgramError(nominals_file, 0,
                                 why + ": " + machine.machine_id + "'s global_check: section (" +
                                     machine.source_path +
                                     ") changed since the list was written; "
                                     "write the list again (ncqual program --check " +
                                     kind + ") and measure to it");
  };
  if (!nominal.ignored.empty() || nominal.points.size() != list.points) {
    throw changed("the list has " + std::to_string(listed.rows.size()) +
                  " points, the program of " + kind + " " + std::to_string(nominal.points.size()));
  }
  for (const solver::GridFilePoint& p : nominal.located) {
    if ((p.measured_mm - p.commanded_mm).norm() > 0.001) {
      throw changed("line " + std::to_string(p.line) + ": point '" + p.point + "' is listed at (" +
                    format_fixed(p.measured_mm.x(), 4) + ", " + format_fixed(p.measured_mm.y(), 4) +
                    ", " + format_fixed(p.measured_mm.z(), 4) + ") mm, the program puts it at (" +
                    format_fixed(p.commanded_mm.x(), 4) + ", " +
                    format_fixed(p.commanded_mm.y(), 4) + ", " +
                    format_fixed(p.commanded_mm.z(), 4) + ") mm");
    }
  }
  const CsvTable table = read_csv_file(export_file);
  const solver::TrackerPointsFromExport measured =
      solver::tracker_points_from_export(table, list.kind, gc);
  solver::check_grid_envelope(table, measured.located, solver::machine_envelope(gc));
  warn_unused(export_file, measured.ignored, "points of " + kind + " on " + machine.machine_id);
  MeasurementSet set;
  set.machine_id = machine.machine_id;
  set.request_id = list.request_id;
  set.kind = list.kind;
  set.instrument = "laser_tracker";
  set.frame = "tracker";
  set.time_ns = time_ns;
  set.origin = DataOrigin::Measured;  // a tracker's export
  set.parameters = list.parameters;
  set.tracker_points = measured.points;
  return set;
}

void add_program(CLI::App& app, Commands& commands) {
  const auto [cmd, o] = add_command(
      app, commands, "program",
      "write the probing program of a check for a real control (LinuxCNC, Fanuc-style macro\n"
      "controls, any control that writes CSV) from the machine config; for a laser-tracker\n"
      "check, the nominal point list for the tracker's software",
      run);
  add_machine_option(cmd, o->machine, "the machine whose control runs it");
  add_kind_option(cmd, "--check", o->kind, "the check to program")->required();
  cmd->add_option("--dialect", o->dialect,
                  "the control's language (probe checks; a tracker check has none)")
      ->type_name("linuxcnc|fanuc|generic-csv");
  cmd->add_option("--parameters", o->parameters,
                  "the request's parameters (e.g. fixture_configuration=3)")
      ->type_name("k=v,...");
  cmd->add_option("--out", o->out, "write the program here (default: stdout)")->type_name("FILE");
  add_plant_option(cmd, o->plant);
}

}  // namespace ncqual::cli
