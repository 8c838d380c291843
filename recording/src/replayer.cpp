// SPDX-License-Identifier: Apache-2.0
#include "ncqual/recording/replayer.hpp"

#include <spdlog/spdlog.h>

#include <set>

namespace ncqual::recording {

Replayer::Replayer(dds::Participant& participant, ReplayOptions options)
    : participant_(participant), options_(options) {}

Replayer::~Replayer() = default;

dds::RawWriter& Replayer::writer_of(const dds::TopicInfo& topic) {
  auto& w = writers_[topic.name];
  if (!w) {
    dds::RawWriterOptions o;
    if (options_.rate <= 0) o.heartbeat_period = options_.fast_heartbeat;
    w = std::make_unique<dds::RawWriter>(participant_, topic, o);
  }
  return *w;
}

ReplayReport Replayer::run(const Selection& selection,
                           const std::function<bool(std::chrono::nanoseconds)>& wait_until) {
  ReplayReport report;
  const std::vector<std::int64_t> due = schedule(selection.samples, options_.rate);
  std::set<std::pair<std::string, std::string>> ready;  // (topic, partition's machine)
  // Per (topic, partition's machine): written since the writer's last wait, and the window.
  std::map<std::pair<std::string, std::string>, int> since_ack;
  for (std::size_t i = 0; i < selection.samples.size(); ++i) {
    const Sample& s = selection.samples[i];
    dds::RawWriter& writer = writer_of(*s.topic);
    const std::string machine = s.topic->per_machine ? s.machine_id : "";
    if (options_.readers > 0 && ready.insert({s.topic->name, machine}).second &&
        !writer.wait_for_readers(machine, options_.readers, options_.ready_timeout)) {
      report.problems.push_back(
          s.topic->name + (machine.empty() ? "" : " of " + machine) + ": fewer than " +
          std::to_string(options_.readers) + " readers matched within " +
          std::to_string(options_.ready_timeout.count()) + " ms; replayed all the same");
    }
    if (options_.rate > 0 && !wait_until(std::chrono::nanoseconds(due[i]))) break;
    if (writer.write(s.bytes(), s.machine_id, s.publish_time_ns)) {
      ++report.written;
      ++report.per_topic[s.topic->name];
    } else {
      ++report.not_written;
      report.problems.push_back(mcap::location(*s.message) + " (" + s.topic->name + " of " +
                                s.machine_id + "): not written (the writer's history stayed full)");
    }
    const int window = std::max(1, writer.history_depth() / 2);
    if (int& n = since_ack[{s.topic->name, machine}]; ++n >= window) {
      n = 0;
      if (!writer.wait_for_acknowledgments(machine, options_.ack_timeout)) {
        spdlog::warn("{}: readers did not acknowledge within {} ms; going on", s.topic->name,
                     options_.ack_timeout.count());
      }
    }
  }
  for (auto& [name, writer] : writers_) {
    if (!writer->wait_for_acknowledgments(options_.ack_timeout)) report.acknowledged = false;
  }
  return report;
}

}  // namespace ncqual::recording
