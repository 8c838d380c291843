// SPDX-License-Identifier: Apache-2.0
// ncqual-solver: turns MeasurementSets into CheckResults (and Compensations) with the pure
// solver library. Thin: arguments, wiring, publishing. No math here.
//
// Exactly one result per measurement set: what it does with each set received, and the sets it
// solved, are the core's (ncqual/solver_service/solved_sets.hpp); here the set is read, the answer
// written through the outbox and the set acknowledged once the answer is saved.
#include "ncqual/common/command_line.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/dds/acknowledged.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/common/log.hpp"
#include "ncqual/solver_service/solved_sets.hpp"
#include "ncqual/storage/state_file.hpp"
#include "ncqual/common/version.hpp"

#include <spdlog/spdlog.h>

#include <filesystem>

namespace {

using namespace ncqual;
using solver_service::SetAction;

int run(int argc, char** argv) {
  ncqual::dds::ServiceMain service_main(
      "solver", "Turns the plant's MeasurementSets into CheckResults (and Compensations).");
  std::optional<std::string> state_flag;
  service_main.app()
      .add_option("--state", state_flag,
                  "the sets solved and the results not yet acknowledged (default: solver.db "
                  "beside the historian's database)")
      ->type_name("FILE");
  return service_main.run(argc, argv, [&](PlantConfig loaded) {
    const PlantConfig plant = std::move(loaded);
    storage::StateFile state = storage::StateFile::open(state_flag.value_or(
        (std::filesystem::path(plant.historian_database).parent_path() / "solver.db").string()));
    solver_service::SolvedSets solved(state);
    ncqual::dds::Service service(service_main.service_options(plant));
    // Sets are read in each machine's partition (a set naming another machine is refused), and
    // a machine's compensations written in its partition, where its acquisition reads them.
    std::vector<std::string> machine_ids;
    for (const auto& m : plant.machines) machine_ids.push_back(m.machine_id);
    ncqual::dds::MachineReaders<ncqual::dds::MeasurementSetTopic> sets(service.participant(),
                                                                       machine_ids);
    ncqual::dds::Writer<ncqual::dds::CheckResultTopic> results(service.participant());
    ncqual::dds::MachineWriters<ncqual::dds::CompensationTopic> compensations(service.participant(),
                                                                              machine_ids);
    ncqual::dds::Acknowledger acks(service, roles::kSolver);
    ncqual::dds::Outbox outbox(service, state);
    outbox.route(results);
    outbox.route(compensations);
    outbox.start();

    const std::string produced_by = version_line("ncqual-solver");
    service.dispatcher().on(sets, [&](const ncqual::dds::Received<MeasurementSet>& in) {
      const MeasurementSet& set = in.value;
      const auto decision = solver_service::decide(
          solved, {set, in.content_hash, in.writer, in.foreign, in.foreign ? in.error : ""});
      switch (decision.action) {
        case SetAction::Refuse:
          // Written on another machine's behalf: no answer for that machine, only the refusal.
          spdlog::error("{} {}: measurement set from writer {} refused: {}", set.machine_id,
                        set.request_id, in.writer, decision.detail);
          acks.acknowledge<ncqual::dds::MeasurementSetTopic>(in, AckOutcome::Refused,
                                                             decision.detail);
          return;
        case SetAction::AcknowledgeAgain:
          spdlog::debug("{} {}: already solved, acknowledged again", set.machine_id,
                        set.request_id);
          acks.acknowledge<ncqual::dds::MeasurementSetTopic>(in, AckOutcome::Accepted,
                                                             decision.detail);
          return;
        case SetAction::Conflict:
          spdlog::error("{} {}: {}", set.machine_id, set.request_id, decision.detail);
          acks.acknowledge<ncqual::dds::MeasurementSetTopic>(in, AckOutcome::Conflict,
                                                             decision.detail);
          return;
        case SetAction::Solve: break;
      }
      // On a simulated clock a result is stamped with its measurement's time (judging takes no
      // simulated time); on the wall clock, now.
      const std::int64_t now = plant.simulated_clock ? set.time_ns : service.clock().now_ns();
      const CheckResult result = solver_service::answer(set, in.error, plant, now, produced_by);
      spdlog::info("{} {} {}: {}{} (set {} from writer {})", result.machine_id, result.request_id,
                   to_string(result.kind), to_string(result.verdict),
                   result.reason.empty() ? "" : " (" + result.reason + ")",
                   ncqual::dds::where_received(in), in.writer);
      std::vector<storage::OutboxEntry> answer{outbox.entry<ncqual::dds::CheckResultTopic>(
          result, {roles::kHistorian, roles::kScheduler})};
      if (const auto compensation = solver_service::compensation_of(result)) {
        answer.push_back(outbox.entry<ncqual::dds::CompensationTopic>(
            *compensation, {roles::kHistorian, roles::kAcquisition}));
      }
      try {
        solved.save(set, in.content_hash, in.writer, answer);
      } catch (const storage::StorageError& e) {
        // Not acknowledged: the acquisition sends the set again and it is solved then.
        spdlog::error("{} {}: result not saved to {}: {}", set.machine_id, set.request_id,
                      state.path(), e.what());
        return;
      }
      outbox.written(answer);
      acks.acknowledge<ncqual::dds::MeasurementSetTopic>(in, AckOutcome::Accepted);
    });
    return service.run();
  });
}

}  // namespace

int main(int argc, char** argv) {
  return ncqual::command_line::guarded_main("ncqual-solver", [&] { return run(argc, argv); });
}
