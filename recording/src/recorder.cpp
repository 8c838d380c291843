// SPDX-License-Identifier: Apache-2.0
#include "ncqual/recording/recorder.hpp"

#include <spdlog/spdlog.h>

namespace ncqual::recording {

Recorder::Recorder(dds::Participant& participant, RecordingWriter& writer,
                   dds::Dispatcher& dispatcher, RecorderOptions options)
    : writer_(writer), dispatcher_(dispatcher), options_(std::move(options)) {
  if (options_.topics.empty()) {
    for (const auto& t : dds::ncqual_topics()) options_.topics.push_back(&t);
  }
  for (const dds::TopicInfo* topic : options_.topics) {
    readers_.push_back(std::make_unique<dds::RawReader>(participant, *topic));
    writer_.add_topic(*topic, readers_.back()->qos_description());
  }
  for (auto& reader : readers_) {
    dds::RawReader* r = reader.get();
    dispatcher_.on(r->condition(), [this, r] { drain(*r); });
  }
  // A chunk at least every second: a recorder killed now loses at most the last second.
  dispatcher_.every(std::chrono::milliseconds(1000), [this] { writer_.flush(); });
}

std::size_t Recorder::drain() {
  std::size_t n = 0;
  for (auto& reader : readers_) n += drain(*reader);
  return n;
}

std::size_t Recorder::finish() {
  if (options_.stop_after != 0 && recorded_ >= options_.stop_after) return 0;
  return drain();
}

std::size_t Recorder::drain(dds::RawReader& reader) {
  std::size_t n = 0;
  for (auto& sample : reader.take()) {
    if (options_.skip_local && sample.local) {
      ++left_out_;
      continue;
    }
    if (!options_.machines.empty()) {
      std::string machine;
      std::string error;
      if (!reader.topic().machine_of(sample.bytes, machine, error)) {
        // Recorded all the same: a recording keeps what was on the wire, readable or not.
        ++unreadable_;
        spdlog::warn("{} from writer {}: {}", reader.topic().name, sample.writer, error);
      } else if (options_.machines.count(machine) == 0) {
        ++left_out_;
        continue;
      }
    }
    writer_.write(reader.topic().name, sample.reception_time_ns, sample.source_time_ns,
                  sample.bytes);
    ++recorded_;
    ++n;
    if (options_.stop_after != 0 && recorded_ >= options_.stop_after) {
      dispatcher_.stop();
      break;
    }
  }
  return n;
}

std::int64_t Recorder::lost() const {
  std::int64_t n = 0;
  for (const auto& r : readers_) n += r->lost();
  return n;
}

}  // namespace ncqual::recording
