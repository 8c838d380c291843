// SPDX-License-Identifier: Apache-2.0
// One machine tool served by an acquisition process: what it does with the CheckRequests and
// Compensations of its machine, with no DDS (the executable wires the topics to it). It never
// judges a measurement.
//
//   request  -> already performed (recorded, also by an earlier run)?    ignore it (settled)
//               already waiting for its correction, or being measured?     ignore it
//               on the wall clock, older than the maximum age?              history: ignore it
//               verifies a correction not yet applied?                      wait for it
//               otherwise                                                   measure and publish
//                                                  (or hand it over to a control: then poll)
//   poll         -> measurements the instruments finished since: record and publish them
//   compensation -> for this machine and not seen before?  apply it, record it, then measure the
//                   requests that waited for it
//
// Each measured request is recorded in the state file (with its set's outbox entry) before the
// set is written, so a restarted acquisition, sent the request again, never moves the machine
// again for a request it measured. Each applied compensation is recorded too: a restart restores
// it into instruments that do not keep it themselves (the simulator), and never applies it twice.
// on_request and on_compensation say when a sample is settled (recorded, or needs no record), the
// moment the executable acknowledges it to its sender.
#pragma once

#include "ncqual/acquisition/instruments.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/storage/state_file.hpp"

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace ncqual::acquisition {

// The requests a machine measured, oldest first, kept in the service's state file as documents
// "performed/<machine>/<request id>" = {"seq": N}; only the newest `capacity` are kept (a request
// is sent again until this acquisition acknowledged it, so only a recent one can come back). And
// the compensations applied to it, all of them, oldest first: "applied/<machine>/<request id>" =
// {"seq": N, "correction": {...}}.
class PerformedRequests {
 public:
  PerformedRequests(storage::StateFile& state, std::string machine_id, std::size_t capacity = 1000);
  // Those recorded by an earlier run, from the state file's documents.
  void load(const std::map<std::string, std::string>& documents);
  // Records one (and forgets the oldest beyond the capacity), with the outbox entries of its
  // measurement in the same transaction: a kill keeps both or neither. Throws StorageError when it
  // cannot be written; then nothing is recorded.
  void record(const std::string& request_id, const std::vector<storage::OutboxEntry>& queue = {});
  bool contains(const std::string& request_id) const { return ids_.count(request_id) > 0; }
  std::size_t size() const { return order_.size(); }
  // Records that the compensation of `request_id` was applied. Throws StorageError as record().
  void record_applied(const std::string& request_id, const Correction& correction);
  // The compensations applied by earlier runs (as loaded), oldest first: request id, correction.
  const std::vector<std::pair<std::string, Correction>>& applied() const { return applied_; }

 private:
  storage::StateFile& state_;
  const std::string machine_id_;
  const std::size_t capacity_;
  std::set<std::string> ids_;
  std::deque<std::string> order_;
  std::int64_t next_seq_ = 0;
  std::vector<std::pair<std::string, Correction>> applied_;
};

struct StationOptions {
  // Simulated clock: a measurement is stamped its request's time plus the instrument's time (the
  // check-kind table's duration) and requests never age. Wall clock: stamped `now`.
  bool simulated_clock = false;
  // Wall clock: requests older than this are history, not work.
  std::int64_t max_request_age_ns = 600'000'000'000;
};

class Station {
 public:
  // Where a measurement goes (the MeasurementSet writer), once it is recorded; false when it could
  // not be written now.
  using Publish = std::function<bool(const MeasurementSet&)>;
  // The outbox entries of a measurement, saved with the record that its request was performed
  // (none: the measurement is only published).
  using Queue = std::function<std::vector<storage::OutboxEntry>(const MeasurementSet&)>;

  Station(std::string machine_id, std::unique_ptr<Instruments> instruments,
          PerformedRequests performed, StationOptions options, Publish publish, Queue queue = {});

  const std::string& id() const { return machine_id_; }

  // A CheckRequest as received at `now_ns`; `malformed` is the wire's complaint about it ("" for
  // a good sample): a malformed request is answered with a MeasurementSet that says so. True when
  // the request is settled: measured and recorded (now or before), or history not to measure;
  // false while it waits for a correction, or when its record could not be saved.
  bool on_request(const CheckRequest& request, const std::string& malformed, std::int64_t now_ns);
  // A Compensation as received at `now_ns` (corrections are applied once per request id). True
  // when it is settled: applied and recorded (now or before), or refused by the instruments
  // (logged; applying it again would not change that).
  bool on_compensation(const Compensation& compensation, std::int64_t now_ns);

  // Collects what the instruments finished measuring since the last call (a control's results
  // file), at `now_ns`: each is recorded and published like a measurement taken at once. The
  // executable calls it about once a second. Returns how many were finished. Their requests are
  // settled when they are sent again.
  std::size_t poll(std::int64_t now_ns);

  // Requests waiting for a correction to be applied.
  std::size_t waiting() const;
  // Requests the instruments are measuring (handed to a control, not back yet).
  std::size_t running() const { return running_.size(); }

 private:
  bool is_waiting(const std::string& request_id) const;
  // Measures, records and publishes; false when the record could not be saved or the
  // measurement goes on (handed to a control).
  bool measure(const CheckRequest& request, const std::string& malformed, std::int64_t now_ns);
  // Records and publishes a measurement; false when the record could not be saved.
  bool finish(const CheckRequest& request, MeasurementSet set);
  // The time a measurement of `request` is stamped with when it is taken at `now_ns`.
  std::int64_t measured_at(const CheckRequest& request, std::int64_t now_ns) const;

  const std::string machine_id_;
  std::unique_ptr<Instruments> instruments_;
  PerformedRequests performed_;
  const StationOptions options_;
  const Publish publish_;
  const Queue queue_;
  std::set<std::string> applied_;  // compensations, by the request id that issued them
  std::map<std::string, std::vector<CheckRequest>> waiting_;  // by the correction they verify
  std::map<std::string, CheckRequest> running_;  // handed to the instruments, by request id
};

}  // namespace ncqual::acquisition
