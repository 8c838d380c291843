// SPDX-License-Identifier: Apache-2.0
// ncqual-historian: one per plant. Stores every request, measurement set, result, compensation,
// status change, intervention and service heartbeat in SQLite, exactly once, and acknowledges
// each sample once it is committed (docs/architecture.md, "Acknowledged storage"): STORED,
// DUPLICATE (the same sample again), CONFLICT (its id was stored with other content: kept beside
// it, flagged) or REFUSED (it can never be stored). A sample the database could not take now
// (locked, full, failing) is not acknowledged: its producer keeps it and sends it again.
// Storage faults (ingest.hpp): what arrives while the database fails waits in a bounded backlog
// and is retried with back-off; the file is checked every second (removed or replaced: every
// attempt is held, and what the connection holds is copied to <file>.rescued-<time>); the
// heartbeat carries the health (ok, degraded, failed), its detail, the backlog and the oldest
// waiting sample, and goes out at once when the health changes. A damaged file is refused at
// start (PRAGMA quick_check). Conflicts and storage faults are also published as Alarms
// (ncqual/Alarm: raised, and cleared when the storage is well again).
#include "ncqual/historian/ingest.hpp"
#include "ncqual/historian/watch_worker.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/common/command_line.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/dds/acknowledged.hpp"
#include "ncqual/dds/identity.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/common/log.hpp"
#include "ncqual/storage/database.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <csignal>
#include <iostream>
#include <type_traits>

namespace {

using ncqual::AckOutcome;
using ncqual::Alarm;
using ncqual::AlarmKind;
using ncqual::storage::StoreOutcome;

AckOutcome ack_outcome(StoreOutcome outcome) {
  switch (outcome) {
    case StoreOutcome::Stored: return AckOutcome::Stored;
    case StoreOutcome::Duplicate: return AckOutcome::Duplicate;
    case StoreOutcome::Conflict: return AckOutcome::Conflict;
  }
  return AckOutcome::Refused;
}

// Raises an alarm (machine id, alarm id, text).
using Raise = std::function<void(const std::string&, const std::string&, const std::string&)>;
// A writer's GUID as people read it: the plant identity whose subject bits it carries (a secured
// plant), else the GUID.
using NameWriter = std::function<std::string(const std::string&)>;

// What two different samples of `Topic` for one check are, in a conflict's text: "measurements",
// "results"; nullptr for a topic that is not a part of a check the scheduler judges.
template <typename Topic>
constexpr const char* check_part() {
  if constexpr (std::is_same_v<Topic, ncqual::dds::MeasurementSetTopic>) return "measurements";
  if constexpr (std::is_same_v<Topic, ncqual::dds::CheckResultTopic>) return "results";
  return nullptr;
}

// The text of a conflict, its log line and its Alarm. For a check's measurement set or result
// (`part`) it opens with what the scheduler holds the machine for (Scheduler::conflict):
// "conflicting measurements of REQUEST from WRITER A and WRITER B".
std::string conflict_text(const char* what, const char* part, const std::string& id,
                          const std::string& machine_id, const ncqual::storage::StoreResult& stored,
                          const std::string& writer, const std::string& content_hash,
                          const NameWriter& name) {
  const std::string first = stored.stored_writer.empty() ? std::string("an unrecorded writer")
                                                         : name(stored.stored_writer);
  const std::string second = name(writer);
  const std::string both = fmt::format(
      "(content {} stored first, {} kept beside it); both kept, the stored one unchanged",
      stored.stored_hash.substr(0, 12), content_hash.substr(0, 12));
  if (part != nullptr) {
    return fmt::format("conflicting {} of {} of machine '{}' from {} and {} {}", part, id,
                       machine_id, first, second, both);
  }
  return fmt::format("{} {} of machine '{}' from {} differs from the one stored from {} {}", what,
                     id, machine_id, second, first, both);
}

// What follows a sample newly stored (the trend watch); not called for a duplicate or conflict.
template <typename Model>
using AfterStore = std::function<void(const Model&)>;

// Stores one received sample and acknowledges it; a conflict is also raised as an alarm. A bad
// sample is logged with its reason and refused; a database failure is rethrown for the ingest to
// keep the sample (not acknowledged).
template <typename Topic>
void store(ncqual::storage::Database& db, ncqual::dds::Acknowledger& acks, const Raise& raise,
           const NameWriter& name, const AfterStore<typename Topic::Model>& after, const char* what,
           const ncqual::dds::Received<typename Topic::Model>& in, std::int64_t now_ns,
           bool open_plant) {
  const std::string& machine_id = in.value.machine_id;
  const std::string id = ncqual::sample_id_of(in.value);
  if (!in.error.empty()) {
    spdlog::error("{} {} of machine '{}' from {} refused: {}", what, id, machine_id,
                  name(in.writer), in.error);
    acks.acknowledge<Topic>(in, AckOutcome::Refused, in.error);
    return;
  }
  ncqual::storage::StoreResult stored;
  try {
    stored = db.store(in.value, {in.content_hash, in.writer, now_ns});
  } catch (const ncqual::storage::StorageError& e) {
    if (e.sqlite_code() != 0) throw;  // the database: the ingest keeps it and says so
    // Refused by validation: it will never be stored, so the producer may drop it.
    spdlog::error("{} {} of machine '{}' refused: {}", what, id, machine_id, e.what());
    acks.acknowledge<Topic>(in, AckOutcome::Refused, e.what());
    return;
  }
  // A per-machine topic's sample says where it came from (Received::partition): on an open plant
  // at info when it is stored, so that a writer outside the machines' partitions (the default
  // one) is on record. A resend is said at debug, as before: after a restart the durable
  // histories send every stored sample again.
  const std::string where = ncqual::dds::where_received(in);
  const auto level = in.partition && open_plant ? spdlog::level::info : spdlog::level::debug;
  switch (stored.outcome) {
    case StoreOutcome::Stored:
      spdlog::log(level, "stored {} {} of {}{}{}", what, id, machine_id, where.empty() ? "" : ", ",
                  where.empty() ? "" : "written " + where + " by " + in.writer);
      break;
    case StoreOutcome::Duplicate:
      spdlog::debug("{} {} of {} already stored{}", what, id, machine_id,
                    where.empty() ? "" : " (sent again " + where + ")");
      break;
    case StoreOutcome::Conflict: {
      const std::string text = conflict_text(what, check_part<Topic>(), id, machine_id, stored,
                                             in.writer, in.content_hash, name);
      // Raised once: a resend of the same content is answered CONFLICT again, not re-raised.
      if (!stored.new_conflict) {
        spdlog::debug("CONFLICT: {} (sent again; already kept)", text);
        break;
      }
      spdlog::error("CONFLICT: {}", text);
      raise(machine_id, "conflict/" + std::string(Topic::kName) + "/" + id + "/" + in.content_hash,
            text);
      break;
    }
  }
  acks.acknowledge<Topic>(in, ack_outcome(stored.outcome),
                          stored.outcome == StoreOutcome::Conflict
                              ? "stored first with content " + stored.stored_hash
                              : "");
  if (stored.outcome == StoreOutcome::Stored && after) after(in.value);
}

std::string rescue_name(const std::string& path, std::int64_t now_ns) {
  char buffer[32];
  std::string stamp(ncqual::format_iso8601(now_ns, buffer));
  stamp.erase(std::remove(stamp.begin(), stamp.end(), ':'), stamp.end());
  return path + ".rescued-" + stamp;
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
    // A write past a file size limit fails (EFBIG) instead of ending the process: handled as
    // the I/O error it is.
    std::signal(SIGXFSZ, SIG_IGN);
    auto db = storage::Database::open(db_path);  // refuses a damaged file (quick_check)
    // A lock held by someone else holds up one attempt for at most this long; the sample waits
    // in the backlog meanwhile and the historian keeps receiving.
    db.set_busy_timeout(std::chrono::milliseconds(500));
    spdlog::info("historian database {}", db_path);

    ncqual::dds::Service service(service_main.service_options(plant));
    auto& p = service.participant();
    ncqual::dds::Acknowledger acks(service, roles::kHistorian);
    // The per-machine topics are read in each machine's partition: a sample that names another
    // machine than its partition's is refused (docs/deploy.md, "Roles").
    std::vector<std::string> machine_ids;
    for (const auto& m : plant.machines) machine_ids.push_back(m.machine_id);
    ncqual::dds::MachineReaders<ncqual::dds::CheckRequestTopic> requests(p, machine_ids);
    ncqual::dds::MachineReaders<ncqual::dds::MeasurementSetTopic> sets(p, machine_ids);
    ncqual::dds::Reader<ncqual::dds::CheckResultTopic> results(p);
    ncqual::dds::Reader<ncqual::dds::MachineStatusTopic> statuses(p);
    ncqual::dds::MachineReaders<ncqual::dds::CompensationTopic> compensations(p, machine_ids);
    ncqual::dds::Reader<ncqual::dds::InterventionTopic> interventions(p);
    ncqual::dds::Reader<ncqual::dds::HeartbeatTopic> heartbeats(p);

    ncqual::dds::Writer<ncqual::dds::AlarmTopic> alarms(p);
    const auto publish_alarm = [&](const std::string& machine_id, AlarmKind kind,
                                   const std::string& alarm_id, bool active,
                                   const std::string& text) {
      Alarm alarm;
      alarm.machine_id = machine_id;
      alarm.alarm_id = alarm_id;
      alarm.kind = kind;
      alarm.active = active;
      alarm.source = roles::kHistorian;
      alarm.instance = service.instance();
      alarm.text = text;
      alarm.time_ns = service.clock().now_ns();
      if (!alarms.write(alarm)) spdlog::error("alarm {} could not be published", alarm_id);
    };
    const Raise raise_conflict = [&](const std::string& machine_id, const std::string& alarm_id,
                                     const std::string& text) {
      publish_alarm(machine_id, AlarmKind::Conflict, alarm_id, true, text);
    };

    historian::Ingest ingest({}, [&](storage::StorageHealth health, const std::string& detail) {
      const bool ok = health == storage::StorageHealth::Ok;
      if (ok) {
        spdlog::info("storage health ok again: {} stores and acknowledges", db_path);
      } else {
        spdlog::error("storage health {}: {}", storage::to_string(health), detail);
      }
      service.beat("running");  // the alarm goes out now, not at the next period
      publish_alarm("", AlarmKind::Storage, "storage/" + service.instance(), !ok,
                    ok ? db_path + " stores and acknowledges again"
                       : std::string(storage::to_string(health)) + ": " + detail);
    });
    service.on_heartbeat([&ingest](Heartbeat& beat) {
      beat.health = std::string(storage::to_string(ingest.health()));
      beat.health_detail = ingest.detail();
      beat.outbox_depth = static_cast<std::int64_t>(ingest.backlog());
      beat.oldest_unacknowledged_ns = ingest.oldest_received_ns();
    });
    const auto steady_now = [] { return std::chrono::steady_clock::now(); };

    // The trend watch (docs/trends.md, "Warnings"): after a result, an intervention or a
    // compensation is stored and acknowledged, the warnings it starts or ends are stored and
    // published, on the watch's own thread and connection (watch_worker.hpp).
    ncqual::dds::Writer<ncqual::dds::TrendWarningTopic> trend_warnings(p);
    historian::WatchWorker watch(db.open_another(), [&](const std::vector<TrendWarning>& changes) {
      for (const TrendWarning& w : changes) {
        if (w.active) {
          spdlog::warn("trend warning raised: {}", w.text);
        } else {
          spdlog::info("trend warning of {} {} ({}) ended by {}", w.machine_id, w.metric, w.kind,
                       w.ended_by);
        }
        if (!trend_warnings.write(w)) {
          spdlog::error("trend warning of {} {} could not be published", w.machine_id, w.metric);
        }
      }
    });
    const AfterStore<CheckResult> after_result = [&](const CheckResult& r) {
      watch.after_result(r);
    };
    const AfterStore<Compensation> after_compensation = [&](const Compensation& c) {
      watch.after_compensation(c);
    };
    const AfterStore<Intervention> after_intervention = [&](const Intervention& i) {
      watch.after_intervention(i);
    };

    const bool open_plant = !p.secured();
    // On a secured plant a writer's GUID names its identity (ncqual/dds/identity.hpp): a conflict
    // says who wrote each side. Read once; a certificate that cannot be read leaves GUIDs.
    std::vector<ncqual::dds::PlantIdentity> identities;
    if (!open_plant) {
      try {
        identities = ncqual::dds::plant_identities(p.security().dir);
      } catch (const std::exception& e) {
        spdlog::warn("the plant's identities are not read ({}): conflicts name writers by GUID",
                     e.what());
      }
    }
    const NameWriter name_writer = [&identities](const std::string& guid) {
      if (const auto id = ncqual::dds::identity_of_guid(guid, identities)) {
        return id->name + " (writer " + guid + ")";
      }
      return "writer " + guid;
    };
    // Every sample a reader receives goes through the ingest: stored and acknowledged, or kept.
    const auto ingest_from = [&](auto& reader, const char* what, const auto& after) {
      using Topic = typename std::remove_reference_t<decltype(reader)>::TopicType;
      service.dispatcher().on(reader, [&, what](const auto& in) {
        const std::int64_t now = service.clock().now_ns();
        ingest.submit(
            now,
            [&db, &acks, &raise_conflict, &name_writer, &after, what, in, now, open_plant] {
              store<Topic>(db, acks, raise_conflict, name_writer, after, what, in, now, open_plant);
            },
            steady_now());
      });
    };
    ingest_from(requests, "request", AfterStore<CheckRequest>{});
    ingest_from(sets, "measurement set", AfterStore<MeasurementSet>{});
    ingest_from(results, "result", after_result);
    ingest_from(statuses, "status", AfterStore<MachineStatus>{});
    ingest_from(compensations, "compensation", after_compensation);
    ingest_from(interventions, "intervention", after_intervention);
    // Heartbeats are a service's latest word: stored when the database is well, else skipped.
    service.dispatcher().on(heartbeats, [&](const ncqual::dds::Received<Heartbeat>& in) {
      if (!in.error.empty()) {
        spdlog::warn("heartbeat of {} {} ignored: {}", in.value.service, in.value.instance,
                     in.error);
        return;
      }
      if (ingest.health() != storage::StorageHealth::Ok || ingest.backlog() > 0) return;
      try {
        db.store(in.value);
      } catch (const storage::StorageError& e) {
        spdlog::warn("heartbeat of {} {} not stored: {}", in.value.service, in.value.instance,
                     e.what());
      }
    });
    service.dispatcher().every(std::chrono::milliseconds(100), [&] { ingest.retry(steady_now()); });
    // The file itself: removed or replaced while open means every later commit would go where
    // nobody reads it. Hold, rescue what the connection holds, and say so; released when the
    // path names the opened file again (moved back).
    bool rescued = false;
    service.dispatcher().every(std::chrono::seconds(1), [&] {
      const std::string problem = db.file_problem();
      if (!problem.empty() && !rescued) {
        rescued = true;
        const std::string copy = rescue_name(db_path, service.clock().now_ns());
        try {
          db.copy_to(copy);
          spdlog::error("{}: everything stored until now is copied to {}", problem, copy);
        } catch (const std::exception& e) {
          spdlog::error("{}: what was stored could not be copied to {}: {}", problem, copy,
                        e.what());
        }
      }
      if (problem.empty()) rescued = false;
      ingest.hold(problem.empty() ? ""
                                  : problem +
                                        "; nothing is stored or acknowledged until it "
                                        "is back or the historian is restarted",
                  steady_now());
    });
    return service.run();
  });
}

}  // namespace

int main(int argc, char** argv) {
  return ncqual::command_line::guarded_main("ncqual-historian", [&] { return run(argc, argv); });
}
