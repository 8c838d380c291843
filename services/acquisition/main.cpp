// ncqual-acquisition: answers the CheckRequests of its machine tool(s) by performing the moves on
// the instrument (here: the simulator) and publishing the raw MeasurementSet. One process may
// serve several machines (--machine a,b,c or --all): each has its own station (simulators,
// machine-filtered readers, the requests it performed and the corrections it applied), and
// nothing is shared between stations but the participant and the MeasurementSet writer. A plant
// runs one per machine's control cabinet, or one on a cell computer for a group of machines. It never judges a measurement. It also stands for the holding fixture's
// control unit: it applies the zero offsets the solver publishes as Compensations (replayed from
// the durable topic after a restart), and a post-calibration that verifies a correction waits
// until that correction is applied. The monthly checks are measured by a simulated laser tracker
// (ncqual/sim/tracker_simulator.hpp) when the machine config has a global_check: section.
#include "ncqual/check_kinds.hpp"
#include "ncqual/command_line.hpp"
#include "ncqual/config.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/log.hpp"
#include "ncqual/sim/fixture_simulator.hpp"
#include "ncqual/sim/machine_simulator.hpp"
#include "ncqual/sim/simulator_config.hpp"
#include "ncqual/sim/tracker_simulator.hpp"
#include "ncqual/state_file.hpp"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <deque>
#include <filesystem>
#include <iostream>
#include <memory>
#include <map>
#include <optional>
#include <set>

namespace {

using namespace ncqual;

// The state file's document of a measured request: {"seq": N}, its place in the order measured.
struct PerformedEntry {
  std::int64_t seq = 0;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(PerformedEntry, seq)

// How many performed request ids each machine remembers in the state file: more than the durable
// CheckRequest history a restarted acquisition can be replayed (500 per machine, deploy/qos).
constexpr std::size_t kRememberedPerformed = 1000;

// One machine tool served by this process.
class Station {
 public:
  Station(const MachineConfig& machine, ncqual::dds::Service& service,
          ncqual::dds::Writer<ncqual::dds::MeasurementSetTopic>& sets, bool simulated,
          std::int64_t max_age_ns, storage::StateFile& state,
          const std::map<std::string, std::string>& documents)
      : machine_(machine),
        sim_config_(machine_.simulator),
        simulator_(machine_, sim_config_),
        service_(service),
        sets_(sets),
        simulated_(simulated),
        max_age_ns_(max_age_ns),
        state_(state),
        requests_(service.participant(), machine_.machine_id),
        compensations_(service.participant(), machine_.machine_id) {
    load_performed(documents);
    if (machine_.fixture) fixture_ = sim::FixtureSimulator::for_machine(machine_, sim_config_);
    if (machine_.global_check) tracker_.emplace(machine_, sim_config_);
    service.dispatcher().on(compensations_, [this](ncqual::dds::Received<Compensation> in) {
      on_compensation(in);
    });
    service.dispatcher().on(requests_, [this](ncqual::dds::Received<CheckRequest> in) {
      on_request(in);
    });
  }
  Station(const Station&) = delete;
  Station& operator=(const Station&) = delete;

  const std::string& id() const { return machine_.machine_id; }

 private:
  // On a simulated clock the measurement is taken at the request's time and takes the
  // instrument's time; on the wall clock it is taken now.
  void perform(const CheckRequest& req, const std::string& malformed) {
    const std::int64_t now =
        simulated_ ? req.time_ns + static_cast<std::int64_t>(check_kind_info(req.kind).duration_min * 60e9)
                   : service_.clock().now_ns();
    MeasurementSet set;
    const bool fixture_check = is_fixture_check(req.kind);
    const bool tracker_check = is_tracker_check(req.kind);
    if (!malformed.empty() || (fixture_check && !fixture_) || (tracker_check && !tracker_)) {
      set.machine_id = req.machine_id;
      set.request_id = req.request_id;
      set.kind = req.kind;
      set.time_ns = now;
      set.parameters = req.parameters;
      set.error = !malformed.empty() ? "malformed CheckRequest: " + malformed
                  : fixture_check    ? "machine '" + id() + "' has no fixture: section to probe"
                                     : "machine '" + id() +
                                        "' has no global_check: section for the laser tracker";
    } else if (fixture_check) {
      set = sim::perform_fixture_check(simulator_, *fixture_, req, now);
    } else if (tracker_check) {
      set = tracker_->perform(req, now);
    } else {
      set = simulator_.perform(req, now);
    }
    spdlog::info("{} {} {}: {} touches, {} tracker points{}", set.machine_id, set.request_id,
                 to_string(set.kind), set.touches.size(), set.tracker_points.size(),
                 set.error.empty() ? "" : " (" + set.error + ")");
    if (!sets_.write(set)) {
      spdlog::error("{}: measurement set could not be queued", set.request_id);
      return;
    }
    remember_performed(req.request_id);
  }

  // The requests this machine already measured, from the state file: a restarted acquisition
  // is replayed the durable request history and must not move the machine for them again.
  void load_performed(const std::map<std::string, std::string>& documents) {
    const std::string prefix = "performed/" + id() + "/";
    std::vector<std::pair<std::int64_t, std::string>> found;
    for (auto it = documents.lower_bound(prefix);
         it != documents.end() && it->first.compare(0, prefix.size(), prefix) == 0; ++it) {
      std::int64_t seq = 0;
      try {
        seq = nlohmann::json::parse(it->second).get<PerformedEntry>().seq;
      } catch (const nlohmann::json::exception&) {
        spdlog::warn("{}: state file {} entry '{}' is not readable; ignored", id(), state_.path(), it->first);
        continue;
      }
      found.emplace_back(seq, it->first.substr(prefix.size()));
    }
    std::sort(found.begin(), found.end());
    for (const auto& [seq, request_id] : found) {
      performed_.insert(request_id);
      performed_order_.push_back(request_id);
      next_seq_ = std::max(next_seq_, seq + 1);
    }
    if (!found.empty()) {
      spdlog::info("{}: {} performed requests remembered from {}", id(), found.size(), state_.path());
    }
  }

  // Records a measured request; forgets the oldest beyond kRememberedPerformed. A failure to
  // write is logged, not fatal: the worst outcome is one repeated measurement after a restart.
  void remember_performed(const std::string& request_id) {
    const std::string prefix = "performed/" + id() + "/";
    performed_order_.push_back(request_id);
    std::vector<std::string> erase;
    while (performed_order_.size() > kRememberedPerformed) {
      erase.push_back(prefix + performed_order_.front());
      performed_order_.pop_front();
    }
    try {
      state_.save({{prefix + request_id, nlohmann::json(PerformedEntry{next_seq_++}).dump()}}, erase);
    } catch (const std::exception& e) {
      spdlog::error("{}: could not record {} as performed: {}", id(), request_id, e.what());
    }
  }

  void on_compensation(const ncqual::dds::Received<Compensation>& in) {
    const Compensation& c = in.value;
    if (!in.error.empty() || c.machine_id != id()) return;
    if (!applied_.insert(c.request_id).second) return;
    if (c.correction.target.rfind("fixture:", 0) == 0) {
      if (!fixture_) {
        spdlog::error("{}: zero offsets for {} but machine '{}' has no fixture", c.request_id,
                      c.correction.target, id());
      } else {
        try {
          fixture_->apply_zero_offsets(c.correction);
          spdlog::info("{}: applied {} zero offsets to {}", c.request_id,
                       c.correction.offsets.size(), c.correction.target);
        } catch (const std::invalid_argument& e) {
          spdlog::error("{}: zero offsets refused: {}", c.request_id, e.what());
        }
      }
    }
    // Post-calibrations that waited for this correction run now.
    if (auto it = waiting_.find(c.request_id); it != waiting_.end()) {
      for (const auto& req : it->second) perform(req, "");
      waiting_.erase(it);
    }
  }

  void on_request(const ncqual::dds::Received<CheckRequest>& in) {
    const CheckRequest& req = in.value;
    if (req.machine_id != id()) return;  // the filter should have done this
    if (!performed_.insert(req.request_id).second) {
      spdlog::debug("{} {}: already performed, not measured again", req.machine_id, req.request_id);
      return;
    }
    const std::int64_t now = service_.clock().now_ns();
    // Requests older than this are history, not work: a restarted acquisition must not move the
    // machine for checks long since answered.
    if (!simulated_ && now - req.time_ns > max_age_ns_) {
      spdlog::info("{} {}: request from {} s ago ignored (older than --max-request-age-s)",
                   req.machine_id, req.request_id, (now - req.time_ns) / 1000000000);
      return;
    }
    if (in.error.empty() && !req.verifies_correction_of.empty() &&
        !applied_.count(req.verifies_correction_of)) {
      spdlog::info("{} {}: waiting for the Compensation of {} before measuring", req.machine_id,
                   req.request_id, req.verifies_correction_of);
      waiting_[req.verifies_correction_of].push_back(req);
      return;
    }
    perform(req, in.error);
  }

  const MachineConfig machine_;
  const sim::SimulatorConfig sim_config_;
  const sim::MachineSimulator simulator_;
  std::optional<sim::FixtureSimulator> fixture_;
  std::optional<sim::TrackerSimulator> tracker_;
  ncqual::dds::Service& service_;
  ncqual::dds::Writer<ncqual::dds::MeasurementSetTopic>& sets_;
  const bool simulated_;
  const std::int64_t max_age_ns_;
  storage::StateFile& state_;
  ncqual::dds::Reader<ncqual::dds::CheckRequestTopic> requests_;
  ncqual::dds::Reader<ncqual::dds::CompensationTopic> compensations_;
  std::set<std::string> performed_;            // requests taken (measured, waiting or refused)
  std::deque<std::string> performed_order_;    // measured ones in the state file, oldest first
  std::int64_t next_seq_ = 0;
  std::set<std::string> applied_;                             // compensations by request id
  std::map<std::string, std::vector<CheckRequest>> waiting_;  // by the correction they verify
};

// What names the machines to serve: --machine (comma-separated ids), --all, or --machine-config.
struct MachineSelection {
  std::optional<std::string> machine, machine_config;
  bool all = false;
};

// The machines named by --machine (comma-separated ids), --all, or --machine-config.
std::vector<MachineConfig> served_machines(const MachineSelection& args, const PlantConfig& plant) {
  std::vector<MachineConfig> out;
  const int ways = (args.all ? 1 : 0) + (args.machine ? 1 : 0) + (args.machine_config ? 1 : 0);
  if (ways != 1) {
    throw ConfigError("name the machines to serve with exactly one of --machine ID[,ID...], --all "
                      "or --machine-config FILE");
  }
  if (args.machine_config) {
    out.push_back(load_machine_config(*args.machine_config));
  } else if (args.all) {
    out = plant.machines;
    if (out.empty()) throw ConfigError("--all: " + plant.source_path + " configures no machine");
  } else {
    out = plant.machines_named(*args.machine, "--machine");
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ncqual;
  CLI::App app("Simulates the machines' instruments from each machine config's simulator section.\n"
               "One process serves every machine named; each keeps its own state.",
               "ncqual-acquisition");
  command_line::configure(app);
  command_line::ServiceOptions options;
  command_line::add_service_options(app, options);
  MachineSelection selection;
  double max_age_s = 600;
  std::optional<std::string> state_flag;
  app.add_option("--machine", selection.machine, "serve these machines of the plant")
      ->type_name("ID[,ID...]");
  app.add_flag("--all", selection.all, "serve every machine of the plant");
  app.add_option("--machine-config", selection.machine_config, "serve the machine of this file")
      ->type_name("FILE");
  app.add_option("--state", state_flag,
                 "the requests already measured, so that a restart does not measure them again\n"
                 "(default: acquisition-<ids>.db, or acquisition-all.db, beside the historian's "
                 "database)")
      ->type_name("FILE");
  app.add_option("--max-request-age-s", max_age_s,
                 "on the wall clock, requests older than this are history, not work")
      ->type_name("S")
      ->capture_default_str();
  if (const auto code = command_line::parse(app, argc, argv)) return *code;
  try {
    init_logging("acquisition", options.log_level);
    const PlantConfig plant = load_plant_config(ncqual::dds::plant_file_from(options.plant));
    const std::vector<MachineConfig> machines = served_machines(selection, plant);
    const std::int64_t max_age_ns = static_cast<std::int64_t>(max_age_s * 1e9);

    // The heartbeat names the machines served: one id, or the ids joined by commas.
    std::string served;
    for (const auto& m : machines) served += (served.empty() ? "" : ",") + m.machine_id;
    ncqual::dds::Service service({"acquisition", served,
                                  ncqual::dds::resolve_domain_id(options.domain, plant.domain_id),
                                  plant.qos_profiles_file});
    ncqual::dds::Writer<ncqual::dds::MeasurementSetTopic> sets(service.participant());
    std::string file_ids = selection.all ? "all" : served;
    std::replace(file_ids.begin(), file_ids.end(), ',', '+');
    storage::StateFile state = storage::StateFile::open(state_flag.value_or(
        (std::filesystem::path(plant.historian_database).parent_path() /
         ("acquisition-" + file_ids + ".db")).string()));
    const auto documents = state.load();
    std::vector<std::unique_ptr<Station>> stations;
    for (const auto& m : machines) {
      stations.push_back(std::make_unique<Station>(m, service, sets, plant.simulated_clock,
                                                   max_age_ns, state, documents));
    }
    spdlog::info("serving {} machine(s): {}", stations.size(), served);
    return service.run();
  } catch (const std::exception& e) {
    std::cerr << "ncqual-acquisition: " << e.what() << "\n";
    return 2;
  }
}
