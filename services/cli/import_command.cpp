#include "import_command.hpp"

#include "ncqual/args.hpp"
#include "ncqual/clock.hpp"
#include "ncqual/config.hpp"
#include "ncqual/csv.hpp"
#include "ncqual/dds/endpoint.hpp"
#include "ncqual/dds/participant.hpp"
#include "ncqual/dds/topics.hpp"
#include "ncqual/solver/instrument_files.hpp"

#include <unistd.h>

#include <chrono>
#include <iostream>
#include <sstream>

namespace ncqual {

const char* const kImportUsage =
    "  import iso230-2 FILE --machine M [--axis x|y|z] [--plant F] [--domain N]\n"
    "  import circle FILE --machine M [--plane XY|YZ|XZ] [--nominal-radius-mm R] [--centre-mm U,V]\n"
    "  import grid --x-run F --y-run F --grid F --machine M [--plant F] [--domain N]\n"
    "      publish an instrument's export as a MeasurementSet: the solver judges it and the\n"
    "      historian stores it like a measured check; prints its request id\n";

namespace {

constexpr int kExitError = 1, kExitUsage = 2;

int usage_error(const std::string& message) {
  std::cerr << "ncqual import: " << message << "\nusage:\n" << kImportUsage;
  return kExitUsage;
}

std::string single_file(const Args& args) {
  if (args.positional().size() != 1) throw ArgError("give exactly one FILE to import");
  return args.positional().front();
}

}  // namespace

int run_import(const std::vector<std::string>& all) {
  if (all.empty()) return usage_error("say what to import");
  const std::string what = all[0];
  const std::vector<std::string> rest(all.begin() + 1, all.end());
  try {
    const Args args(rest,
                    {"machine", "plant", "domain", "axis", "plane", "nominal-radius-mm",
                     "centre-mm", "x-run", "y-run", "grid"},
                    {});
    const PlantConfig plant = load_plant_config(plant_config_path(args.get_or("plant", "")));
    const std::string machine_id = args.require("machine");
    const MachineConfig* machine = plant.find_machine(machine_id);
    if (!machine) throw ArgError("--machine '" + machine_id + "' is not configured in " + plant.source_path);
    if (!machine->global_check) {
      throw ArgError("machine '" + machine_id + "' has no global_check: section (" +
                     machine->source_path + "): its tracker checks cannot be judged");
    }
    const GlobalCheckConfig& gc = *machine->global_check;
    const ProbeGeometry& target = gc.targets.front();

    const WallClock clock;
    MeasurementSet set;
    set.machine_id = machine_id;
    set.request_id = "import-" + machine_id + "-" + std::to_string(clock.now_ns()) + "-" +
                     std::to_string(getpid());
    set.instrument = "import";
    set.frame = "tracker";
    set.time_ns = clock.now_ns();
    set.parameters.push_back({"imported", 1, ""});
    if (what == "iso230-2") {
      const std::string file = single_file(args);
      int axis = gc.linear_run.axis;
      if (const auto a = args.get("axis")) {
        if (*a != "x" && *a != "y" && *a != "z") throw ArgError("--axis '" + *a + "': expected x, y or z");
        axis = (*a)[0] - 'x';
      }
      const solver::Iso230_2File run = solver::read_iso230_2_csv(read_csv_file(file));
      set.kind = CheckKind::LinearAxisRun;
      set.frame = "machine";
      set.parameters.push_back({"axis", static_cast<double>(axis), ""});
      set.tracker_points = solver::tracker_points_for_linear_run(run, axis, gc.linear_run.at_mm, target);
    } else if (what == "circle") {
      const std::string file = single_file(args);
      std::optional<solver::Plane> plane;
      if (const auto p = args.get("plane")) {
        plane = solver::parse_plane(*p);
        if (!plane) throw ArgError("--plane '" + *p + "': expected XY, YZ or XZ");
      }
      const solver::CircleFile circle = solver::read_circle_csv(read_csv_file(file), plane);
      set.kind = circle.input.plane == solver::Plane::XY   ? CheckKind::CircleXY
                 : circle.input.plane == solver::Plane::YZ ? CheckKind::CircleYZ
                                                           : CheckKind::CircleXZ;
      set.frame = "machine";
      if (args.has("nominal-radius-mm")) {
        set.parameters.push_back({"nominal_radius_mm", args.get_double("nominal-radius-mm", 0), "mm"});
      }
      if (const auto c = args.get("centre-mm")) {
        std::stringstream in(*c);
        double u = 0, v = 0;
        char comma = 0;
        if (!(in >> u >> comma >> v) || comma != ',') {
          throw ArgError("--centre-mm '" + *c + "': expected two numbers U,V (mm)");
        }
        set.parameters.push_back({"centre_u_mm", u, "mm"});
        set.parameters.push_back({"centre_v_mm", v, "mm"});
      }
      AxisPosition centre;
      centre.x_mm = gc.circle.centre_mm.x();
      centre.y_mm = gc.circle.centre_mm.y();
      centre.z_mm = gc.circle.centre_mm.z();
      set.tracker_points = solver::tracker_points_for_circle(
          circle, stylus_ball_centre(centre, target), target);
    } else if (what == "grid") {
      if (!args.positional().empty()) throw ArgError("grid takes its files as options");
      auto read = [](const std::string& f) { return solver::read_grid_csv(read_csv_file(f)); };
      set.kind = CheckKind::GlobalGrid;
      set.tracker_points = solver::tracker_points_for_grid(
          read(args.require("x-run")), read(args.require("y-run")), read(args.require("grid")),
          target);
    } else {
      return usage_error("unknown export '" + what + "'");
    }

    const int domain = ncqual::dds::resolve_domain_id(args.get_int("domain", -1), plant.domain_id);
    ncqual::dds::Participant participant({domain, plant.qos_profiles_file, "ncqual-import"});
    ncqual::dds::Writer<ncqual::dds::MeasurementSetTopic> sets(participant);
    // The solver and the historian both read measurement sets: wait for both.
    if (!sets.wait_for_readers(2, std::chrono::seconds(10))) {
      std::cerr << "ncqual import: the solver and the historian are not both listening on domain "
                << domain << "\n";
      return kExitError;
    }
    if (!sets.write(set) || !sets.wait_for_acknowledgments(std::chrono::seconds(10))) {
      std::cerr << "ncqual import: the measurement set was not acknowledged\n";
      return kExitError;
    }
    std::cerr << "imported " << set.tracker_points.size() << " points as "
              << to_string(set.kind) << " of " << machine_id << "\n";
    std::cout << set.request_id << "\n";
    return 0;
  } catch (const ArgError& e) {
    return usage_error(what + ": " + e.what());
  } catch (const CsvError& e) {
    std::cerr << e.what() << "\n";
    return kExitError;
  } catch (const ConfigError& e) {
    std::cerr << "ncqual import: " << e.what() << "\n";
    return kExitError;
  } catch (const std::invalid_argument& e) {
    std::cerr << "ncqual import: " << e.what() << "\n";
    return kExitError;
  }
}

}  // namespace ncqual
