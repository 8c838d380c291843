// SPDX-License-Identifier: Apache-2.0
// The recorder: a reader of every ncqual topic (or those asked), each with its topic's profile
// QoS, in every partition, writing each sample as received into a RecordingWriter. Durable topics
// are read TRANSIENT_LOCAL, so a recorder that joins late also gets the history the writers still
// hold; the volatile ones (commands, acknowledgements, heartbeats) from the moment it matches.
// `ncqual record` runs it in the foreground, `ncqual-recorder` as a service.
#pragma once

#include "ncqual/dds/dispatcher.hpp"
#include "ncqual/dds/raw.hpp"
#include "ncqual/recording/recording.hpp"

#include <chrono>
#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace ncqual::recording {

struct RecorderOptions {
  std::vector<const dds::TopicInfo*> topics;  // empty: every ncqual topic
  std::set<std::string> machines;             // only these machines' samples; empty: every one
  bool skip_local = false;  // leave out what this process's own participant writes (heartbeats)
  std::uint64_t stop_after = 0;  // stop the dispatcher after this many messages (0: never)
};

class Recorder {
 public:
  // Creates the readers on `participant` and adds each topic's channel to `writer`; registers
  // with `dispatcher` (samples as they arrive, a flush every second).
  Recorder(dds::Participant& participant, RecordingWriter& writer, dds::Dispatcher& dispatcher,
           RecorderOptions options);

  // Takes what every reader holds now and writes it; returns how many samples were written.
  std::size_t drain();
  // At stop, before the file is closed: what the readers received (and so acknowledged) that the
  // dispatcher had not handed over yet is written too, unless --stop-after was reached. A
  // recorder stopped right after a burst lost the tail of it without this.
  std::size_t finish();

  std::uint64_t recorded() const { return recorded_; }
  std::uint64_t left_out() const { return left_out_; }      // another machine's, or local
  std::uint64_t unreadable() const { return unreadable_; }  // could not be read for its machine
  // Samples the readers know they lost (best-effort heartbeats, history overruns).
  std::int64_t lost() const;
  const std::vector<std::unique_ptr<dds::RawReader>>& readers() const { return readers_; }

 private:
  std::size_t drain(dds::RawReader& reader);

  RecordingWriter& writer_;
  dds::Dispatcher& dispatcher_;
  RecorderOptions options_;
  std::vector<std::unique_ptr<dds::RawReader>> readers_;
  std::uint64_t recorded_ = 0;
  std::uint64_t left_out_ = 0;
  std::uint64_t unreadable_ = 0;
};

}  // namespace ncqual::recording
