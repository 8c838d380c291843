// SPDX-License-Identifier: Apache-2.0
// The sets the solver solved, and its decision for each set received (solved_sets.hpp).
#include "ncqual/solver_service/solved_sets.hpp"

#include "ncqual/solver/solve.hpp"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <tuple>

namespace ncqual::solver_service {

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(SolvedDocument, time_ns, content_hash, writer)

namespace {
constexpr std::string_view kSolvedPrefix = "solved/";
std::string key_of(const std::string& request_id) {
  return std::string(kSolvedPrefix) + request_id;
}
}  // namespace

SolvedSets::SolvedSets(storage::StateFile& file, std::size_t kept) : file_(file), kept_(kept) {
  std::vector<std::tuple<std::int64_t, std::string, SolvedDocument>> found;
  for (const auto& [key, doc] : file_.load()) {
    if (key.rfind(kSolvedPrefix, 0) != 0) continue;
    try {
      const auto solved = nlohmann::json::parse(doc).get<SolvedDocument>();
      found.emplace_back(solved.time_ns, key.substr(kSolvedPrefix.size()), solved);
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

const SolvedDocument* SolvedSets::find(const std::string& id) const {
  const auto it = ids_.find(id);
  return it == ids_.end() ? nullptr : &it->second;
}

void SolvedSets::save(const MeasurementSet& set, const std::string& content_hash,
                      const std::string& writer, const std::vector<storage::OutboxEntry>& answer) {
  // The oldest beyond the bound go in the same transaction; memory follows once it committed.
  const std::size_t excess = order_.size() + 1 > kept_ ? order_.size() + 1 - kept_ : 0;
  std::vector<std::string> erase;
  erase.reserve(excess);
  for (std::size_t i = 0; i < excess; ++i) erase.push_back(key_of(order_[i]));
  const SolvedDocument solved{set.time_ns, content_hash, writer};
  file_.save({{key_of(set.request_id), nlohmann::json(solved).dump()}}, erase, answer);
  for (std::size_t i = 0; i < excess; ++i) {
    ids_.erase(order_.front());
    order_.pop_front();
  }
  order_.push_back(set.request_id);
  ids_[set.request_id] = solved;
}

SetDecision decide(const SolvedSets& solved, const ReceivedSet& in) {
  if (in.foreign) return {SetAction::Refuse, in.foreign_error};
  const SolvedDocument* done = solved.find(in.set.request_id);
  if (done == nullptr) return {SetAction::Solve, ""};
  if (done->content_hash.empty() || done->content_hash == in.content_hash) {
    return {SetAction::AcknowledgeAgain, "already solved"};
  }
  // Another set for a request already solved: not solved again, and not forgotten. The historian
  // keeps it as a conflict and raises it; the scheduler holds the machine.
  return {SetAction::Conflict, "conflicting measurements of " + in.set.request_id +
                                   ": solved from writer " + done->writer + "'s set (content " +
                                   done->content_hash.substr(0, 12) + "), this one from writer " +
                                   in.writer + " (content " + in.content_hash.substr(0, 12) +
                                   ") differs; not solved again"};
}

CheckResult answer(const MeasurementSet& set, const std::string& malformed,
                   const PlantConfig& plant, std::int64_t now_ns, const std::string& produced_by) {
  CheckResult result;
  if (!malformed.empty()) {
    result.machine_id = set.machine_id;
    result.request_id = set.request_id;
    result.kind = set.kind;
    result.verdict = Verdict::Invalid;
    result.reason = malformed;
    result.time_ns = now_ns;
    result.origin = set.origin;
  } else {
    result = solver::solve(set, plant, now_ns);
  }
  result.produced_by = produced_by;  // every verdict names the software that made it
  return result;
}

std::optional<Compensation> compensation_of(const CheckResult& result) {
  if (!result.correction) return std::nullopt;
  return Compensation{result.machine_id, result.request_id, *result.correction, result.time_ns};
}

}  // namespace ncqual::solver_service
