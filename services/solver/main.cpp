// SPDX-License-Identifier: Apache-2.0
// ncqual-solver: turns MeasurementSets into CheckResults (and Compensations) with the pure
// solver library. Thin: arguments, wiring, publishing. No math here.
//
// Exactly one result per measurement set (docs/architecture.md, "Acknowledged storage"): the
// result, its compensation and the note that the set is solved are saved in one transaction of
// the solver's state file, and only then is the set acknowledged to the acquisition. A set sent
// again (its acknowledgement was lost, the solver was killed) is acknowledged again, never solved
// again. The result stays in the outbox until the historian stored it and the scheduler applied it.
#include "ncqual/common/command_line.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/dds/acknowledged.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/common/json.hpp"
#include "ncqual/common/log.hpp"
#include "ncqual/solver/solve.hpp"
#include "ncqual/storage/state_file.hpp"
#include "ncqual/common/version.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <deque>
#include <filesystem>
#include <iostream>
#include <tuple>
#include <unordered_map>

namespace {

using namespace ncqual;

// A set solved: state document "solved/<request id>". The newest kSolvedKept are kept, far more
// than any outbox or durable history can send again.
struct SolvedDocument {
  std::int64_t time_ns = 0;  // the set's
  std::string content_hash;  // of the set solved ("" when an older version solved it)
  std::string writer;        // its writer's GUID
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(SolvedDocument, time_ns, content_hash, writer)
constexpr std::size_t kSolvedKept = 20000;
constexpr const char* kSolvedPrefix = "solved/";

class SolvedSets {
 public:
  explicit SolvedSets(storage::StateFile& file) : file_(file) {
    std::vector<std::tuple<std::int64_t, std::string, SolvedDocument>> found;
    for (const auto& [key, doc] : file_.load()) {
      if (key.rfind(kSolvedPrefix, 0) != 0) continue;
      try {
        const auto solved = nlohmann::json::parse(doc).get<SolvedDocument>();
        found.emplace_back(solved.time_ns,
                           key.substr(std::char_traits<char>::length(kSolvedPrefix)), solved);
      } catch (const nlohmann::json::exception&) {
        spdlog::warn("solver state {}: '{}' unreadable, ignored", file_.path(), key);
      }
    }
    std::sort(found.begin(), found.end(),
              [](const auto& a, const auto& b) { return std::get<0>(a) < std::get<0>(b); });
    for (const auto& [t, id, solved] : found) {
      ids_[id] = solved;
      order_.push_back(id);
    }
  }
  // The set solved for request `id`, if any.
  const SolvedDocument* find(const std::string& id) const {
    const auto it = ids_.find(id);
    return it == ids_.end() ? nullptr : &it->second;
  }
  // Saves the set as solved, with the outbox entries of its answer, in one transaction.
  void save(const MeasurementSet& set, const std::string& content_hash, const std::string& writer,
            const std::vector<storage::OutboxEntry>& answer) {
    // The oldest beyond the bound go in the same transaction; memory follows once it committed.
    const std::size_t excess =
        order_.size() + 1 > kSolvedKept ? order_.size() + 1 - kSolvedKept : 0;
    std::vector<std::string> erase;
    erase.reserve(excess);
    for (std::size_t i = 0; i < excess; ++i) erase.push_back(kSolvedPrefix + order_[i]);
    const SolvedDocument solved{set.time_ns, content_hash, writer};
    file_.save({{kSolvedPrefix + set.request_id, nlohmann::json(solved).dump()}}, erase, answer);
    for (std::size_t i = 0; i < excess; ++i) {
      ids_.erase(order_.front());
      order_.pop_front();
    }
    order_.push_back(set.request_id);
    ids_[set.request_id] = solved;
  }

 private:
  storage::StateFile& file_;
  std::unordered_map<std::string, SolvedDocument> ids_;
  std::deque<std::string> order_;
};

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
    SolvedSets solved(state);
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
      if (in.foreign) {
        // Written on another machine's behalf: no answer for that machine, only the refusal.
        spdlog::error("{} {}: measurement set from writer {} refused: {}", set.machine_id,
                      set.request_id, in.writer, in.error);
        acks.acknowledge<ncqual::dds::MeasurementSetTopic>(in, AckOutcome::Refused, in.error);
        return;
      }
      if (const SolvedDocument* done = solved.find(set.request_id)) {
        if (done->content_hash.empty() || done->content_hash == in.content_hash) {
          spdlog::debug("{} {}: already solved, acknowledged again", set.machine_id,
                        set.request_id);
          acks.acknowledge<ncqual::dds::MeasurementSetTopic>(in, AckOutcome::Accepted,
                                                             "already solved");
          return;
        }
        // Another set for a request already solved: not solved again, and not forgotten. The
        // historian keeps it as a conflict and raises it; the scheduler holds the machine.
        const std::string detail = "conflicting measurements of " + set.request_id +
                                   ": solved from writer " + done->writer + "'s set (content " +
                                   done->content_hash.substr(0, 12) + "), this one from writer " +
                                   in.writer + " (content " + in.content_hash.substr(0, 12) +
                                   ") differs; not solved again";
        spdlog::error("{} {}: {}", set.machine_id, set.request_id, detail);
        acks.acknowledge<ncqual::dds::MeasurementSetTopic>(in, AckOutcome::Conflict, detail);
        return;
      }
      // On a simulated clock a result is stamped with its measurement's time (judging takes no
      // simulated time); on the wall clock, now.
      const std::int64_t now = plant.simulated_clock ? set.time_ns : service.clock().now_ns();
      CheckResult result;
      if (!in.error.empty()) {
        // A malformed sample still gets an answer, so the scheduler is never left waiting.
        result.machine_id = set.machine_id;
        result.request_id = set.request_id;
        result.kind = set.kind;
        result.verdict = Verdict::Invalid;
        result.reason = in.error;
        result.time_ns = now;
      } else {
        result = solver::solve(set, plant, now);
      }
      result.produced_by = produced_by;  // every verdict names the software that made it
      spdlog::info("{} {} {}: {}{} (set {} from writer {})", result.machine_id, result.request_id,
                   to_string(result.kind), to_string(result.verdict),
                   result.reason.empty() ? "" : " (" + result.reason + ")",
                   ncqual::dds::where_received(in), in.writer);
      std::vector<storage::OutboxEntry> answer{outbox.entry<ncqual::dds::CheckResultTopic>(
          result, {roles::kHistorian, roles::kScheduler})};
      if (result.correction) {
        answer.push_back(outbox.entry<ncqual::dds::CompensationTopic>(
            Compensation{result.machine_id, result.request_id, *result.correction, result.time_ns},
            {roles::kHistorian, roles::kAcquisition}));
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
