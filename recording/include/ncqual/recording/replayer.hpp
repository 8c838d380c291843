// SPDX-License-Identifier: Apache-2.0
// The replay: writes a Selection's samples (recording.hpp) into a domain again, as recorded:
// the same bytes, through writers with each topic's profile QoS, a per-machine topic's in its
// machine's partition, stamped with the recorded source timestamp, in log-time order, paced by
// the recorded times divided by a rate or as fast as the readers acknowledge.
#pragma once

#include "ncqual/dds/raw.hpp"
#include "ncqual/recording/recording.hpp"

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace ncqual::recording {

struct ReplayOptions {
  double rate = 1.0;  // <= 0: as fast as the readers acknowledge
  // Before the first sample of a topic, wait until its writer has matched this many readers
  // (0: do not wait); `ready_timeout` bounds the wait.
  int readers = 0;
  std::chrono::milliseconds ready_timeout{30000};
  // How long a writer waits for its readers' acknowledgements: whenever it has written half its
  // history depth (per machine's partition; 250 of the durable profile's 500, 50 of the command
  // profile's 100) since the last wait, so that a KEEP_LAST history never overwrites what a reader
  // has not yet received, and at the end.
  std::chrono::milliseconds ack_timeout{30000};
  // When replaying as fast as the readers take it: the writers' heartbeat period (raw.hpp,
  // RawWriterOptions), so that each wait for acknowledgements lasts about this long rather than
  // the profile's 500 ms. A paced replay keeps the profile's.
  std::chrono::milliseconds fast_heartbeat{10};
};

struct ReplayReport {
  std::uint64_t written = 0;
  std::uint64_t not_written = 0;      // the writer refused (history full past max_blocking_time)
  bool acknowledged = true;           // every matched reader acknowledged everything at the end
  std::vector<std::string> problems;  // each names the sample's place in the file
  std::map<std::string, std::uint64_t> per_topic;
};

class Replayer {
 public:
  explicit Replayer(dds::Participant& participant, ReplayOptions options = {});
  ~Replayer();

  // Writes `selection`'s samples. `wait_until(offset)` returns once `offset` has passed since the
  // replay started (the caller's clock), or false to stop; it is not called when replaying as
  // fast as possible.
  ReplayReport run(const Selection& selection,
                   const std::function<bool(std::chrono::nanoseconds)>& wait_until);

 private:
  dds::RawWriter& writer_of(const dds::TopicInfo& topic);
  dds::Participant& participant_;
  ReplayOptions options_;
  std::map<std::string, std::unique_ptr<dds::RawWriter>> writers_;
};

}  // namespace ncqual::recording
