// SPDX-License-Identifier: Apache-2.0
// ncqual-recorder: records the plant's DDS traffic into MCAP files for as long as it runs
// (docs/recordings.md): every ncqual topic (or --topics), each read with its profile's QoS, a new
// file every --split-every (default one a day) or --max-size-mib, a chunk written at least every
// second. Announces itself by heartbeat; on a secured plant runs as the identity `recorder`.
// `ncqual record` is the same recorder in the foreground.
#include "ncqual/dds/service.hpp"
#include "ncqual/recording/recorder.hpp"
#include "ncqual/recording/recording.hpp"
#include "ncqual/common/version.hpp"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace {

int run(int argc, char** argv) {
  using namespace ncqual;
  namespace dds = ncqual::dds;
  dds::ServiceMain service_main(
      "recorder", "Records the plant's DDS traffic into MCAP files (docs/recordings.md).");
  std::string out;
  std::vector<std::string> topics;
  std::vector<std::string> machines;
  std::string compression = "zstd";
  std::uint64_t max_size_mib = 0;
  std::string split_every = "1d";
  CLI::App& app = service_main.app();
  app.add_option("--out", out,
                 "the recording's path; files are numbered after it, FILE-0001.mcap, ... "
                 "(default: recordings/ncqual.mcap beside the historian's database)");
  app.add_option("--topics", topics, "only these topics (CheckResult,MeasurementSet,...)")
      ->delimiter(',');
  app.add_option("--machine", machines, "only these machines' samples")->delimiter(',');
  app.add_option("--compression", compression, "of the chunks: zstd, lz4 or none")
      ->check(CLI::IsMember({"zstd", "lz4", "none"}));
  app.add_option("--max-size-mib", max_size_mib, "a new file past this size (0: no limit)");
  app.add_option("--split-every", split_every, "a new file after this long (90s, 15m, 1h, 1d)");
  return service_main.run(argc, argv, [&](const PlantConfig& plant) {
    const auto split = recording::parse_duration_ns(split_every);
    if (!split) {
      throw ConfigError("--split-every '" + split_every +
                        "': expected a duration (90s, 15m, 1h, 1d)");
    }
    if (out.empty()) {
      out = (std::filesystem::path(plant.historian_database).parent_path() / "recordings" /
             "ncqual.mcap")
                .string();
    }
    if (const auto dir = std::filesystem::path(out).parent_path(); !dir.empty()) {
      std::filesystem::create_directories(dir);
    }
    dds::ServiceOptions options = service_main.service_options(plant);
    options.raw_heartbeat = true;  // every topic is read raw in this participant (raw.hpp)
    dds::Service service(options);
    recording::FileOptions file;
    file.library = version_line("ncqual-recorder");
    file.compression = compression == "none" ? "" : compression;
    file.max_size_bytes = max_size_mib << 20U;
    file.split_every_ns = *split;
    file.metadata = recording::recording_metadata("ncqual-recorder", options.participant.domain_id,
                                                  plant.plant, service.clock().now_ns());
    recording::RecordingWriter writer(out, file);
    recording::RecorderOptions recorder_options;
    recorder_options.topics = recording::topics_named(topics);
    recorder_options.machines = std::set<std::string>(machines.begin(), machines.end());
    recorder_options.skip_local = true;  // not its own heartbeats
    recording::Recorder recorder(service.participant(), writer, service.dispatcher(),
                                 recorder_options);
    spdlog::info("recording {} topics into {}", recorder.readers().size(), writer.files().back());
    std::size_t files_logged = 1;
    service.on_heartbeat([&](Heartbeat&) {
      if (writer.files().size() != files_logged) {
        files_logged = writer.files().size();
        spdlog::info("recording into {} ({} samples so far)", writer.files().back(),
                     recorder.recorded());
      }
    });
    const int code = service.run();
    recorder.finish();
    writer.close();
    spdlog::info("{} samples recorded into {} file(s), the last {}; {} lost by the readers",
                 recorder.recorded(), writer.files().size(), writer.files().back(),
                 recorder.lost());
    return code;
  });
}

}  // namespace

int main(int argc, char** argv) {
  return ncqual::command_line::guarded_main("ncqual-recorder", [&] { return run(argc, argv); });
}
