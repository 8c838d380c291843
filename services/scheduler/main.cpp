// SPDX-License-Identifier: Apache-2.0
// ncqual-scheduler: runs the qualification process (scheduler.hpp) for every machine of the
// plant, or of --machine: reads CheckResults, CheckCommands, Interventions and the historian's
// conflict Alarms, writes CheckRequests and MachineStatus through the outbox of its state file,
// and acknowledges what it received once its decision is saved (answer.hpp). Wall clock: it
// decides as results arrive and once a second; simulated clock: run_simulated (driver.hpp).
#include "ncqual/scheduler/answer.hpp"
#include "ncqual/scheduler/driver.hpp"
#include "ncqual/scheduler/scheduler.hpp"

#include "ncqual/common/command_line.hpp"
#include "ncqual/dds/acknowledged.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/common/log.hpp"

#include <spdlog/spdlog.h>

namespace ncqual {
namespace {

int run(int argc, char** argv) {
  dds::ServiceMain service_main(
      "scheduler",
      "Runs the qualification process of every machine of the plant (or of --machine).");
  scheduler::Flags flags;
  scheduler::add_flags(service_main.app(), flags);
  return service_main.run(argc, argv, [&](PlantConfig loaded) {
    const scheduler::Settings settings = scheduler::settle(std::move(loaded), flags);
    const scheduler::ServedPlant& served = settings.served;
    const PlantConfig& plant = served.plant;
    storage::StateFile state = storage::StateFile::open(settings.state_file);
    // The simulated clock goes on where the state file left it.
    SimulatedClock simulated(scheduler::saved_clock_ns(state).value_or(plant.simulated_start_ns));
    WallClock wall;
    const Clock& clock = plant.simulated_clock ? static_cast<const Clock&>(simulated) : wall;

    dds::Service service(service_main.service_options(plant));
    auto& p = service.participant();
    // One request writer per machine, in its partition: an acquisition reads its machines' only.
    std::vector<std::string> machine_ids;
    for (const auto& m : plant.machines) machine_ids.push_back(m.machine_id);
    dds::MachineWriters<dds::CheckRequestTopic> requests(p, machine_ids);
    dds::Writer<dds::MachineStatusTopic> statuses(p);
    dds::Reader<dds::CheckResultTopic> results(p);
    dds::Reader<dds::CheckCommandTopic> commands(p);
    dds::Reader<dds::InterventionTopic> interventions(p);
    dds::Writer<dds::InterventionTopic> relayed(p);
    // The historian's conflicts: two different sets or results for one request hold the machine.
    dds::Reader<dds::AlarmTopic> alarms(p);
    dds::Acknowledger acks(service, roles::kScheduler);
    dds::Outbox outbox(service, state);
    outbox.route(requests);
    outbox.route(statuses);
    outbox.route(relayed);
    outbox.start();

    // A decision's requests and statuses are saved in its transaction (queue), then written.
    scheduler::Scheduler::Outputs outputs;
    outputs.queue = [&outbox](const std::vector<CheckRequest>& rs,
                              const std::vector<MachineStatus>& ss) {
      std::vector<storage::OutboxEntry> entries;
      entries.reserve(rs.size() + ss.size());
      for (const auto& r : rs) {
        entries.push_back(
            outbox.entry<dds::CheckRequestTopic>(r, {roles::kHistorian, roles::kAcquisition}));
      }
      for (const auto& st : ss) {
        entries.push_back(outbox.entry<dds::MachineStatusTopic>(st, {roles::kHistorian}));
      }
      return entries;
    };
    outputs.written = [&outbox](const std::vector<storage::OutboxEntry>& saved) {
      outbox.written(saved);
    };
    scheduler::Scheduler sched(plant, clock, outputs, &state);
    bool progress = false;
    // Each sample of its machines is answered once the decision is saved (answer.hpp).
    const auto mine = [&served](const std::string& machine_id) {
      return served.others.count(machine_id) == 0;  // else another scheduler's machine
    };
    service.dispatcher().on(results, [&](const dds::Received<CheckResult>& in) {
      if (!mine(in.value.machine_id)) return;
      progress = true;
      const auto a = scheduler::answer_result(sched, in.value, in.error);
      if (a.ack) acks.acknowledge<dds::CheckResultTopic>(in, *a.ack, a.detail);
    });
    service.dispatcher().on(commands, [&](const dds::Received<CheckCommand>& in) {
      if (!mine(in.value.machine_id)) return;
      progress = true;
      const auto a = scheduler::answer_command(sched, in.value, in.error);
      if (a.ack) acks.acknowledge<dds::CheckCommandTopic>(in, *a.ack, a.detail);
    });
    service.dispatcher().on(interventions, [&](const dds::Received<Intervention>& in) {
      if (in.local || !mine(in.value.machine_id)) return;  // local: our own relay
      progress = true;
      const auto a = scheduler::answer_intervention(sched, in.value, in.error);
      if (a.ack == AckOutcome::Accepted) {
        try {
          // Relayed: the historian gets it even if it was down when the operator sent it.
          outbox.send<dds::InterventionTopic>(in.value, {roles::kHistorian});
        } catch (const storage::StorageError& e) {
          spdlog::error("intervention {} not kept for the historian: {}", in.value.intervention_id,
                        e.what());
          return;
        }
      }
      if (a.ack) acks.acknowledge<dds::InterventionTopic>(in, *a.ack, a.detail);
    });
    service.dispatcher().on(alarms, [&](const dds::Received<Alarm>& in) {
      if (mine(in.value.machine_id) && scheduler::answer_alarm(sched, in.value, in.error)) {
        progress = true;
      }
    });
    sched.start(settings.cycle);

    if (!plant.simulated_clock) {
      service.dispatcher().every(std::chrono::seconds(1), [&] { sched.tick(); });
      return service.run();
    }
    // Simulated time: run the calendar as fast as the checks come back (driver.hpp).
    auto& d = service.dispatcher();
    scheduler::run_simulated(sched, simulated,
                             {[&](std::chrono::milliseconds patience) {
                                progress = false;
                                return d.run_until([&] { return progress; }, patience);
                              },
                              [&] { return d.stopping(); }},
                             settings.run);
    outbox.drain(std::chrono::seconds(5));
    return 0;
  });
}

}  // namespace
}  // namespace ncqual

int main(int argc, char** argv) {
  return ncqual::command_line::guarded_main("ncqual-scheduler",
                                            [&] { return ncqual::run(argc, argv); });
}
