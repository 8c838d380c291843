// SPDX-License-Identifier: Apache-2.0
// ncqual-acquisition: answers the CheckRequests of its machine tool(s) by measuring with the
// instruments each machine config's `instrument:` section names (the simulator, or the machine's
// own control through program and results files) and publishing the raw MeasurementSet; it never
// judges one.
// It also stands for the fixture's control unit: it applies the zero offsets the solver publishes
// as Compensations. What a machine does with its requests and compensations is its station's
// (ncqual/acquisition/station.hpp); which machines one process serves, selection.hpp. This file
// wires one station per machine to its readers and its MeasurementSet writer in the machine's own
// partition (docs/deploy.md, "Roles"), through the outbox (docs/architecture.md, "Acknowledged
// storage").
#include "ncqual/acquisition/selection.hpp"
#include "ncqual/acquisition/station.hpp"
#include "ncqual/common/command_line.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/dds/acknowledged.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/common/log.hpp"
#include "ncqual/common/version.hpp"

#include <spdlog/spdlog.h>

#include <memory>
#include <optional>

namespace {

using namespace ncqual;

// One machine served: its station, fed by its request and compensation readers (in the machine's
// partition, filtered to its id).
class Served {
 public:
  // Requests and compensations are acknowledged (role acquisition) once the station settled
  // them: their senders keep them until then.
  Served(ncqual::dds::Service& service, ncqual::dds::Acknowledger& acks,
         std::unique_ptr<acquisition::Station> station)
      : station_(std::move(station)),
        requests_(service.participant(), station_->id()),
        compensations_(service.participant(), station_->id()) {
    const Clock& clock = service.clock();
    acquisition::Station& s = *station_;
    service.dispatcher().on(
        compensations_, [&s, &clock, &acks](const ncqual::dds::Received<Compensation>& in) {
          if (!in.error.empty()) {
            spdlog::error("compensation {} refused: {}", in.value.request_id, in.error);
            acks.acknowledge<ncqual::dds::CompensationTopic>(in, AckOutcome::Refused, in.error);
          } else if (s.on_compensation(in.value, clock.now_ns())) {
            acks.acknowledge<ncqual::dds::CompensationTopic>(in, AckOutcome::Accepted);
          }
        });
    service.dispatcher().on(
        requests_, [&s, &clock, &acks](const ncqual::dds::Received<CheckRequest>& in) {
          if (s.on_request(in.value, in.error, clock.now_ns())) {
            acks.acknowledge<ncqual::dds::CheckRequestTopic>(in, AckOutcome::Accepted);
          }
        });
    // Measurements that go on outside the process (a control running its program) come back
    // here; their requests are acknowledged when they are sent again.
    service.dispatcher().every(std::chrono::milliseconds(1000),
                               [&s, &clock] { s.poll(clock.now_ns()); });
  }

 private:
  std::unique_ptr<acquisition::Station> station_;
  ncqual::dds::Reader<ncqual::dds::CheckRequestTopic> requests_;
  ncqual::dds::Reader<ncqual::dds::CompensationTopic> compensations_;
};

int run(int argc, char** argv) {
  using namespace ncqual;
  ncqual::dds::ServiceMain service_main(
      "acquisition",
      "Measures the checks of the machines named with the instruments each machine config's\n"
      "instrument: section names: the simulator (its simulator: section), or the machine's own\n"
      "control, handed a probing program in a folder and read back from its results file\n"
      "(control-files; docs/connecting-a-machine.md).\n"
      "One process serves every machine named; each keeps its own state.");
  CLI::App& app = service_main.app();
  acquisition::MachineSelection selection;
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
  return service_main.run(argc, argv, [&](PlantConfig loaded) {
    const PlantConfig plant = std::move(loaded);
    const std::vector<MachineConfig> machines = acquisition::served_machines(selection, plant);
    const std::int64_t max_age_ns = static_cast<std::int64_t>(max_age_s * 1e9);

    // The heartbeat names the machines served: one id, or the ids joined by commas.
    const std::string served = acquisition::served_ids(machines);
    ncqual::dds::Service service(service_main.service_options(plant, served));
    // One writer per machine, in its partition: on a secured plant the permissions of this
    // acquisition's identity allow those partitions only.
    ncqual::dds::MachineWriters<ncqual::dds::MeasurementSetTopic> sets(
        service.participant(), acquisition::ids_of(machines));
    storage::StateFile state = storage::StateFile::open(
        state_flag.value_or(acquisition::default_state_file(selection, machines, plant)));
    const auto documents = state.load();
    ncqual::dds::Outbox outbox(service, state);
    outbox.route(sets);
    outbox.start();
    ncqual::dds::Acknowledger acks(service, roles::kAcquisition);
    // The entry a station saves with its record (queue), written once saved (publish).
    std::vector<storage::OutboxEntry> staged;
    const auto queue = [&outbox, &staged](const MeasurementSet& set) {
      staged = {
          outbox.entry<ncqual::dds::MeasurementSetTopic>(set, {roles::kHistorian, roles::kSolver})};
      return staged;
    };
    const auto publish = [&outbox, &staged](const MeasurementSet&) {
      outbox.written(staged);
      staged.clear();
      return true;
    };
    const acquisition::StationOptions station_options{plant.simulated_clock, max_age_ns};
    std::vector<std::unique_ptr<Served>> stations;
    for (const auto& m : machines) {
      acquisition::PerformedRequests performed(state, m.machine_id);
      performed.load(documents);
      stations.push_back(std::make_unique<Served>(
          service, acks,
          std::make_unique<acquisition::Station>(
              m.machine_id,
              acquisition::make_instruments(m, service.clock(), version_line("ncqual")),
              std::move(performed), station_options, publish, queue)));
    }
    spdlog::info("serving {} machine(s): {}", stations.size(), served);
    return service.run();
  });
}

}  // namespace

int main(int argc, char** argv) {
  return ncqual::command_line::guarded_main("ncqual-acquisition", [&] { return run(argc, argv); });
}
