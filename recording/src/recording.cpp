// SPDX-License-Identifier: Apache-2.0
#include "ncqual/recording/recording.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/common/version.hpp"

#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

namespace ncqual::recording {

extern const char* const kIdlText;  // idl_text.cpp, generated from idl/ncqual.idl

namespace {

constexpr std::size_t kListed = 20;  // problems listed by name; the rest are counted

std::string numbered(const std::string& path, std::size_t part) {
  const std::filesystem::path p(path);
  char number[16];
  std::snprintf(number, sizeof number, "-%04zu", part);
  return (p.parent_path() / (p.stem().string() + number + p.extension().string())).string();
}

// The highest N of the files "<stem>-NNNN<ext>" beside `path` (0 when there is none).
std::size_t highest_part(const std::string& path) {
  const std::filesystem::path p(path);
  const std::filesystem::path dir = p.parent_path().empty() ? "." : p.parent_path();
  const std::string prefix = p.stem().string() + "-";
  const std::string ext = p.extension().string();
  std::size_t highest = 0;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= prefix.size() + ext.size() || name.compare(0, prefix.size(), prefix) != 0 ||
        name.compare(name.size() - ext.size(), ext.size(), ext) != 0) {
      continue;
    }
    const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - ext.size());
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos ||
        digits.size() > 9) {
      continue;
    }
    highest = std::max<std::size_t>(highest, std::stoul(digits));
  }
  return highest;
}

std::string iso(std::uint64_t ns) {
  char buffer[32];
  return std::string(format_iso8601(static_cast<std::int64_t>(ns), buffer));
}

}  // namespace

std::string_view idl_text() { return kIdlText; }

std::vector<const dds::TopicInfo*> topics_named(const std::vector<std::string>& names) {
  std::vector<const dds::TopicInfo*> out;
  for (const auto& joined : names) {
    std::stringstream in(joined);
    std::string name;
    while (std::getline(in, name, ',')) {
      if (name.empty()) continue;
      const dds::TopicInfo* t = dds::find_topic(name);
      if (t == nullptr) {
        std::string known;
        for (const auto& k : dds::ncqual_topics()) {
          known += (known.empty() ? "" : ", ") + k.name.substr(k.name.find('/') + 1);
        }
        throw std::invalid_argument("'" + name + "' is not an ncqual topic (" + known + ")");
      }
      if (std::find(out.begin(), out.end(), t) == out.end()) out.push_back(t);
    }
  }
  return out;
}

std::map<std::string, std::string> recording_metadata(const std::string& recorder, int domain,
                                                      const std::string& plant,
                                                      std::int64_t started_ns) {
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  return {{"recorder", recorder}, {"version", version_line(recorder)},
          {"host", host},         {"domain", std::to_string(domain)},
          {"plant", plant},       {"started", iso(static_cast<std::uint64_t>(started_ns))}};
}

std::map<std::string, std::string> channel_metadata(const dds::TopicInfo& topic) {
  std::map<std::string, std::string> m;
  m["type"] = topic.type_name;
  m["keyed"] = topic.keyed ? "true" : "false";
  if (topic.keyed) m["key"] = "machine_id";
  m["partition"] = topic.per_machine ? "ncqual/machine/<machine_id>" : "";
  m["writer_profile"] = topic.writer_profile;
  m["reader_profile"] = topic.reader_profile;
  m["data_representation"] = "XCDR1";
  return m;
}

// ---- RecordingWriter -------------------------------------------------------------------------

RecordingWriter::RecordingWriter(std::string path, FileOptions options)
    : path_(std::move(path)), options_(std::move(options)) {
  open_next();
}

RecordingWriter::~RecordingWriter() {
  try {
    close();
  } catch (...) {
    // A destructor must not throw: close() reports.
  }
}

void RecordingWriter::open_next() {
  const bool rotating = options_.max_size_bytes != 0 || options_.split_every_ns != 0;
  std::string file = path_;
  if (rotating) {
    // After the highest number there: a restarted recorder overwrites nothing.
    if (files_.empty()) next_part_ = highest_part(path_);
    file = numbered(path_, ++next_part_);
    while (std::filesystem::exists(file)) file = numbered(path_, ++next_part_);
  } else if (!options_.overwrite && std::filesystem::exists(file)) {
    throw mcap::Error(file + ": exists already; give another file, or --overwrite");
  }
  mcap::Options o;
  o.profile = "ncqual";
  o.library = options_.library;
  o.compression = options_.compression;
  o.chunk_size = options_.chunk_bytes;
  writer_ = std::make_unique<mcap::Writer>(file, o);
  files_.push_back(file);
  auto metadata = options_.metadata;
  if (rotating) metadata["part"] = std::to_string(next_part_);
  writer_->add_metadata("ncqual", metadata);
  schemas_.clear();
  for (auto& [name, topic] : topics_) {
    topic.channel = 0;
    define(topic);  // every topic recorded has its channel in every file, messages or not
  }
  file_start_ns_ = -1;
}

void RecordingWriter::add_topic(const dds::TopicInfo& topic,
                                const std::map<std::string, std::string>& qos) {
  Topic t{topic, channel_metadata(topic), 0};
  for (const auto& [key, value] : qos) t.metadata[key] = value;
  define(topics_[topic.name] = std::move(t));
}

void RecordingWriter::define(Topic& t) {
  if (t.channel != 0) return;
  auto schema = schemas_.find(t.info.type_name);
  if (schema == schemas_.end()) {
    const std::string_view idl = idl_text();
    schema = schemas_
                 .emplace(t.info.type_name,
                          writer_->add_schema(t.info.type_name, "omgidl",
                                              std::vector<std::uint8_t>(idl.begin(), idl.end())))
                 .first;
  }
  t.channel = writer_->add_channel(schema->second, t.info.name, "cdr", t.metadata);
}

void RecordingWriter::write(const std::string& topic, std::int64_t log_time_ns,
                            std::int64_t publish_time_ns, const std::vector<std::uint8_t>& bytes) {
  auto it = topics_.find(topic);
  if (it == topics_.end()) throw mcap::Error(path_ + ": no channel for topic '" + topic + "'");
  if (file_start_ns_ >= 0) {
    const bool too_big = options_.max_size_bytes != 0 && writer_->size() >= options_.max_size_bytes;
    const bool too_old =
        options_.split_every_ns != 0 && log_time_ns - file_start_ns_ >= options_.split_every_ns;
    if (too_big || too_old) {
      writer_->close();
      closed_bytes_ += std::filesystem::file_size(files_.back());
      open_next();
    }
  }
  Topic& t = it->second;
  define(t);
  if (file_start_ns_ < 0) file_start_ns_ = log_time_ns;
  writer_->write(t.channel, ++sequence_,
                 static_cast<std::uint64_t>(std::max<std::int64_t>(log_time_ns, 0)),
                 static_cast<std::uint64_t>(std::max<std::int64_t>(publish_time_ns, 0)),
                 std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  ++messages_;
}

void RecordingWriter::flush() {
  if (writer_) writer_->close_chunk();
}

void RecordingWriter::close() {
  if (!writer_) return;
  auto writer = std::move(writer_);
  writer->close();
  closed_bytes_ += std::filesystem::file_size(files_.back());
}

std::uint64_t RecordingWriter::bytes() const {
  return closed_bytes_ + (writer_ ? writer_->size() : 0);
}

mcap::Recording recover(const std::string& in, const std::string& out) {
  mcap::Recording r = mcap::read_file(in);
  if (std::filesystem::exists(out) && std::filesystem::equivalent(in, out)) {
    throw mcap::Error(out + ": the recovered file must be another file than " + in);
  }
  mcap::Options o;
  o.profile = r.header.profile;
  o.library = r.header.library;
  o.compression = r.compression.size() == 1 ? *r.compression.begin() : "";
  mcap::Writer w(out, o);
  for (const auto& m : r.metadata) w.add_metadata(m.name, m.metadata);
  std::map<std::uint16_t, std::uint16_t> schema_ids;
  for (const auto& [id, s] : r.schemas) schema_ids[id] = w.add_schema(s.name, s.encoding, s.data);
  std::map<std::uint16_t, std::uint16_t> channel_ids;
  for (const auto& [id, c] : r.channels) {
    const auto schema = schema_ids.find(c.schema_id);
    channel_ids[id] = w.add_channel(schema == schema_ids.end() ? 0 : schema->second, c.topic,
                                    c.message_encoding, c.metadata);
  }
  for (const auto& m : r.messages) {
    mcap::Message copy = m;
    copy.channel_id = channel_ids.at(m.channel_id);
    w.write(copy);
  }
  w.close();
  return r;
}

// ---- Info ------------------------------------------------------------------------------------

namespace {

// Whether `channel` of `recording` carries an ncqual topic ncqual can read; else why not.
ChannelInfo describe_channel(const mcap::Recording& recording, const mcap::Channel& channel) {
  ChannelInfo c;
  c.id = channel.id;
  c.topic = channel.topic;
  c.message_encoding = channel.message_encoding;
  c.metadata = channel.metadata;
  const auto schema = recording.schemas.find(channel.schema_id);
  if (schema != recording.schemas.end()) {
    c.schema_name = schema->second.name;
    c.schema_encoding = schema->second.encoding;
    const std::string_view idl = idl_text();
    c.schema_is_this_build =
        schema->second.data.size() == idl.size() &&
        std::equal(idl.begin(), idl.end(), schema->second.data.begin(),
                   [](char a, std::uint8_t b) { return static_cast<std::uint8_t>(a) == b; });
  }
  const dds::TopicInfo* topic = nullptr;
  for (const auto& t : dds::ncqual_topics()) {
    if (t.name == channel.topic) topic = &t;
  }
  if (topic == nullptr) {
    c.problem = "not an ncqual topic";
  } else if (channel.message_encoding != "cdr") {
    c.problem = "message encoding '" + channel.message_encoding + "', not cdr";
  } else if (schema == recording.schemas.end()) {
    c.problem = "no schema (ncqual's channels name their type)";
  } else if (c.schema_encoding != "omgidl") {
    c.problem = "schema encoding '" + c.schema_encoding + "', not omgidl";
  } else if (c.schema_name != topic->type_name) {
    for (const auto& layout : topic->older) {
      if (layout.type_name == c.schema_name) c.older = &layout;
    }
    if (c.older != nullptr) {
      c.topic_info = topic;
    } else {
      c.problem = "schema '" + c.schema_name + "' is not the topic's type " + topic->type_name;
      if (!topic->older.empty()) c.problem += " nor an older wire contract's layout of it";
    }
  } else {
    c.topic_info = topic;
  }
  return c;
}

}  // namespace

Info inspect(const mcap::Recording& recording, const std::string& file, std::uint64_t file_bytes) {
  Info info;
  info.file = file;
  info.file_bytes = file_bytes;
  info.header = recording.header;
  info.metadata = recording.metadata;
  info.indexed = recording.indexed;
  info.compression = recording.compression;
  info.chunks = recording.chunks.size();
  info.warnings = recording.warnings;
  std::map<std::uint16_t, std::size_t> index;
  for (const auto& [id, channel] : recording.channels) {
    index[id] = info.channels.size();
    info.channels.push_back(describe_channel(recording, channel));
  }
  bool first = true;
  for (const auto& m : recording.messages) {
    ++info.messages;
    if (first || m.log_time < info.start_ns) info.start_ns = m.log_time;
    if (first || m.log_time > info.end_ns) info.end_ns = m.log_time;
    first = false;
    ChannelInfo& c = info.channels[index.at(m.channel_id)];
    ++c.messages;
    if (c.topic_info == nullptr) continue;
    std::string machine;
    std::string error;
    std::vector<std::uint8_t> upgraded;
    const bool readable = c.older == nullptr
                              ? c.topic_info->machine_of(m.data, machine, error)
                              : c.older->upgrade(m.data, upgraded, error) &&
                                    c.topic_info->machine_of(upgraded, machine, error);
    if (readable) {
      ++info.per_machine[{c.topic, machine}];
    } else {
      if (info.unreadable++ < kListed) {
        info.problems.push_back(mcap::location(m) + " (" + c.topic + "): " + error);
      }
    }
  }
  return info;
}

std::string to_json(const Info& info) {
  nlohmann::ordered_json j;
  j["file"] = info.file;
  j["bytes"] = info.file_bytes;
  j["profile"] = info.header.profile;
  j["library"] = info.header.library;
  j["indexed"] = info.indexed;
  j["compression"] = nlohmann::json::array();
  for (const auto& c : info.compression) j["compression"].push_back(c.empty() ? "none" : c);
  j["chunks"] = info.chunks;
  j["messages"] = info.messages;
  j["start_ns"] = info.start_ns;
  j["end_ns"] = info.end_ns;
  j["start"] = info.messages != 0 ? iso(info.start_ns) : "";
  j["end"] = info.messages != 0 ? iso(info.end_ns) : "";
  j["metadata"] = nlohmann::json::array();
  for (const auto& m : info.metadata) {
    j["metadata"].push_back({{"name", m.name}, {"metadata", m.metadata}});
  }
  j["channels"] = nlohmann::json::array();
  for (const auto& c : info.channels) {
    nlohmann::ordered_json cj;
    cj["id"] = c.id;
    cj["topic"] = c.topic;
    cj["message_encoding"] = c.message_encoding;
    cj["schema"] = c.schema_name;
    cj["schema_encoding"] = c.schema_encoding;
    cj["schema_is_this_build"] = c.schema_is_this_build;
    if (c.topic_info != nullptr) {
      cj["wire_contract"] = c.older != nullptr ? c.older->contract : c.topic_info->contract;
    }
    cj["messages"] = c.messages;
    cj["ncqual"] = c.topic_info != nullptr;
    if (!c.problem.empty()) cj["problem"] = c.problem;
    cj["metadata"] = c.metadata;
    j["channels"].push_back(cj);
  }
  j["per_machine"] = nlohmann::json::array();
  for (const auto& [key, count] : info.per_machine) {
    j["per_machine"].push_back(
        {{"topic", key.first}, {"machine", key.second}, {"messages", count}});
  }
  j["unreadable"] = info.unreadable;
  j["problems"] = info.problems;
  j["warnings"] = info.warnings;
  return j.dump(2);
}

// ---- Selection -------------------------------------------------------------------------------

Selection select(const mcap::Recording& recording, const Filter& filter, const std::string& file) {
  Selection s;
  std::map<std::uint16_t, ChannelInfo> channels;
  bool any_ncqual = false;
  for (const auto& [id, channel] : recording.channels) {
    channels[id] = describe_channel(recording, channel);
    any_ncqual = any_ncqual || channels[id].topic_info != nullptr;
  }
  if (!any_ncqual) {
    std::string names;
    std::size_t n = 0;
    for (const auto& [id, c] : channels) {
      if (n++ == 5) {
        names += ", ...";
        break;
      }
      names += (names.empty() ? "" : ", ") + c.topic + " (" + c.problem + ")";
    }
    throw mcap::Error(file + ": no ncqual topic in this recording" +
                      (names.empty() ? std::string(" (it has no channels)")
                                     : std::string(": its channels are ") + names));
  }
  std::map<std::uint16_t, std::uint64_t> skipped_per_channel;
  std::uint64_t unreadable = 0;
  for (const auto& m : recording.messages) {
    const ChannelInfo& c = channels.at(m.channel_id);
    if (c.topic_info == nullptr) {
      ++skipped_per_channel[m.channel_id];
      ++s.skipped_messages;
      continue;
    }
    if (!filter.topics.empty() && filter.topics.count(c.topic) == 0) {
      ++s.filtered_out;
      continue;
    }
    const auto log = static_cast<std::int64_t>(m.log_time);
    if ((filter.from_ns && log < *filter.from_ns) || (filter.to_ns && log > *filter.to_ns)) {
      ++s.filtered_out;
      continue;
    }
    Sample sample;
    std::string error;
    if (c.older != nullptr && !c.older->upgrade(m.data, sample.upgraded, error)) {
      ++s.skipped_messages;
      if (unreadable++ < kListed) {
        s.skipped.push_back(mcap::location(m) + " (" + c.topic + ", wire contract " +
                            std::to_string(c.older->contract) + "): " + error);
      }
      continue;
    }
    sample.message = &m;
    if (!c.topic_info->machine_of(sample.bytes(), sample.machine_id, error)) {
      ++s.skipped_messages;
      if (unreadable++ < kListed) {
        s.skipped.push_back(mcap::location(m) + " (" + c.topic + "): " + error);
      }
      continue;
    }
    if (!filter.machines.empty() && filter.machines.count(sample.machine_id) == 0) {
      ++s.filtered_out;
      continue;
    }
    sample.topic = c.topic_info;
    sample.log_time_ns = log;
    sample.publish_time_ns = static_cast<std::int64_t>(m.publish_time);
    if (c.older != nullptr) ++s.upgraded[c.topic][c.older->contract];
    s.samples.push_back(std::move(sample));
  }
  for (const auto& [id, count] : skipped_per_channel) {
    const ChannelInfo& c = channels.at(id);
    s.skipped.insert(s.skipped.begin(),
                     c.topic + " (" + std::to_string(count) + " messages): " + c.problem);
  }
  std::stable_sort(s.samples.begin(), s.samples.end(),
                   [](const Sample& a, const Sample& b) { return a.log_time_ns < b.log_time_ns; });
  return s;
}

std::vector<std::int64_t> schedule(const std::vector<Sample>& samples, double rate) {
  std::vector<std::int64_t> due(samples.size(), 0);
  if (samples.empty() || !(rate > 0)) return due;
  const std::int64_t first = samples.front().log_time_ns;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    due[i] = static_cast<std::int64_t>(
        std::llround(static_cast<double>(samples[i].log_time_ns - first) / rate));
  }
  return due;
}

std::optional<std::int64_t> parse_duration_ns(std::string_view text) {
  if (text.empty()) return std::nullopt;
  std::int64_t unit = 1000000000LL;
  switch (text.back()) {
    case 's': text.remove_suffix(1); break;
    case 'm':
      unit *= 60;
      text.remove_suffix(1);
      break;
    case 'h':
      unit *= 3600;
      text.remove_suffix(1);
      break;
    case 'd':
      unit *= 86400;
      text.remove_suffix(1);
      break;
    default: break;
  }
  std::int64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value <= 0 ||
      value > std::numeric_limits<std::int64_t>::max() / unit) {
    return std::nullopt;
  }
  return value * unit;
}

}  // namespace ncqual::recording
