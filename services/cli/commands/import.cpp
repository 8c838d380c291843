// SPDX-License-Identifier: Apache-2.0
// `ncqual import`: a real instrument's export published as a MeasurementSet, so it goes through
// the whole service chain (the solver judges it, the historian stores set and result) like a
// simulated measurement. The files are those of `ncqual analyze` (analyze_command.hpp); the
// points are labelled as the monthly programs label them (solver/instrument_files.hpp).
//
//   ncqual import iso230-2 FILE --machine M [--axis x|y|z] [--plant F] [--domain N]
//       kind linear_axis_run; the run along --axis (default the machine's linear_run axis) at
//       the machine's linear_run position
//   ncqual import circle FILE --machine M [--plane XY|YZ|XZ] [--nominal-radius-mm R]
//                         [--centre-mm U,V] [--plant F] [--domain N]
//       kind circle_xy|yz|xz; F about the given reference, else the least-squares circle
//   ncqual import grid --x-run F --y-run F --grid F --machine M [--plant F] [--domain N]
//       kind global_grid with its master-frame runs
//   ncqual import touches LOG --program PROG --machine M [--plant F] [--domain N]
//       a real control's touch log of a program written by `ncqual program`, as the check the
//       program names, under the program's request id (ncqual/probing/program.hpp)
//   ncqual import points EXPORT --nominals LIST --machine M [--plant F] [--domain N]
//       a laser tracker's point export of any tracker check, as the check its nominal list
//       (`ncqual program --check KIND`) names, under the list's request id (points_from_files)
//
// Prints the request id of the set (`ncqual wait --request ID` waits for its result) once the
// historian stored it and the solver saved its result (ncqual/dds/acknowledged_send.hpp). Exit
// codes: 0 imported, 1 refused file (file:line:column on stderr; values no instrument on the
// machine can have read, solver::check_*_envelope, too) or no acknowledgement from the
// solver or the historian within 60 s, 2 bad usage (and a machine the plant does not configure), 9
// refused by a service.
#include "commands.hpp"

#include "ncqual/dds/acknowledged_send.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/common/csv.hpp"
#include "ncqual/dds/endpoint.hpp"
#include "ncqual/dds/participant.hpp"
#include "ncqual/dds/topics.hpp"
#include "ncqual/solver/instrument_files.hpp"

#include <chrono>
#include <iostream>

namespace ncqual::cli {
namespace {

// What the three imports take on the command line.
struct Options {
  std::string what;  // iso230-2, circle, grid, touches, points
  DdsOptions dds;
  std::string file, machine;
  std::optional<std::string> axis, plane, centre_mm;
  std::optional<double> nominal_radius_mm;
  std::string x_run, y_run, grid;
  std::string program;  // touches: the program; points: the nominal list
};

// Publishes an imported set: done once the historian stored it and the solver saved its result.
int publish(const PlantConfig& plant, const DdsOptions& dds, const MeasurementSet& set,
            const std::string& what);

int run(const Options& o) {
  const PlantConfig plant = plant_from(o.dds.plant);
  const std::string& machine_id = o.machine;
  const MachineConfig* machine = &configured_machine(plant, machine_id);
  if (o.what == "touches") {
    MeasurementSet set = touches_from_files(o.file, o.program, *machine, WallClock().now_ns());
    set.instrument = kImportedInstrument;
    return publish(plant, o.dds, set, std::to_string(set.touches.size()) + " touches");
  }
  if (o.what == "points") {
    MeasurementSet set = points_from_files(o.file, o.program, *machine, WallClock().now_ns());
    set.instrument = kImportedInstrument;
    return publish(plant, o.dds, set, std::to_string(set.tracker_points.size()) + " points");
  }
  if (!machine->global_check) {
    throw UsageError("machine '" + machine_id + "' has no global_check: section (" +
                     machine->source_path + "): its tracker checks cannot be judged");
  }
  const GlobalCheckConfig& gc = *machine->global_check;
  const ProbeGeometry& target = gc.targets.front();
  // Finite but impossible on this machine (a file in another unit): refused at the cell.
  const solver::Envelope envelope = solver::machine_envelope(gc);

  const WallClock clock;
  MeasurementSet set;
  set.machine_id = machine_id;
  set.request_id = new_sample_id("import", machine_id);
  set.instrument = kImportedInstrument;
  set.frame = "tracker";
  set.time_ns = clock.now_ns();
  set.origin = DataOrigin::Measured;  // an instrument's export (ncqual's simulator writes none)
  set.parameters.push_back({"imported", 1, ""});
  if (o.what == "iso230-2") {
    const std::string& file = o.file;
    int axis = gc.linear_run.axis;
    if (const auto& a = o.axis) {
      if (*a != "x" && *a != "y" && *a != "z")
        throw UsageError("--axis '" + *a + "': expected x, y or z");
      axis = (*a)[0] - 'x';
    }
    const CsvTable table = read_csv_file(file);
    const solver::Iso230_2File run = solver::read_iso230_2_csv(table);
    solver::check_iso230_2_envelope(table, axis, envelope);
    for (const auto& w : solver::iso230_2_conformance(solver::evaluate_iso230_2(run.readings))) {
      std::cerr << "warning: " << file << ": " << w << "\n";
    }
    set.kind = CheckKind::LinearAxisRun;
    set.frame = "machine";
    set.parameters.push_back({"axis", static_cast<double>(axis), ""});
    set.tracker_points =
        solver::tracker_points_for_linear_run(run, axis, gc.linear_run.at_mm, target);
  } else if (o.what == "circle") {
    const std::string& file = o.file;
    const std::optional<solver::Plane> plane = plane_option(o.plane);
    const CsvTable table = read_csv_file(file);
    const solver::CircleFile circle = solver::read_circle_csv(table, plane, o.nominal_radius_mm);
    solver::check_circle_envelope(table, envelope, plane, o.nominal_radius_mm);
    for (const auto& w :
         solver::iso230_4_conformance(solver::evaluate_circular_test(circle.input))) {
      std::cerr << "warning: " << file << ": " << w << "\n";
    }
    set.kind = circle.input.plane == solver::Plane::XY   ? CheckKind::CircleXY
               : circle.input.plane == solver::Plane::YZ ? CheckKind::CircleYZ
                                                         : CheckKind::CircleXZ;
    set.frame = "machine";
    if (const auto& r0 = circle.input.nominal_radius_mm) {  // given, or declared in the file
      set.parameters.push_back({"nominal_radius_mm", *r0, "mm"});
    }
    if (o.centre_mm) {
      const auto [u, v] = centre_option(*o.centre_mm);
      set.parameters.push_back({"centre_u_mm", u, "mm"});
      set.parameters.push_back({"centre_v_mm", v, "mm"});
    }
    AxisPosition centre;
    centre.x_mm = gc.circle.centre_mm.x();
    centre.y_mm = gc.circle.centre_mm.y();
    centre.z_mm = gc.circle.centre_mm.z();
    set.tracker_points =
        solver::tracker_points_for_circle(circle, stylus_ball_centre(centre, target), target);
  } else {
    auto read = [&](const std::string& f, const std::string& prefix) {
      return read_grid_file(f, prefix, machine).points;
    };
    set.kind = CheckKind::GlobalGrid;
    set.tracker_points = solver::tracker_points_for_grid(
        read(o.x_run, "x_run"), read(o.y_run, "y_run"), read(o.grid, "grid"), target);
  }

  return publish(plant, o.dds, set, std::to_string(set.tracker_points.size()) + " points");
}

int publish(const PlantConfig& plant, const DdsOptions& dds, const MeasurementSet& set,
            const std::string& what) {
  // On a secured plant an import publishes as the machine's acquisition, whose permissions
  // allow its MeasurementSets (an operator's do not).
  const ncqual::dds::ParticipantOptions options =
      command_participant(plant, dds, "ncqual-import", "acquisition-" + set.machine_id);
  const int domain = options.domain_id;
  ncqual::dds::Participant participant(options);
  // In the machine's partition, as its acquisition writes (an acquisition's identity may write
  // there only).
  ncqual::dds::Writer<ncqual::dds::MeasurementSetTopic> sets(
      participant, ncqual::dds::InPartitionOf{set.machine_id});
  // Imported once the historian stored it and the solver saved its result.
  const ncqual::dds::OrderOutcome order = ncqual::dds::send_acknowledged(
      participant, sets, set, {roles::kHistorian, roles::kSolver}, std::chrono::seconds(60));
  if (!order.silent.empty()) {
    std::cerr << "ncqual import: " << set.request_id << " was not acknowledged within 60 s by the";
    for (const auto& r : order.silent) std::cerr << " " << r;
    std::cerr << " on domain " << domain << "\n";
    return kExitError;
  }
  if (const Acknowledgement* refused = order.refused()) {
    std::cerr << "ncqual import: the " << refused->by << " refused " << set.request_id << ": "
              << refused->detail << "\n";
    return kExitRefused;
  }
  std::cerr << "imported " << what << " as " << to_string(set.kind) << " of " << set.machine_id
            << "\n";
  std::cout << set.request_id << "\n";
  return kExitOk;
}

}  // namespace

void add_import(CLI::App& app, Commands& commands) {
  CLI::App* import = app.add_subcommand(
      "import",
      "publish an instrument's export as a MeasurementSet of the machine: the solver judges\n"
      "it and the historian stores it like a measured check; prints its request id");
  import->require_subcommand(1);
  // The options of every import; `file`: whether it takes one positional FILE.
  const auto add = [&](const std::string& what, const std::string& description, bool file) {
    auto added = add_command(*import, commands, what, description, run);
    const auto& [cmd, o] = added;
    o->what = what;
    if (file) cmd->add_option("FILE", o->file, "the instrument's export")->required();
    add_machine_option(cmd, o->machine, "the machine it measured");
    add_dds_options(cmd, o->dds);
    return added;
  };
  const auto [iso, iso_o] = add("iso230-2", "as kind linear_axis_run, along --axis", true);
  iso->add_option("--axis", iso_o->axis,
                  "the axis of the run (default: the machine's linear_run axis)")
      ->type_name("x|y|z");
  const auto [circle, circle_o] = add("circle", "as kind circle_xy|yz|xz", true);
  circle->add_option("--plane", circle_o->plane, "the plane of the test")->type_name("XY|YZ|XZ");
  circle
      ->add_option(
          "--nominal-radius-mm", circle_o->nominal_radius_mm,
          "F about this radius (default: the file's '# Radius:', else the least-squares circle's)")
      ->type_name("R");
  circle->add_option("--centre-mm", circle_o->centre_mm, "F about this centre (plane's u, v)")
      ->type_name("U,V");
  const auto [grid, grid_o] = add("grid", "as kind global_grid with its master-frame runs", false);
  grid->add_option("--x-run", grid_o->x_run, "the X run of the master frame")
      ->type_name("F")
      ->required();
  grid->add_option("--y-run", grid_o->y_run, "the Y run of the master frame")
      ->type_name("F")
      ->required();
  grid->add_option("--grid", grid_o->grid, "the grid's points")->type_name("F")->required();
  const auto [touches, touches_o] =
      add("touches", "a control's touch log, as the check its program names", true);
  touches->add_option("--program", touches_o->program, "the probing program that wrote it")
      ->type_name("PROG")
      ->required();
  const auto [points, points_o] =
      add("points", "a laser tracker's point export, as the tracker check its nominal list names",
          true);
  points->add_option("--nominals", points_o->program, "the nominal list it was measured to")
      ->type_name("LIST")
      ->required();
}

}  // namespace ncqual::cli
