// SPDX-License-Identifier: Apache-2.0
// ncqual-historian: one per plant. Stores every request, measurement set, result, compensation,
// status change, intervention and heartbeat in SQLite, exactly once, and acknowledges each sample
// once it is committed. What it does with a sample is its core's (ncqual/historian/store.hpp);
// through database faults, ingest.hpp and file_guard.hpp (docs/reliability.md); after a store,
// the trend watch (watch_worker.hpp). Here: the readers, the acknowledgements and the Alarms
// (conflicts, and the storage's health: raised, and cleared when it is well again).
#include "ncqual/historian/file_guard.hpp"
#include "ncqual/historian/ingest.hpp"
#include "ncqual/historian/store.hpp"
#include "ncqual/historian/watch_worker.hpp"

#include "ncqual/common/command_line.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/dds/acknowledged.hpp"
#include "ncqual/dds/identity.hpp"
#include "ncqual/dds/service.hpp"

#include <spdlog/spdlog.h>

#include <csignal>
#include <type_traits>

namespace ncqual {
namespace {

// How each topic's samples are named in log lines, conflicts and alarm ids.
template <typename Topic>
historian::SampleKind kind_of(const char* what) {
  using Model = typename Topic::Model;
  const char* part = std::is_same_v<Model, MeasurementSet> ? "measurements"
                     : std::is_same_v<Model, CheckResult>  ? "results"
                                                           : nullptr;
  return {what, part, Topic::kName};
}

int run(int argc, char** argv) {
  dds::ServiceMain service_main(
      "historian", "Stores every sample of the plant in the SQLite historian, exactly once.");
  std::string db_flag;
  service_main.app()
      .add_option("--db", db_flag, "the database (default: the plant's historian.database)")
      ->type_name("PATH");
  return service_main.run(argc, argv, [&](PlantConfig loaded) {
    const PlantConfig plant = std::move(loaded);
    const std::string db_path = db_flag.empty() ? plant.historian_database : db_flag;
    // A write past a file size limit fails (EFBIG) instead of ending the process.
    std::signal(SIGXFSZ, SIG_IGN);
    auto db = storage::Database::open(db_path);  // refuses a damaged file (quick_check)
    // A lock held by someone else holds up one attempt for at most this long; the sample waits
    // in the backlog meanwhile and the historian keeps receiving.
    db.set_busy_timeout(std::chrono::milliseconds(500));
    spdlog::info("historian database {}", db_path);

    dds::Service service(service_main.service_options(plant));
    auto& p = service.participant();
    dds::Acknowledger acks(service, roles::kHistorian);
    dds::Writer<dds::AlarmTopic> alarms(p);
    const auto publish_alarm = [&](Alarm alarm) {
      alarm.source = roles::kHistorian;
      alarm.instance = service.instance();
      alarm.time_ns = service.clock().now_ns();
      if (!alarms.write(alarm)) spdlog::error("alarm {} could not be published", alarm.alarm_id);
    };
    historian::Ingest ingest({}, [&](storage::StorageHealth health, const std::string& detail) {
      service.beat("running");  // the alarm goes out now, not at the next period
      publish_alarm(historian::storage_alarm(health, detail, db_path, service.instance()));
    });
    service.on_heartbeat([&ingest](Heartbeat& beat) { ingest.describe(beat); });
    const auto steady_now = [] { return std::chrono::steady_clock::now(); };

    // The trend watch (docs/trends.md, "Warnings") on its own thread and connection.
    dds::Writer<dds::TrendWarningTopic> trend_warnings(p);
    historian::WatchWorker watch(db.open_another(), [&](const std::vector<TrendWarning>& changes) {
      for (const TrendWarning& w : changes) {
        if (!trend_warnings.write(w)) {
          spdlog::error("trend warning of {} {} could not be published", w.machine_id, w.metric);
        }
      }
    });

    // On a secured plant a writer's GUID names its identity: a conflict says who wrote each side.
    const bool open_plant = !p.secured();
    const auto identities =
        dds::plant_identities_to_name(open_plant ? "" : p.security().dir, "conflicts");
    const historian::NameWriter name_writer = [&identities](const std::string& guid) {
      return dds::writer_name(guid, identities);
    };
    // Every sample a reader receives goes through the ingest: stored and acknowledged, or kept.
    const auto ingest_from = [&](auto& reader, const historian::SampleKind& kind) {
      using Topic = typename std::remove_reference_t<decltype(reader)>::TopicType;
      service.dispatcher().on(reader, [&, kind](const auto& in) {
        const std::int64_t now = service.clock().now_ns();
        ingest.submit(
            now,
            [&, kind, in, now] {
              const historian::Arrival arrival{in.error, in.content_hash, in.writer,
                                               dds::where_received(in)};
              const auto out = historian::store_sample(db, kind, in.value, arrival, now, open_plant,
                                                       name_writer);
              if (out.alarm) publish_alarm(*out.alarm);
              acks.acknowledge<Topic>(in, out.ack, out.ack_detail);
              if (out.newly_stored) watch.after_stored(in.value);
            },
            steady_now());
      });
    };
    // The per-machine topics are read in each machine's partition: a sample that names another
    // machine than its partition's is refused (docs/deploy.md, "Roles").
    std::vector<std::string> machine_ids;
    for (const auto& m : plant.machines) machine_ids.push_back(m.machine_id);
    dds::MachineReaders<dds::CheckRequestTopic> requests(p, machine_ids);
    ingest_from(requests, kind_of<dds::CheckRequestTopic>("request"));
    dds::MachineReaders<dds::MeasurementSetTopic> sets(p, machine_ids);
    ingest_from(sets, kind_of<dds::MeasurementSetTopic>("measurement set"));
    dds::Reader<dds::CheckResultTopic> results(p);
    ingest_from(results, kind_of<dds::CheckResultTopic>("result"));
    dds::Reader<dds::MachineStatusTopic> statuses(p);
    ingest_from(statuses, kind_of<dds::MachineStatusTopic>("status"));
    dds::MachineReaders<dds::CompensationTopic> compensations(p, machine_ids);
    ingest_from(compensations, kind_of<dds::CompensationTopic>("compensation"));
    // What a service of an older version writes (docs/architecture.md, "Changing the wire
    // contract"): contract 1's sets and results, read by a second participant (one type per
    // topic name in a participant), stored with their origin unknown and acknowledged with the
    // hash of the bytes that service sent, so that its outbox lets them go.
    auto& older = service.older_contracts_participant();
    dds::MachineReaders<dds::MeasurementSetContract1Topic> sets_contract1(older, machine_ids);
    ingest_from(sets_contract1, kind_of<dds::MeasurementSetContract1Topic>("measurement set"));
    dds::Reader<dds::CheckResultContract1Topic> results_contract1(older);
    ingest_from(results_contract1, kind_of<dds::CheckResultContract1Topic>("result"));
    dds::Reader<dds::InterventionTopic> interventions(p);
    ingest_from(interventions, kind_of<dds::InterventionTopic>("intervention"));
    dds::Reader<dds::HeartbeatTopic> heartbeats(p);
    service.dispatcher().on(heartbeats, [&](const dds::Received<Heartbeat>& in) {
      historian::store_heartbeat(db, ingest, in.value, in.error);
    });
    // Its own last word: its reader stops with the receive loop, so it stores that one itself.
    // Stop the historian last: what the others say as they stop reaches it only while it runs.
    service.before_stop(
        [&] { historian::store_heartbeat(db, ingest, service.heartbeat("stopped"), ""); });
    service.dispatcher().every(std::chrono::milliseconds(100), [&] { ingest.retry(steady_now()); });
    historian::FileGuard guard(db, db_path);
    service.dispatcher().every(std::chrono::seconds(1), [&] {
      ingest.hold(guard.check(service.clock().now_ns()), steady_now());
    });
    return service.run();
  });
}

}  // namespace
}  // namespace ncqual

int main(int argc, char** argv) {
  return ncqual::command_line::guarded_main("ncqual-historian",
                                            [&] { return ncqual::run(argc, argv); });
}
