// SPDX-License-Identifier: Apache-2.0
// ncqual-historian: one per plant. Stores every request, measurement set, result,
// compensation, status change, intervention and service heartbeat in SQLite, exactly once
// (storing is idempotent on each sample's id, so DDS redelivery after a restart is harmless).
#include "ncqual/command_line.hpp"
#include "ncqual/config.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/log.hpp"
#include "ncqual/storage.hpp"

#include <spdlog/spdlog.h>

#include <iostream>

namespace {

// The id the log names a sample by: its request's, but for interventions and heartbeats.
template <typename Model>
std::string sample_id(const Model& sample) {
  return sample.request_id;
}
std::string sample_id(const ncqual::Intervention& sample) { return sample.intervention_id; }
std::string sample_id(const ncqual::Heartbeat& sample) {
  return sample.service + "@" + sample.instance;
}

// Stores one received sample; a bad sample is logged with its reason and skipped, and the
// historian keeps running with everything already stored intact.
template <typename Model>
void store(ncqual::storage::Database& db, const char* what,
           const ncqual::dds::Received<Model>& in) {
  const std::string& machine_id = in.value.machine_id;
  const std::string id = sample_id(in.value);
  if (!in.error.empty()) {
    spdlog::error("{} {} of machine '{}' not stored: {}", what, id, machine_id, in.error);
    return;
  }
  try {
    if (db.store(in.value)) {
      spdlog::debug("stored {} {} of {}", what, id, machine_id);
    } else {
      spdlog::debug("{} {} of {} already stored", what, id, machine_id);
    }
  } catch (const ncqual::storage::StorageError& e) {
    spdlog::error("{} {} of machine '{}' not stored: {}", what, id, machine_id, e.what());
  }
}

int run(int argc, char** argv) {
  using namespace ncqual;
  ncqual::dds::ServiceMain service_main(
      "historian", "Stores every sample of the plant in the SQLite historian, exactly once.");
  std::string db_flag;
  service_main.app()
      .add_option("--db", db_flag, "the database (default: the plant's historian.database)")
      ->type_name("PATH");
  return service_main.run(argc, argv, [&](PlantConfig loaded) {
    const PlantConfig plant = std::move(loaded);
    const std::string db_path = db_flag.empty() ? plant.historian_database : db_flag;
    auto db = storage::Database::open(db_path);
    spdlog::info("historian database {}", db_path);

    ncqual::dds::Service service(service_main.service_options(plant));
    auto& p = service.participant();
    ncqual::dds::Reader<ncqual::dds::CheckRequestTopic> requests(p);
    ncqual::dds::Reader<ncqual::dds::MeasurementSetTopic> sets(p);
    ncqual::dds::Reader<ncqual::dds::CheckResultTopic> results(p);
    ncqual::dds::Reader<ncqual::dds::MachineStatusTopic> statuses(p);
    ncqual::dds::Reader<ncqual::dds::CompensationTopic> compensations(p);
    ncqual::dds::Reader<ncqual::dds::InterventionTopic> interventions(p);
    ncqual::dds::Reader<ncqual::dds::HeartbeatTopic> heartbeats(p);

    // Every sample a reader receives is stored, named `what` in the log.
    const auto ingest = [&](auto& reader, const char* what) {
      service.dispatcher().on(reader, [&db, what](const auto& in) { store(db, what, in); });
    };
    ingest(requests, "request");
    ingest(sets, "measurement set");
    ingest(results, "result");
    ingest(statuses, "status");
    ingest(compensations, "compensation");
    ingest(interventions, "intervention");
    ingest(heartbeats, "heartbeat");
    return service.run();
  });
}

}  // namespace

int main(int argc, char** argv) {
  return ncqual::command_line::guarded_main("ncqual-historian", [&] { return run(argc, argv); });
}
