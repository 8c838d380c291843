// SPDX-License-Identifier: Apache-2.0
// How a short-lived sender (`ncqual check`, `intervene`, `import`, tests) sends what a service
// must act on (docs/architecture.md, "Acknowledged storage"): it writes the sample and waits for
// the Acknowledgement of every role that must take it — by topic, sample id and content hash, so
// another reader on the domain (a recorder, a monitoring tool) matching first proves nothing —
// writing it again meanwhile (after 0.25 s, then twice as long each time, at most every 2 s: the
// first acknowledgement may be given before our reader matched). It says which role did not
// answer, or which refused and why.
#pragma once

#include "ncqual/dds/endpoint.hpp"
#include "ncqual/dds/serialized.hpp"
#include "ncqual/dds/topics.hpp"

#include <fastdds/dds/core/condition/WaitSet.hpp>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <map>
#include <string>
#include <vector>

namespace ncqual::dds {

struct OrderOutcome {
  std::map<std::string, Acknowledgement> answers;  // by role, of those that answered
  std::vector<std::string> silent;                 // roles that did not answer in time
  // The first refusal, if any role refused.
  const Acknowledgement* refused() const {
    for (const auto& [role, ack] : answers) {
      if (ack.outcome == AckOutcome::Refused) return &ack;
    }
    return nullptr;
  }
};

// Sends `sample` and waits up to `patience` until every role of `awaited` acknowledged it.
template <typename Topic>
OrderOutcome send_acknowledged(Participant& participant, Writer<Topic>& writer,
                               const typename Topic::Model& sample,
                               const std::vector<std::string>& awaited,
                               std::chrono::milliseconds patience) {
  using namespace eprosima::fastdds::dds;
  // Before the first write: acknowledgements are volatile.
  Reader<AcknowledgementTopic> acks(participant, sample.machine_id);
  // Our reader should hear the acknowledging services before the first write (best effort: a
  // missed first acknowledgement only costs a second write).
  acks.wait_for_writers(1, std::min(patience, std::chrono::milliseconds(3000)));
  const auto wire = to_wire_as<typename Topic::Wire>(sample);
  const std::string hash = sha256_hex(serialize<Topic>(wire));
  const std::string id = sample_id_of(sample);
  WaitSet waitset;
  waitset.attach_condition(acks.condition());
  OrderOutcome out;
  const auto deadline = std::chrono::steady_clock::now() + patience;
  auto next_write = std::chrono::steady_clock::now();
  auto interval = std::chrono::milliseconds(250);
  const auto all_answered = [&] {
    return std::all_of(awaited.begin(), awaited.end(),
                       [&](const std::string& r) { return out.answers.count(r) > 0; });
  };
  while (!all_answered()) {
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) break;
    if (now >= next_write) {
      writer.write_wire(wire);
      next_write = now + interval;
      interval = std::min(interval * 2, std::chrono::milliseconds(2000));
    }
    ConditionSeq active;
    const auto until = std::min(deadline, next_write);
    waitset.wait(active, to_dds_duration(
                             std::chrono::duration_cast<std::chrono::milliseconds>(until - now)));
    for (auto& in : acks.take()) {
      const Acknowledgement& a = in.value;
      if (!in.error.empty() || a.topic != Topic::kName || a.sample_id != id ||
          a.content_hash != hash) {
        continue;
      }
      // The first answer of each role counts (a write again may bring a DUPLICATE after STORED).
      if (std::find(awaited.begin(), awaited.end(), a.by) != awaited.end()) {
        out.answers.emplace(a.by, a);
      }
    }
  }
  for (const auto& r : awaited) {
    if (!out.answers.count(r)) out.silent.push_back(r);
  }
  return out;
}

}  // namespace ncqual::dds
