// SPDX-License-Identifier: Apache-2.0
// ncqual-scheduler: runs the qualification process (scheduler.hpp) for every machine of the
// plant, or of --machine. Reads CheckResults, CheckCommands, Interventions and the historian's
// conflict Alarms (a check whose record is in doubt holds its machine); writes
// CheckRequests and MachineStatus; its durable state is the plant's scheduler.state_database.
// Acknowledged (docs/architecture.md, "Acknowledged storage"): its requests, statuses and the
// interventions it applied stay in the state file's outbox until the historian stored them; it
// acknowledges every result, order and intervention of its machines once its decision is saved,
// so a result produced while it was down is sent again by the solver until it is learnt.
// Wall clock: it decides as results arrive and once a second; simulated clock: run_simulated
// (driver.hpp). This file parses the command line and wires DDS to the Scheduler and driver.hpp.
#include "ncqual/scheduler/driver.hpp"
#include "ncqual/scheduler/scheduler.hpp"

#include "ncqual/common/command_line.hpp"
#include "ncqual/dds/acknowledged.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/common/log.hpp"

#include <spdlog/spdlog.h>

#include <iostream>
#include <set>

namespace {

int run(int argc, char** argv) {
  using namespace ncqual;
  ncqual::dds::ServiceMain service_main(
      "scheduler",
      "Runs the qualification process of every machine of the plant (or of --machine).");
  CLI::App& app = service_main.app();
  std::optional<std::string> machine_list, cycle_text, state_flag, until_text;
  std::optional<double> days;
  double stall_s = 30;
  std::optional<double> speed;
  app.add_option("--machine", machine_list,
                 "serve only these machines (one scheduler per machine or group; default: all)")
      ->type_name("ID[,ID...]");
  app.add_option("--cycle", cycle_text,
                 "checks to run once at start, in order (default without a calendar: the "
                 "plant's scheduler.startup_checks; '' for none)")
      ->type_name("KIND,KIND,...");
  app.add_option("--state", state_flag,
                 "the durable state file (default: the plant's scheduler.state_database; with "
                 "--machine, scheduler-<ids>.db beside it)")
      ->type_name("FILE");
  app.add_option("--days", days, "simulated clock only: stop once nothing is due before that time")
      ->type_name("N");
  app.add_option("--until", until_text, "simulated clock only: as --days, to an ISO 8601 UTC time")
      ->type_name("ISO-TIME");
  app.add_option("--stall-s", stall_s,
                 "simulated clock: wall seconds without an answer before the clock runs on to "
                 "the check's timeout")
      ->type_name("S")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--speed", speed,
                 "simulated clock: at most X simulated seconds per wall second (default: as fast "
                 "as the checks come back)")
      ->type_name("X")
      ->check(CLI::PositiveNumber);
  return service_main.run(argc, argv, [&](PlantConfig loaded) {
    const scheduler::ServedPlant served = scheduler::serve_only(std::move(loaded), machine_list);
    const PlantConfig& plant = served.plant;
    const std::vector<CheckKind> cycle =
        cycle_text ? scheduler::check_kind_list(*cycle_text)
                   : (plant.calendar ? std::vector<CheckKind>{} : plant.startup_checks);
    const std::optional<std::int64_t> until = scheduler::simulated_run_end(plant, days, until_text);
    if (speed && !plant.simulated_clock) {
      throw std::invalid_argument("--speed needs the plant's clock.mode: simulated");
    }
    storage::StateFile state =
        storage::StateFile::open(state_flag.value_or(plant.scheduler_state_database));
    // The simulated clock goes on where the state file left it.
    SimulatedClock simulated(scheduler::saved_clock_ns(state).value_or(plant.simulated_start_ns));
    WallClock wall;
    const Clock& clock = plant.simulated_clock ? static_cast<const Clock&>(simulated) : wall;

    ncqual::dds::Service service(service_main.service_options(plant));
    auto& p = service.participant();
    // One request writer per machine, in its partition: an acquisition reads its machines' only.
    std::vector<std::string> machine_ids;
    for (const auto& m : plant.machines) machine_ids.push_back(m.machine_id);
    ncqual::dds::MachineWriters<ncqual::dds::CheckRequestTopic> requests(p, machine_ids);
    ncqual::dds::Writer<ncqual::dds::MachineStatusTopic> statuses(p);
    ncqual::dds::Reader<ncqual::dds::CheckResultTopic> results(p);
    ncqual::dds::Reader<ncqual::dds::CheckCommandTopic> commands(p);
    ncqual::dds::Reader<ncqual::dds::InterventionTopic> interventions(p);
    ncqual::dds::Writer<ncqual::dds::InterventionTopic> relayed(p);
    // The historian's conflicts: two different sets or results for one request hold the machine.
    ncqual::dds::Reader<ncqual::dds::AlarmTopic> alarms(p);
    ncqual::dds::Acknowledger acks(service, roles::kScheduler);
    ncqual::dds::Outbox outbox(service, state);
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
        entries.push_back(outbox.entry<ncqual::dds::CheckRequestTopic>(
            r, {roles::kHistorian, roles::kAcquisition}));
      }
      for (const auto& st : ss) {
        entries.push_back(outbox.entry<ncqual::dds::MachineStatusTopic>(st, {roles::kHistorian}));
      }
      return entries;
    };
    outputs.written = [&outbox](const std::vector<storage::OutboxEntry>& saved) {
      outbox.written(saved);
    };
    scheduler::Scheduler sched(plant, clock, outputs, &state);
    bool progress = false;
    service.dispatcher().on(results, [&](const ncqual::dds::Received<CheckResult>& in) {
      if (served.others.count(in.value.machine_id)) return;  // another scheduler's machine
      progress = true;
      if (!in.error.empty()) {
        spdlog::error("result {} of '{}' refused: {}", in.value.request_id, in.value.machine_id,
                      in.error);
        acks.acknowledge<ncqual::dds::CheckResultTopic>(in, AckOutcome::Refused, in.error);
        return;
      }
      sched.result(in.value);
      if (sched.saved()) acks.acknowledge<ncqual::dds::CheckResultTopic>(in, AckOutcome::Accepted);
    });
    service.dispatcher().on(commands, [&](const ncqual::dds::Received<CheckCommand>& in) {
      if (served.others.count(in.value.machine_id)) return;  // another scheduler's machine
      progress = true;
      const std::string refused = in.error.empty() ? sched.command(in.value) : in.error;
      if (!refused.empty()) {
        spdlog::error("check command {} refused: {}", in.value.request_id, refused);
        acks.acknowledge<ncqual::dds::CheckCommandTopic>(in, AckOutcome::Refused, refused);
      } else if (sched.saved()) {
        acks.acknowledge<ncqual::dds::CheckCommandTopic>(in, AckOutcome::Accepted);
      }
    });
    service.dispatcher().on(interventions, [&](const ncqual::dds::Received<Intervention>& in) {
      if (in.local) return;                                  // our own relay to the historian
      if (served.others.count(in.value.machine_id)) return;  // another scheduler's machine
      progress = true;
      if (!in.error.empty()) {
        spdlog::warn("intervention {} refused: {}", in.value.intervention_id, in.error);
        acks.acknowledge<ncqual::dds::InterventionTopic>(in, AckOutcome::Refused, in.error);
        return;
      }
      const std::string unchanged = sched.intervention(in.value);
      if (!unchanged.empty())
        spdlog::warn("intervention {}: {}", in.value.intervention_id, unchanged);
      if (!sched.saved()) return;
      try {
        // Relayed: the historian gets it even if it was down when the operator sent it.
        outbox.send<ncqual::dds::InterventionTopic>(in.value, {roles::kHistorian});
      } catch (const storage::StorageError& e) {
        spdlog::error("intervention {} not kept for the historian: {}", in.value.intervention_id,
                      e.what());
        return;
      }
      acks.acknowledge<ncqual::dds::InterventionTopic>(in, AckOutcome::Accepted, unchanged);
    });
    service.dispatcher().on(alarms, [&](const ncqual::dds::Received<Alarm>& in) {
      const auto conflict = scheduler::check_conflict_of(in.value);
      if (!conflict || served.others.count(in.value.machine_id)) return;
      if (!in.error.empty()) {
        spdlog::error("alarm {} not read: {}", in.value.alarm_id, in.error);
        return;
      }
      progress = true;
      const std::string unchanged = sched.conflict(in.value.machine_id, *conflict, in.value.text);
      if (!unchanged.empty()) spdlog::warn("conflict {}: {}", in.value.alarm_id, unchanged);
    });
    sched.start(cycle);

    if (!plant.simulated_clock) {
      service.dispatcher().every(std::chrono::seconds(1), [&] { sched.tick(); });
      return service.run();
    }
    // Simulated time: run the calendar as fast as the checks come back (driver.hpp).
    auto& d = service.dispatcher();
    scheduler::SimulatedRunOptions run_options;
    run_options.until_ns = until;
    run_options.stall = std::chrono::milliseconds(static_cast<std::int64_t>(stall_s * 1000));
    run_options.speed = speed;
    scheduler::run_simulated(sched, simulated,
                             {[&](std::chrono::milliseconds patience) {
                                progress = false;
                                return d.run_until([&] { return progress; }, patience);
                              },
                              [&] { return d.stopping(); }},
                             run_options);
    outbox.drain(std::chrono::seconds(5));
    return 0;
  });
}

}  // namespace

int main(int argc, char** argv) {
  return ncqual::command_line::guarded_main("ncqual-scheduler", [&] { return run(argc, argv); });
}
