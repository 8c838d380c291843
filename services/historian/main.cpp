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

// Stores one received sample; a bad sample is logged with its reason and skipped, and the
// historian keeps running with everything already stored intact.
template <typename Model>
void store(ncqual::storage::Database& db, const char* what, const ncqual::dds::Received<Model>& in,
           const std::string& machine_id, const std::string& id) {
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

    auto& d = service.dispatcher();
    d.on(requests, [&](const ncqual::dds::Received<CheckRequest>& in) {
      store(db, "request", in, in.value.machine_id, in.value.request_id);
    });
    d.on(sets, [&](const ncqual::dds::Received<MeasurementSet>& in) {
      store(db, "measurement set", in, in.value.machine_id, in.value.request_id);
    });
    d.on(results, [&](const ncqual::dds::Received<CheckResult>& in) {
      store(db, "result", in, in.value.machine_id, in.value.request_id);
    });
    d.on(statuses, [&](const ncqual::dds::Received<MachineStatus>& in) {
      store(db, "status", in, in.value.machine_id, in.value.request_id);
    });
    d.on(compensations, [&](const ncqual::dds::Received<Compensation>& in) {
      store(db, "compensation", in, in.value.machine_id, in.value.request_id);
    });
    d.on(interventions, [&](const ncqual::dds::Received<Intervention>& in) {
      store(db, "intervention", in, in.value.machine_id, in.value.intervention_id);
    });
    d.on(heartbeats, [&](const ncqual::dds::Received<Heartbeat>& in) {
      store(db, "heartbeat", in, in.value.machine_id, in.value.service + "@" + in.value.instance);
    });
    return service.run();
  });
}

}  // namespace

int main(int argc, char** argv) {
  return ncqual::command_line::guarded_main("ncqual-historian", [&] { return run(argc, argv); });
}
