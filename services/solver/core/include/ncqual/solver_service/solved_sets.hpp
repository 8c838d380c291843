// SPDX-License-Identifier: Apache-2.0
// The solver service without DDS: which sets it has solved, and what it does with each set it
// receives (docs/architecture.md, "Acknowledged storage": exactly one result per measurement set).
//
//   written on another machine's behalf   -> refused, no answer for that machine
//   solved before, same content (or solved
//   by a version that kept no hash)        -> acknowledged again from the record, not solved again
//   solved before, other content          -> CONFLICT: not solved again; the historian keeps it
//   not solved                            -> solved; the result, its compensation and the note
//                                            "solved" saved in one transaction, then acknowledged
//
// A set whose save failed is not acknowledged, and is solved when its producer sends it again.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/storage/state_file.hpp"

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <unordered_map>
#include <vector>

namespace ncqual::solver_service {

// A set solved: state document "solved/<request id>".
struct SolvedDocument {
  std::int64_t time_ns = 0;  // the set's
  std::string content_hash;  // of the set solved ("" when an older version solved it)
  std::string writer;        // its writer's GUID
};

// The newest this many solved sets are kept: far more than any outbox or durable history can send
// again.
constexpr std::size_t kSolvedKept = 20000;

// The sets solved, as the solver's state file holds them (read once at start; the file is the
// solver's alone).
class SolvedSets {
 public:
  explicit SolvedSets(storage::StateFile& file, std::size_t kept = kSolvedKept);

  // The set solved for request `id`, if any.
  const SolvedDocument* find(const std::string& id) const;
  // Saves the set as solved with the outbox entries of its answer, in one transaction; the oldest
  // beyond the bound go in the same one. Throws storage::StorageError, and then nothing changed.
  void save(const MeasurementSet& set, const std::string& content_hash, const std::string& writer,
            const std::vector<storage::OutboxEntry>& answer);
  std::size_t size() const { return order_.size(); }

 private:
  storage::StateFile& file_;
  std::size_t kept_;
  std::unordered_map<std::string, SolvedDocument> ids_;
  std::deque<std::string> order_;  // oldest first
};

// What to do with a set received.
enum class SetAction { Refuse, AcknowledgeAgain, Conflict, Solve };

struct SetDecision {
  SetAction action = SetAction::Solve;
  std::string detail;  // the refusal or the conflict, in words; "already solved" for a resend
};

// A set as received: who wrote it, its content hash, and whether it names another machine than
// the partition it came in (then `foreign_error` says so).
struct ReceivedSet {
  const MeasurementSet& set;
  std::string content_hash;
  std::string writer;
  bool foreign = false;
  std::string foreign_error;
};

SetDecision decide(const SolvedSets& solved, const ReceivedSet& in);

// The result that answers a set: the solver's, or INVALID with `malformed` (a sample that could
// not be read: the scheduler is never left waiting); stamped with `now_ns` and `produced_by`, and
// with the set's origin (also when INVALID: a malformed simulated set stays simulated).
CheckResult answer(const MeasurementSet& set, const std::string& malformed,
                   const PlantConfig& plant, std::int64_t now_ns, const std::string& produced_by);

// The Compensation a result publishes, if it carries a correction.
std::optional<Compensation> compensation_of(const CheckResult& result);

}  // namespace ncqual::solver_service
