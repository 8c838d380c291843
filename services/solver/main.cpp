// SPDX-License-Identifier: Apache-2.0
// ncqual-solver: turns MeasurementSets into CheckResults (and Compensations) with the pure
// solver library. Thin: arguments, wiring, publishing. No storage, no math here.
#include "ncqual/command_line.hpp"
#include "ncqual/config.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/log.hpp"
#include "ncqual/version.hpp"
#include "ncqual/solver/solve.hpp"

#include <spdlog/spdlog.h>

#include <deque>
#include <iostream>
#include <unordered_set>

namespace {

// Remembers the request ids solved recently, so that a set delivered twice (a restarted
// acquisition, two paths) is answered once. Bounded: oldest forgotten first.
class RecentIds {
 public:
  explicit RecentIds(std::size_t capacity) : capacity_(capacity) {}
  bool insert(const std::string& id) {
    if (!seen_.insert(id).second) return false;
    order_.push_back(id);
    if (order_.size() > capacity_) {
      seen_.erase(order_.front());
      order_.pop_front();
    }
    return true;
  }

 private:
  std::size_t capacity_;
  std::unordered_set<std::string> seen_;
  std::deque<std::string> order_;
};

int run(int argc, char** argv) {
  using namespace ncqual;
  ncqual::dds::ServiceMain service_main(
      "solver", "Turns the plant's MeasurementSets into CheckResults (and Compensations).");
  return service_main.run(argc, argv, [&](PlantConfig loaded) {
    const PlantConfig plant = std::move(loaded);
    ncqual::dds::Service service(service_main.service_options(plant));
    ncqual::dds::Reader<ncqual::dds::MeasurementSetTopic> sets(service.participant());
    ncqual::dds::Writer<ncqual::dds::CheckResultTopic> results(service.participant());
    ncqual::dds::Writer<ncqual::dds::CompensationTopic> compensations(service.participant());
    RecentIds solved(10000);

    const std::string produced_by = version_line("ncqual-solver");
    service.dispatcher().on(sets, [&](const ncqual::dds::Received<MeasurementSet>& in) {
      const MeasurementSet& set = in.value;
      if (!solved.insert(set.request_id)) {
        spdlog::debug("{} {}: already solved, ignored", set.machine_id, set.request_id);
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
      spdlog::info("{} {} {}: {}{}", result.machine_id, result.request_id, to_string(result.kind),
                   to_string(result.verdict),
                   result.reason.empty() ? "" : " (" + result.reason + ")");
      if (!results.write(result)) {
        spdlog::error("{} {}: result could not be queued", result.machine_id, result.request_id);
      }
      if (result.correction) {
        compensations.write(
            Compensation{result.machine_id, result.request_id, *result.correction, result.time_ns});
      }
    });
    return service.run();
  });
}

}  // namespace

int main(int argc, char** argv) {
  return ncqual::command_line::guarded_main("ncqual-solver", [&] { return run(argc, argv); });
}
