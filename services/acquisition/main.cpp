// ncqual-acquisition: one per machine tool. Answers the CheckRequests of its machine by
// performing the moves on the instrument (here: the simulator) and publishing the raw
// MeasurementSet. It never judges a measurement. It also stands for the holding fixture's
// control unit: it applies the zero offsets the solver publishes as Compensations (replayed from
// the durable topic after a restart), and a post-calibration that verifies a correction waits
// until that correction is applied. The monthly checks are measured by a simulated laser tracker
// (ncqual/sim/tracker_simulator.hpp) when the machine config has a global_check: section.
#include "ncqual/args.hpp"
#include "ncqual/config.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/log.hpp"
#include "ncqual/sim/fixture_simulator.hpp"
#include "ncqual/sim/machine_simulator.hpp"
#include "ncqual/sim/simulator_config.hpp"
#include "ncqual/sim/tracker_simulator.hpp"

#include <spdlog/spdlog.h>

#include <iostream>
#include <map>
#include <optional>
#include <set>

int main(int argc, char** argv) {
  using namespace ncqual;
  try {
    const Args args(std::vector<std::string>(argv + 1, argv + argc),
                    {"plant", "machine", "machine-config", "domain", "log-level", "max-request-age-s"},
                    {"help"});
    if (args.has("help")) {
      std::cout << "usage: ncqual-acquisition --plant FILE (--machine ID | --machine-config FILE)\n"
                   "                          [--domain N] [--max-request-age-s 600] [--log-level info]\n"
                   "Simulates the machine's instruments from the machine config's simulator section.\n";
      return 0;
    }
    init_logging("acquisition", args.get_or("log-level", "info"));
    const PlantConfig plant = load_plant_config(ncqual::dds::plant_file_from(args.get_or("plant", "")));
    MachineConfig machine;
    if (auto file = args.get("machine-config")) {
      machine = load_machine_config(*file);
    } else {
      const std::string id = args.require("machine");
      const MachineConfig* m = plant.find_machine(id);
      if (!m) throw ConfigError("--machine '" + id + "' is not configured in " + plant.source_path);
      machine = *m;
    }
    const sim::SimulatorConfig sim_config = sim::parse_simulator_config(machine);
    const sim::MachineSimulator simulator(machine, sim_config);
    std::optional<sim::FixtureSimulator> fixture;
    if (machine.fixture) fixture = sim::FixtureSimulator::for_machine(machine, sim_config);
    std::optional<sim::TrackerSimulator> tracker;
    if (machine.global_check) tracker.emplace(machine, sim_config);
    // Requests older than this are history, not work: a restarted acquisition must not move the
    // machine for checks long since answered.
    const std::int64_t max_age_ns =
        static_cast<std::int64_t>(args.get_double("max-request-age-s", 600) * 1e9);

    ncqual::dds::Service service({"acquisition", machine.machine_id,
                          ncqual::dds::resolve_domain_id(args.get_int("domain", -1), plant.domain_id),
                          plant.qos_profiles_file});
    ncqual::dds::Reader<ncqual::dds::CheckRequestTopic> requests(service.participant(), machine.machine_id);
    ncqual::dds::Writer<ncqual::dds::MeasurementSetTopic> sets(service.participant());
    ncqual::dds::Reader<ncqual::dds::CompensationTopic> compensations(service.participant(),
                                                                      machine.machine_id);
    std::set<std::string> performed;
    std::set<std::string> applied;                             // compensations by request id
    std::map<std::string, std::vector<CheckRequest>> waiting;  // by the correction they verify

    // On a simulated clock the measurement is taken at the request's time and takes the
    // instrument's time; on the wall clock it is taken now.
    const bool simulated = plant.simulated_clock;
    auto perform = [&](const CheckRequest& req, const std::string& malformed) {
      const std::int64_t now =
          simulated ? req.time_ns + static_cast<std::int64_t>(sim::check_duration_min(req.kind) * 60e9)
                    : service.clock().now_ns();
      MeasurementSet set;
      const bool fixture_check = req.kind == CheckKind::FixturePreCalibration ||
                                 req.kind == CheckKind::FixturePostCalibration;
      const bool tracker_check = is_tracker_check(req.kind);
      if (!malformed.empty() || (fixture_check && !fixture) || (tracker_check && !tracker)) {
        set.machine_id = req.machine_id;
        set.request_id = req.request_id;
        set.kind = req.kind;
        set.time_ns = now;
        set.parameters = req.parameters;
        set.error = !malformed.empty() ? "malformed CheckRequest: " + malformed
                    : fixture_check    ? "machine '" + machine.machine_id +
                                          "' has no fixture: section to probe"
                                       : "machine '" + machine.machine_id +
                                          "' has no global_check: section for the laser tracker";
      } else if (fixture_check) {
        set = sim::perform_fixture_check(simulator, *fixture, req, now);
      } else if (tracker_check) {
        set = tracker->perform(req, now);
      } else {
        set = simulator.perform(req, now);
      }
      spdlog::info("{} {} {}: {} touches, {} tracker points{}", set.machine_id, set.request_id,
                   to_string(set.kind), set.touches.size(), set.tracker_points.size(),
                   set.error.empty() ? "" : " (" + set.error + ")");
      if (!sets.write(set)) spdlog::error("{}: measurement set could not be queued", set.request_id);
    };

    service.dispatcher().on(compensations, [&](ncqual::dds::Received<Compensation> in) {
      const Compensation& c = in.value;
      if (!in.error.empty() || c.machine_id != machine.machine_id) return;
      if (!applied.insert(c.request_id).second) return;
      if (c.correction.target.rfind("fixture:", 0) == 0) {
        if (!fixture) {
          spdlog::error("{}: zero offsets for {} but this machine has no fixture", c.request_id,
                        c.correction.target);
        } else {
          try {
            fixture->apply_zero_offsets(c.correction);
            spdlog::info("{}: applied {} zero offsets to {}", c.request_id,
                         c.correction.offsets.size(), c.correction.target);
          } catch (const std::invalid_argument& e) {
            spdlog::error("{}: zero offsets refused: {}", c.request_id, e.what());
          }
        }
      }
      // Post-calibrations that waited for this correction run now.
      if (auto it = waiting.find(c.request_id); it != waiting.end()) {
        for (const auto& req : it->second) perform(req, "");
        waiting.erase(it);
      }
    });

    service.dispatcher().on(requests, [&](ncqual::dds::Received<CheckRequest> in) {
      const CheckRequest& req = in.value;
      if (req.machine_id != machine.machine_id) return;  // the filter should have done this
      if (!performed.insert(req.request_id).second) return;
      const std::int64_t now = service.clock().now_ns();
      if (!simulated && now - req.time_ns > max_age_ns) {
        spdlog::info("{} {}: request from {} s ago ignored (older than --max-request-age-s)",
                     req.machine_id, req.request_id, (now - req.time_ns) / 1000000000);
        return;
      }
      if (in.error.empty() && !req.verifies_correction_of.empty() &&
          !applied.count(req.verifies_correction_of)) {
        spdlog::info("{} {}: waiting for the Compensation of {} before measuring",
                     req.machine_id, req.request_id, req.verifies_correction_of);
        waiting[req.verifies_correction_of].push_back(req);
        return;
      }
      perform(req, in.error);
    });
    return service.run();
  } catch (const std::exception& e) {
    std::cerr << "ncqual-acquisition: " << e.what() << "\n";
    return 2;
  }
}
