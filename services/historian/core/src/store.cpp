// SPDX-License-Identifier: Apache-2.0
// One received sample stored and its acknowledgement decided (store.hpp).
#include "ncqual/historian/store.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace ncqual::historian {

namespace {

AckOutcome ack_outcome(storage::StoreOutcome outcome) {
  switch (outcome) {
    case storage::StoreOutcome::Stored: return AckOutcome::Stored;
    case storage::StoreOutcome::Duplicate: return AckOutcome::Duplicate;
    case storage::StoreOutcome::Conflict: return AckOutcome::Conflict;
  }
  return AckOutcome::Refused;
}

}  // namespace

std::string conflict_text(const SampleKind& kind, const std::string& id,
                          const std::string& machine_id, const storage::StoreResult& stored,
                          const std::string& writer, const std::string& content_hash,
                          const NameWriter& name) {
  const std::string first = stored.stored_writer.empty() ? std::string("an unrecorded writer")
                                                         : name(stored.stored_writer);
  const std::string second = name(writer);
  const std::string both = fmt::format(
      "(content {} stored first, {} kept beside it); both kept, the stored one unchanged",
      stored.stored_hash.substr(0, 12), content_hash.substr(0, 12));
  if (kind.check_part != nullptr) {
    return fmt::format("conflicting {} of {} of machine '{}' from {} and {} {}", kind.check_part,
                       id, machine_id, first, second, both);
  }
  return fmt::format("{} {} of machine '{}' from {} differs from the one stored from {} {}",
                     kind.what, id, machine_id, second, first, both);
}

template <typename Model>
Outcome store_sample(storage::Database& db, const SampleKind& kind, const Model& value,
                     const Arrival& in, std::int64_t now_ns, bool open_plant,
                     const NameWriter& name) {
  const std::string& machine_id = value.machine_id;
  const std::string id = sample_id_of(value);
  if (!in.error.empty()) {
    spdlog::error("{} {} of machine '{}' from {} refused: {}", kind.what, id, machine_id,
                  name(in.writer), in.error);
    return {AckOutcome::Refused, in.error, std::nullopt, false};
  }
  storage::StoreResult stored;
  try {
    stored = db.store(value, {in.content_hash, in.writer, now_ns});
  } catch (const storage::StorageError& e) {
    if (e.sqlite_code() != 0) throw;  // the database: the ingest keeps it and says so
    // Refused by validation: it will never be stored, so the producer may drop it.
    spdlog::error("{} {} of machine '{}' refused: {}", kind.what, id, machine_id, e.what());
    return {AckOutcome::Refused, e.what(), std::nullopt, false};
  }
  Outcome outcome{ack_outcome(stored.outcome), "", std::nullopt,
                  stored.outcome == storage::StoreOutcome::Stored};
  // A per-machine topic's sample says where it came from: on an open plant at info when it is
  // stored, so that a writer outside the machines' partitions (the default one) is on record. A
  // resend is said at debug: after a restart the durable histories send every stored sample again.
  const auto level = !in.where.empty() && open_plant ? spdlog::level::info : spdlog::level::debug;
  switch (stored.outcome) {
    case storage::StoreOutcome::Stored:
      spdlog::log(level, "stored {} {} of {}{}{}", kind.what, id, machine_id,
                  in.where.empty() ? "" : ", ",
                  in.where.empty() ? "" : "written " + in.where + " by " + in.writer);
      break;
    case storage::StoreOutcome::Duplicate:
      spdlog::debug("{} {} of {} already stored{}", kind.what, id, machine_id,
                    in.where.empty() ? "" : " (sent again " + in.where + ")");
      break;
    case storage::StoreOutcome::Conflict: {
      outcome.ack_detail = "stored first with content " + stored.stored_hash;
      const std::string text =
          conflict_text(kind, id, machine_id, stored, in.writer, in.content_hash, name);
      // Raised once: a resend of the same content is answered CONFLICT again, not re-raised.
      if (!stored.new_conflict) {
        spdlog::debug("CONFLICT: {} (sent again; already kept)", text);
        break;
      }
      spdlog::error("CONFLICT: {}", text);
      Alarm alarm;
      alarm.machine_id = machine_id;
      alarm.alarm_id = "conflict/" + std::string(kind.topic) + "/" + id + "/" + in.content_hash;
      alarm.kind = AlarmKind::Conflict;
      alarm.active = true;
      alarm.text = text;
      outcome.alarm = std::move(alarm);
      break;
    }
  }
  return outcome;
}

template Outcome store_sample(storage::Database&, const SampleKind&, const CheckRequest&,
                              const Arrival&, std::int64_t, bool, const NameWriter&);
template Outcome store_sample(storage::Database&, const SampleKind&, const MeasurementSet&,
                              const Arrival&, std::int64_t, bool, const NameWriter&);
template Outcome store_sample(storage::Database&, const SampleKind&, const CheckResult&,
                              const Arrival&, std::int64_t, bool, const NameWriter&);
template Outcome store_sample(storage::Database&, const SampleKind&, const MachineStatus&,
                              const Arrival&, std::int64_t, bool, const NameWriter&);
template Outcome store_sample(storage::Database&, const SampleKind&, const Compensation&,
                              const Arrival&, std::int64_t, bool, const NameWriter&);
template Outcome store_sample(storage::Database&, const SampleKind&, const Intervention&,
                              const Arrival&, std::int64_t, bool, const NameWriter&);

void store_heartbeat(storage::Database& db, const Ingest& ingest, const Heartbeat& beat,
                     const std::string& error) {
  if (!error.empty()) {
    spdlog::warn("heartbeat of {} {} ignored: {}", beat.service, beat.instance, error);
    return;
  }
  if (ingest.health() != storage::StorageHealth::Ok || ingest.backlog() > 0) return;
  try {
    db.store(beat);
  } catch (const storage::StorageError& e) {
    spdlog::warn("heartbeat of {} {} not stored: {}", beat.service, beat.instance, e.what());
  }
}

Alarm storage_alarm(storage::StorageHealth health, const std::string& detail,
                    const std::string& db_path, const std::string& instance) {
  Alarm alarm;
  alarm.alarm_id = "storage/" + instance;
  alarm.kind = AlarmKind::Storage;
  alarm.active = health != storage::StorageHealth::Ok;
  if (alarm.active) {
    spdlog::error("storage health {}: {}", storage::to_string(health), detail);
    alarm.text = std::string(storage::to_string(health)) + ": " + detail;
  } else {
    spdlog::info("storage health ok again: {} stores and acknowledges", db_path);
    alarm.text = db_path + " stores and acknowledges again";
  }
  return alarm;
}

}  // namespace ncqual::historian
