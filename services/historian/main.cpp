// SPDX-License-Identifier: Apache-2.0
// ncqual-historian: one per plant. Stores every request, measurement set, result, compensation,
// status change, intervention and service heartbeat in SQLite, exactly once, and acknowledges
// each sample once it is committed (docs/architecture.md, "Acknowledged storage"): STORED,
// DUPLICATE (the same sample again), CONFLICT (its id was stored with other content: kept beside
// it, flagged) or REFUSED (it can never be stored). A sample the database could not take now
// (locked, full, failing) is not acknowledged: its producer keeps it and sends it again.
#include "ncqual/command_line.hpp"
#include "ncqual/config.hpp"
#include "ncqual/dds/acknowledged.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/log.hpp"
#include "ncqual/storage.hpp"

#include <spdlog/spdlog.h>

#include <iostream>

namespace {

using ncqual::AckOutcome;
using ncqual::storage::StoreOutcome;

AckOutcome ack_outcome(StoreOutcome outcome) {
  switch (outcome) {
    case StoreOutcome::Stored: return AckOutcome::Stored;
    case StoreOutcome::Duplicate: return AckOutcome::Duplicate;
    case StoreOutcome::Conflict: return AckOutcome::Conflict;
  }
  return AckOutcome::Refused;
}

// Stores one received sample and acknowledges it. A bad sample is logged with its reason and
// refused; a database failure is logged and not acknowledged; the historian keeps running with
// everything already stored intact.
template <typename Topic>
void store(ncqual::storage::Database& db, ncqual::dds::Acknowledger& acks, const char* what,
           const ncqual::dds::Received<typename Topic::Model>& in, std::int64_t now_ns) {
  const std::string& machine_id = in.value.machine_id;
  const std::string id = ncqual::sample_id_of(in.value);
  if (!in.error.empty()) {
    spdlog::error("{} {} of machine '{}' refused: {}", what, id, machine_id, in.error);
    acks.acknowledge<Topic>(in, AckOutcome::Refused, in.error);
    return;
  }
  try {
    const auto stored = db.store(in.value, {in.content_hash, in.writer, now_ns});
    switch (stored.outcome) {
      case StoreOutcome::Stored: spdlog::debug("stored {} {} of {}", what, id, machine_id); break;
      case StoreOutcome::Duplicate:
        spdlog::debug("{} {} of {} already stored", what, id, machine_id);
        break;
      case StoreOutcome::Conflict:
        spdlog::error(
            "CONFLICT: {} {} of machine '{}' from writer {} differs from the one stored (content "
            "{} against {}); both kept, the stored one unchanged",
            what, id, machine_id, in.writer, in.content_hash.substr(0, 12),
            stored.stored_hash.substr(0, 12));
        break;
    }
    acks.acknowledge<Topic>(in, ack_outcome(stored.outcome),
                            stored.outcome == StoreOutcome::Conflict
                                ? "stored first with content " + stored.stored_hash
                                : "");
  } catch (const ncqual::storage::StorageError& e) {
    if (e.sqlite_code() == 0) {
      // Refused by validation: it will never be stored, so the producer may drop it.
      spdlog::error("{} {} of machine '{}' refused: {}", what, id, machine_id, e.what());
      acks.acknowledge<Topic>(in, AckOutcome::Refused, e.what());
    } else {
      spdlog::error(
          "{} {} of machine '{}' not stored (not acknowledged; its producer sends it "
          "again): {}",
          what, id, machine_id, e.what());
    }
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
    ncqual::dds::Acknowledger acks(service, roles::kHistorian);
    ncqual::dds::Reader<ncqual::dds::CheckRequestTopic> requests(p);
    ncqual::dds::Reader<ncqual::dds::MeasurementSetTopic> sets(p);
    ncqual::dds::Reader<ncqual::dds::CheckResultTopic> results(p);
    ncqual::dds::Reader<ncqual::dds::MachineStatusTopic> statuses(p);
    ncqual::dds::Reader<ncqual::dds::CompensationTopic> compensations(p);
    ncqual::dds::Reader<ncqual::dds::InterventionTopic> interventions(p);
    ncqual::dds::Reader<ncqual::dds::HeartbeatTopic> heartbeats(p);

    // Every sample a reader receives is stored and acknowledged, named `what` in the log.
    const auto ingest = [&](auto& reader, const char* what) {
      using Topic = typename std::remove_reference_t<decltype(reader)>::TopicType;
      service.dispatcher().on(reader, [&db, &acks, &service, what](const auto& in) {
        store<Topic>(db, acks, what, in, service.clock().now_ns());
      });
    };
    ingest(requests, "request");
    ingest(sets, "measurement set");
    ingest(results, "result");
    ingest(statuses, "status");
    ingest(compensations, "compensation");
    ingest(interventions, "intervention");
    service.dispatcher().on(heartbeats, [&db](const ncqual::dds::Received<Heartbeat>& in) {
      if (!in.error.empty()) {
        spdlog::warn("heartbeat of {} {} ignored: {}", in.value.service, in.value.instance,
                     in.error);
        return;
      }
      try {
        db.store(in.value);
      } catch (const storage::StorageError& e) {
        spdlog::error("heartbeat of {} {} not stored: {}", in.value.service, in.value.instance,
                      e.what());
      }
    });
    return service.run();
  });
}

}  // namespace

int main(int argc, char** argv) {
  return ncqual::command_line::guarded_main("ncqual-historian", [&] { return run(argc, argv); });
}
