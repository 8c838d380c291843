// SPDX-License-Identifier: Apache-2.0
// `ncqual record` and `ncqual recording`: recordings of the plant's DDS traffic as MCAP files
// (docs/recordings.md).
//
//   ncqual record --out FILE.mcap [--topics T,...] [--machine M,...] [--compression zstd|lz4|none]
//                 [--max-size-mib N] [--split-every D] [--stop-after N] [--duration D]
//                 [--overwrite] [--plant F] [--domain N] [--secure DIR] [--identity NAME]
//     Joins the domain as a reader of every ncqual topic (each with its profile's QoS, durable
//     topics TRANSIENT_LOCAL) and writes every sample as received until Ctrl-C (SIGINT/SIGTERM),
//     --stop-after samples or --duration; the file is then closed with its index. A chunk is
//     written at least every second, so a killed recorder loses at most the last second
//     (`ncqual recording recover` indexes what it left).
//   ncqual recording info FILE [--json]
//     Channels, schemas, messages per topic and machine, time range, compression, whether the
//     file is indexed; messages that cannot be read as their topic's type.
//   ncqual recording recover IN OUT
//     Writes what IN holds (a recording killed mid-way) into OUT as a complete, indexed file.
//
// Exit codes: 0, 1 a file that cannot be written or read (the message names the record and byte),
// 2 bad usage.
#include "commands.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/dds/dispatcher.hpp"
#include "ncqual/recording/recorder.hpp"
#include "ncqual/recording/recording.hpp"
#include "ncqual/common/version.hpp"

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <set>

namespace ncqual::cli {
namespace {

std::string iso(std::uint64_t ns) {
  char buffer[32];
  return std::string(format_iso8601(static_cast<std::int64_t>(ns), buffer));
}

std::chrono::nanoseconds duration_option(const std::string& flag, const std::string& text) {
  const auto ns = recording::parse_duration_ns(text);
  if (!ns) throw UsageError(flag + " '" + text + "': expected a duration (90s, 15m, 1h, 1d)");
  return std::chrono::nanoseconds(*ns);
}

// ---- record ----------------------------------------------------------------------------------

struct RecordOptions {
  DdsOptions dds;
  std::string out;
  std::vector<std::string> topics, machines;
  std::string compression = "zstd";
  std::uint64_t max_size_mib = 0;
  std::string split_every, duration;
  std::uint64_t stop_after = 0;
  bool overwrite = false;
};

int run_record(const RecordOptions& o) {
  // Before the participant starts its threads, so that they inherit the mask.
  ncqual::dds::Dispatcher dispatcher;
  ncqual::dds::handle_termination_signals([&dispatcher](int) { dispatcher.stop(); });
  const PlantConfig plant = plant_from(o.dds.plant);
  recording::FileOptions file;
  file.library = version_line("ncqual");
  file.compression = o.compression == "none" ? "" : o.compression;
  file.max_size_bytes = o.max_size_mib << 20U;
  if (!o.split_every.empty())
    file.split_every_ns = duration_option("--split-every", o.split_every).count();
  file.overwrite = o.overwrite;
  recording::RecorderOptions recorder_options;
  recorder_options.topics = topics_option(o.topics);
  recorder_options.machines = std::set<std::string>(o.machines.begin(), o.machines.end());
  recorder_options.stop_after = o.stop_after;
  const auto limit = o.duration.empty() ? std::chrono::nanoseconds::max()
                                        : duration_option("--duration", o.duration);

  const ncqual::dds::ParticipantOptions options =
      command_participant(plant, o.dds, "ncqual-record", "recorder");
  file.metadata = recording::recording_metadata("ncqual record", options.domain_id, plant.plant,
                                                WallClock().now_ns());
  recording::RecordingWriter writer(o.out, file);
  ncqual::dds::Participant participant(options);
  recording::Recorder recorder(participant, writer, dispatcher, recorder_options);
  std::cerr << "recording " << recorder.readers().size() << " topics of domain "
            << options.domain_id << " into " << writer.files().back()
            << (o.stop_after != 0 ? " until " + std::to_string(o.stop_after) + " samples" : "")
            << (o.duration.empty() ? "" : " for " + o.duration) << "; Ctrl-C stops" << std::endl;
  if (limit == std::chrono::nanoseconds::max()) {
    dispatcher.run();
  } else {
    dispatcher.run_until([] { return false; },
                         std::chrono::duration_cast<std::chrono::milliseconds>(limit));
  }
  recorder.finish();
  writer.close();
  std::cerr << recorder.recorded() << " samples recorded into " << writer.files().size()
            << " file(s):";
  for (const auto& f : writer.files()) std::cerr << " " << f;
  std::cerr << " (" << writer.bytes() << " bytes)";
  if (recorder.lost() != 0) std::cerr << "; the readers lost " << recorder.lost();
  if (recorder.unreadable() != 0) {
    std::cerr << "; " << recorder.unreadable() << " could not be read for their machine";
  }
  std::cerr << "\n";
  return kExitOk;
}

// ---- recording info --------------------------------------------------------------------------

struct InfoOptions {
  std::string file;
  bool json = false;
};

std::string duration_text(std::uint64_t ns) {
  const std::uint64_t s = ns / 1000000000ULL;
  std::ostringstream out;
  if (s >= 86400) out << s / 86400 << " d ";
  if (s >= 3600) out << (s % 86400) / 3600 << " h ";
  out << (s % 3600) / 60 << " min " << s % 60 << " s";
  return out.str();
}

int run_info(const InfoOptions& o) {
  const mcap::Recording r = mcap::read_file(o.file);
  const recording::Info info = recording::inspect(r, o.file, std::filesystem::file_size(o.file));
  if (o.json) {
    std::cout << recording::to_json(info) << "\n";
    return kExitOk;
  }
  std::string compression;
  for (const auto& c : info.compression)
    compression += (compression.empty() ? "" : ", ") + (c.empty() ? "none" : c);
  std::cout << "file        " << info.file << " (" << info.file_bytes << " bytes), "
            << (info.indexed ? "indexed" : "NOT indexed (run `ncqual recording recover`)") << ", "
            << info.chunks << " chunks, compression "
            << (compression.empty() ? "none" : compression) << "\n";
  std::cout << "written by  " << (info.header.library.empty() ? "(not said)" : info.header.library)
            << (info.header.profile.empty() ? "" : ", profile " + info.header.profile) << "\n";
  for (const auto& m : info.metadata) {
    std::cout << "metadata    " << m.name << ":";
    for (const auto& [k, v] : m.metadata) std::cout << " " << k << "=" << v << ";";
    std::cout << "\n";
  }
  std::cout << "messages    " << info.messages;
  if (info.messages != 0) {
    std::cout << " from " << iso(info.start_ns) << " to " << iso(info.end_ns) << " ("
              << duration_text(info.end_ns - info.start_ns) << ")";
  }
  std::cout << "\n\nchannels\n";
  std::cout << "  " << std::left << std::setw(4) << "id" << std::setw(26) << "topic" << std::right
            << std::setw(9) << "messages"
            << "  schema\n";
  for (const auto& c : info.channels) {
    std::cout << "  " << std::left << std::setw(4) << c.id << std::setw(26) << c.topic << std::right
              << std::setw(9) << c.messages << "  "
              << (c.schema_name.empty() ? "(none)" : c.schema_name) << " ("
              << (c.schema_encoding.empty() ? "-" : c.schema_encoding) << ", " << c.message_encoding
              << ")";
    if (c.topic_info != nullptr) {
      std::cout << (c.schema_is_this_build ? ", this build's IDL" : ", another version's IDL");
      if (c.older != nullptr) {
        std::cout << "; wire contract " << c.older->contract << ", replayed as contract "
                  << c.topic_info->contract;
      }
    } else {
      std::cout << ", not replayed: " << c.problem;
    }
    std::cout << "\n";
  }
  if (!info.per_machine.empty()) {
    std::cout << "\nper topic and machine\n";
    for (const auto& [key, count] : info.per_machine) {
      std::cout << "  " << std::left << std::setw(26) << key.first << std::setw(16)
                << (key.second.empty() ? "(none)" : key.second) << std::right << std::setw(9)
                << count << "\n";
    }
  }
  if (info.unreadable != 0) {
    std::cout << "\n" << info.unreadable << " messages cannot be read as their topic's type:\n";
    for (const auto& p : info.problems) std::cout << "  " << p << "\n";
  }
  for (const auto& w : info.warnings) std::cerr << "warning: " << w << "\n";
  return kExitOk;
}

// ---- recording recover -----------------------------------------------------------------------

struct RecoverOptions {
  std::string in, out;
  bool overwrite = false;
};

int run_recover(const RecoverOptions& o) {
  if (!o.overwrite && std::filesystem::exists(o.out)) {
    throw UsageError(o.out + " exists already; give another file, or --overwrite");
  }
  const mcap::Recording r = recording::recover(o.in, o.out);
  for (const auto& w : r.warnings) std::cerr << "warning: " << w << "\n";
  std::cerr << "recovered " << r.messages.size() << " messages on " << r.channels.size()
            << " channels from " << r.chunks.size() << " chunks of " << o.in << " into " << o.out
            << (r.indexed ? " (the input was indexed already)" : "") << "\n";
  return kExitOk;
}

}  // namespace

void add_record(CLI::App& app, Commands& commands) {
  const auto [cmd, o] = add_command(app, commands, "record",
                                    "record the plant's DDS traffic into an MCAP file", run_record);
  cmd->add_option("--out", o->out, "the recording (numbered FILE-0001.mcap, ... when rotating)")
      ->type_name("FILE.mcap")
      ->required();
  add_sample_filter_options(cmd, o->topics, o->machines);
  cmd->add_option("--compression", o->compression, "of the chunks (default zstd)")
      ->check(CLI::IsMember({"zstd", "lz4", "none"}));
  cmd->add_option("--max-size-mib", o->max_size_mib, "a new file past this size")->type_name("N");
  cmd->add_option("--split-every", o->split_every, "a new file after this long (90s, 15m, 1h, 1d)")
      ->type_name("D");
  cmd->add_option("--stop-after", o->stop_after, "stop after this many samples")->type_name("N");
  cmd->add_option("--duration", o->duration, "stop after this long (90s, 15m, 1h, 1d)")
      ->type_name("D");
  cmd->add_flag("--overwrite", o->overwrite, "replace an existing file");
  add_dds_options(cmd, o->dds);

  CLI::App* recording = app.add_subcommand("recording", "look into and repair recordings");
  recording->require_subcommand(1);
  const auto [info, io] = add_command(
      *recording, commands, "info",
      "channels, messages per topic and machine, time range, compression, index", run_info);
  info->add_option("file", io->file, "the recording")->type_name("FILE.mcap")->required();
  add_json_flag(info, io->json);
  const auto [recover, ro] = add_command(
      *recording, commands, "recover",
      "write a recording killed mid-way again as a complete, indexed file", run_recover);
  recover->add_option("in", ro->in, "the recording to read")->type_name("IN.mcap")->required();
  recover->add_option("out", ro->out, "the file to write")->type_name("OUT.mcap")->required();
  recover->add_flag("--overwrite", ro->overwrite, "replace OUT if it exists");
}

}  // namespace ncqual::cli
