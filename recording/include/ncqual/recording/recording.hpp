// SPDX-License-Identifier: Apache-2.0
// Recordings of a plant's DDS traffic as MCAP files (ncqual/mcap/mcap.hpp), what is in them, and
// which of their samples a replay sends. No DDS here: the recorder (recorder.hpp) and the replay
// (replayer.hpp) wire these to readers and writers.
//
// The layout (docs/recordings.md): Header profile "ncqual", library "ncqual <version>"; one
// Metadata record "ncqual" (who recorded, where, with which version); one Schema per topic type,
// encoding "omgidl", named by the fully scoped type ("ncqual::msg::CheckResult"), whose data is
// the whole of idl/ncqual.idl; one Channel per topic ("ncqual/CheckResult"), message encoding
// "cdr", with the topic's QoS and key in its metadata; each Message the serialized payload as on
// the wire (encapsulation header included), log_time when it was received, publish_time the
// writer's source timestamp.
#pragma once

#include "ncqual/dds/raw.hpp"
#include "ncqual/mcap/mcap.hpp"

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::recording {

// idl/ncqual.idl of this build, the data of every schema.
std::string_view idl_text();

// The channel metadata of `topic` besides the reader's QoS: its type, key, partitions and
// profiles.
std::map<std::string, std::string> channel_metadata(const dds::TopicInfo& topic);

// The topics `names` names ("CheckResult" or "ncqual/CheckResult", any case, also several
// joined by commas); throws std::invalid_argument naming an unknown one and the known ones.
std::vector<const dds::TopicInfo*> topics_named(const std::vector<std::string>& names);

// What the Metadata record "ncqual" of a recording says: `recorder` (e.g. "ncqual record"),
// the version, the host, the domain, the plant, and when it started (ISO 8601 UTC).
std::map<std::string, std::string> recording_metadata(const std::string& recorder, int domain,
                                                      const std::string& plant,
                                                      std::int64_t started_ns);

// ---- Writing ---------------------------------------------------------------------------------

struct FileOptions {
  std::string library;                                 // Header.library: "ncqual 0.1.0 (git ...)"
  std::string compression;                             // of the chunks: "", "zstd" or "lz4"
  std::uint64_t chunk_bytes = std::uint64_t{1} << 20;  // a chunk is closed past this many
  // Rotation: a new file once the current one holds this many bytes (0: never) ...
  std::uint64_t max_size_bytes = 0;
  // ... or once its first message is this old (0: never).
  std::int64_t split_every_ns = 0;
  // Without rotation, an existing file is refused unless this is set; with rotation, numbering
  // goes on after the highest number already there, so a restarted recorder overwrites nothing.
  bool overwrite = false;
  // Written as the Metadata record "ncqual" of every file (with its part number when rotating).
  std::map<std::string, std::string> metadata;
};

// A recording's files: `path` itself, or with rotation `path`'s stem numbered ("run.mcap" gives
// "run-0001.mcap", "run-0002.mcap", ..., after the highest number there already). Each file is
// a complete MCAP file of its own with the channel of every topic added, messages or not.
class RecordingWriter {
 public:
  // Throws mcap::Error when the (first) file cannot be created, and for an unknown compression.
  RecordingWriter(std::string path, FileOptions options);
  ~RecordingWriter();
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;

  // The channel of `topic`, with its reader's QoS (`qos`) besides channel_metadata().
  void add_topic(const dds::TopicInfo& topic, const std::map<std::string, std::string>& qos);
  // One received sample of a topic added before. Rotates first when due (by size, or by
  // `log_time_ns` against the file's first message).
  void write(const std::string& topic, std::int64_t log_time_ns, std::int64_t publish_time_ns,
             const std::vector<std::uint8_t>& bytes);
  // Writes and flushes the open chunk: what the recorder calls every second so that a killed
  // recorder loses at most the last second.
  void flush();
  // Closes the file being written (summary, footer). Idempotent.
  void close();

  // The files written so far, in order (the last one is being written until close()).
  const std::vector<std::string>& files() const { return files_; }
  std::uint64_t messages() const { return messages_; }
  std::uint64_t bytes() const;  // of every file, the open chunk included

 private:
  void open_next();
  std::string path_;
  FileOptions options_;
  std::unique_ptr<mcap::Writer> writer_;
  std::vector<std::string> files_;
  std::uint64_t closed_bytes_ = 0;  // of the files closed
  std::uint64_t messages_ = 0;
  std::int64_t file_start_ns_ = -1;  // log time of the open file's first message
  struct Topic {
    dds::TopicInfo info;
    std::map<std::string, std::string> metadata;
    std::uint16_t channel = 0;  // in the open file; 0: not yet added there
  };
  std::map<std::string, Topic> topics_;
  void define(Topic& t);                          // its schema and channel in the open file
  std::map<std::string, std::uint16_t> schemas_;  // type name -> schema id, in the open file
  std::uint32_t sequence_ = 0;
  std::size_t next_part_ = 0;  // the number of the last file opened when rotating
};

// Reads `in` (a recording killed mid-way, or any readable MCAP file) and writes every schema,
// channel, metadata and message it holds to `out` as a complete, indexed file with the same
// compression. Returns what was read (its warnings say what was missing).
mcap::Recording recover(const std::string& in, const std::string& out);

// ---- What a recording holds ------------------------------------------------------------------

// One channel's samples, as ncqual reads them.
struct ChannelInfo {
  std::uint16_t id = 0;
  std::string topic;
  std::string message_encoding;
  std::string schema_name;      // "" without a schema
  std::string schema_encoding;  // "omgidl"
  std::map<std::string, std::string> metadata;
  std::uint64_t messages = 0;
  // An ncqual topic of the same type, in CDR: its samples can be read and replayed. Else
  // `problem` says why not (another system's channel, another type under an ncqual name).
  const dds::TopicInfo* topic_info = nullptr;
  // Of a channel recorded in an older wire contract's layout of its topic: that layout. Its
  // samples are read, and replayed, in the topic's current layout (OlderLayout::upgrade).
  const dds::OlderLayout* older = nullptr;
  std::string problem;
  bool schema_is_this_build = false;  // the schema's IDL is exactly this build's idl_text()
};

struct Info {
  std::string file;
  std::uint64_t file_bytes = 0;
  mcap::Header header;
  std::vector<mcap::Metadata> metadata;
  bool indexed = false;
  std::set<std::string> compression;
  std::size_t chunks = 0;
  std::uint64_t messages = 0;
  std::uint64_t start_ns = 0;  // log times of the first and last message (0 without messages)
  std::uint64_t end_ns = 0;
  std::vector<ChannelInfo> channels;
  // Messages per (topic, machine) of the ncqual channels.
  std::map<std::pair<std::string, std::string>, std::uint64_t> per_machine;
  // Messages that could not be read as their topic's type: "<location>: <why>" (at most 20
  // listed; `unreadable` counts them all).
  std::vector<std::string> problems;
  std::uint64_t unreadable = 0;
  std::vector<std::string> warnings;  // the reader's
};

// What `recording` (read from `file`, `file_bytes` long) holds.
Info inspect(const mcap::Recording& recording, const std::string& file, std::uint64_t file_bytes);
// `info` as one JSON object (times as ns and ISO 8601 UTC).
std::string to_json(const Info& info);

// ---- What a replay sends ---------------------------------------------------------------------

struct Filter {
  std::set<std::string> topics;         // full topic names; empty: every ncqual topic
  std::set<std::string> machines;       // empty: every machine
  std::optional<std::int64_t> from_ns;  // log time, inclusive
  std::optional<std::int64_t> to_ns;    // log time, inclusive
};

struct Sample {
  const dds::TopicInfo* topic = nullptr;
  std::string machine_id;
  std::int64_t log_time_ns = 0;
  std::int64_t publish_time_ns = 0;
  const mcap::Message* message = nullptr;  // into the Recording selected from
  // A message of an older wire contract: the same sample in its topic's current layout.
  std::vector<std::uint8_t> upgraded;
  // The sample's bytes in the topic's current layout: what a replay writes and a resolve reads.
  const std::vector<std::uint8_t>& bytes() const {
    return upgraded.empty() ? message->data : upgraded;
  }
};

struct Selection {
  std::vector<Sample> samples;     // in log-time order (file order among equal times)
  std::uint64_t filtered_out = 0;  // by topic, machine or time
  // Messages left out because they cannot be replayed as ncqual samples, per channel: "topic
  // (N messages): why", and unreadable messages "<location>: <why>" (at most 20 each).
  std::vector<std::string> skipped;
  std::uint64_t skipped_messages = 0;
  // Samples recorded in an older wire contract's layout, read in the current one, per topic and
  // contract: "ncqual/CheckResult" -> {1: 12}.
  std::map<std::string, std::map<int, std::uint64_t>> upgraded;
};

// The samples of `recording` that `filter` selects. Throws mcap::Error naming the file when it
// holds no ncqual channel at all (another system's recording).
Selection select(const mcap::Recording& recording, const Filter& filter, const std::string& file);

// When each sample is due, from the replay's start, at `rate` times the recorded pace: the log
// time since the first sample's, divided by the rate (ns; every value 0 for rate <= 0: as fast
// as possible).
std::vector<std::int64_t> schedule(const std::vector<Sample>& samples, double rate);

// A duration as the command line takes it: "90s", "15m", "1h", "1d" or a plain number of
// seconds; nothing when it is not one (or not positive).
std::optional<std::int64_t> parse_duration_ns(std::string_view text);

}  // namespace ncqual::recording
