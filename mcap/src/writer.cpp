// SPDX-License-Identifier: Apache-2.0
// The MCAP writer of ncqual/mcap/mcap.hpp: records serialised as the specification lays them
// out, chunks compressed with libzstd (one zstd frame) or liblz4 (the LZ4 frame format).
#include "ncqual/mcap/mcap.hpp"

#include "records.hpp"

#include <lz4frame.h>
#include <zstd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <ostream>
#include <utility>

namespace ncqual::mcap {
namespace {

// ---- serialisation (little-endian, as the specification's field types) ----

void put_u8(std::string& out, std::uint8_t v) { out.push_back(static_cast<char>(v)); }
void put_u16(std::string& out, std::uint16_t v) {
  for (int i = 0; i < 2; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFFU));
}
void put_u32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFFU));
}
void put_u64(std::string& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFFU));
}
std::uint32_t length32(std::size_t n, const char* what) {
  if (n > std::numeric_limits<std::uint32_t>::max()) {
    throw Error(std::string("mcap writer: ") + what + " is longer than 4 GiB");
  }
  return static_cast<std::uint32_t>(n);
}
// String, and uint32 length-prefixed Bytes, Array and Map contents.
void put_prefixed32(std::string& out, std::string_view bytes, const char* what) {
  put_u32(out, length32(bytes.size(), what));
  out.append(bytes);
}
void put_record(std::string& out, std::uint8_t opcode, std::string_view content) {
  put_u8(out, opcode);
  put_u64(out, content.size());
  out.append(content);
}
std::string_view as_chars(const std::vector<std::uint8_t>& bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

std::string schema_record(const Schema& s) {
  std::string c;
  put_u16(c, s.id);
  put_prefixed32(c, s.name, "a schema name");
  put_prefixed32(c, s.encoding, "a schema encoding");
  put_prefixed32(c, as_chars(s.data), "a schema's data");
  std::string r;
  put_record(r, kSchema, c);
  return r;
}

std::string channel_record(const Channel& ch) {
  std::string c;
  put_u16(c, ch.id);
  put_u16(c, ch.schema_id);
  put_prefixed32(c, ch.topic, "a topic");
  put_prefixed32(c, ch.message_encoding, "a message encoding");
  std::string map;
  for (const auto& [key, value] : ch.metadata) {
    put_prefixed32(map, key, "a metadata key");
    put_prefixed32(map, value, "a metadata value");
  }
  put_prefixed32(c, map, "a channel's metadata");
  std::string r;
  put_record(r, kChannel, c);
  return r;
}

std::string compress(const std::string& compression, const std::string& records) {
  if (compression.empty()) return records;
  std::string out;
  if (compression == "zstd") {
    out.resize(ZSTD_compressBound(records.size()));
    // Level 1: on recorded CDR (doubles that differ in every set) it makes files as small as the
    // default level 3 does, at more than twice the speed (tests/bench/recording_bench.cpp).
    const std::size_t n = ZSTD_compress(out.data(), out.size(), records.data(), records.size(), 1);
    if (ZSTD_isError(n) != 0U) {
      throw Error(std::string("mcap writer: zstd compression failed: ") + ZSTD_getErrorName(n));
    }
    out.resize(n);
    return out;
  }
  // lz4: one LZ4 frame, with the content size in its header.
  LZ4F_preferences_t preferences{};
  preferences.frameInfo.contentSize = records.size();
  out.resize(LZ4F_compressFrameBound(records.size(), &preferences));
  const std::size_t n =
      LZ4F_compressFrame(out.data(), out.size(), records.data(), records.size(), &preferences);
  if (LZ4F_isError(n) != 0U) {
    throw Error(std::string("mcap writer: lz4 compression failed: ") + LZ4F_getErrorName(n));
  }
  out.resize(n);
  return out;
}

}  // namespace

struct Writer::State {
  std::ofstream file;
  std::ostream* out = nullptr;
  std::string name;  // for errors
  Options options;
  std::uint64_t position = 0;  // bytes written
  std::uint32_t data_crc = 0;  // of every byte written so far (the data section until close)
  bool closed = false;

  std::map<std::uint16_t, Schema> schemas;
  std::map<std::uint16_t, Channel> channels;
  std::set<std::uint16_t> schemas_written;
  std::set<std::uint16_t> channels_written;

  // The chunk being filled: its uncompressed records, and per channel the (log_time, offset in
  // `chunk`) of each message.
  std::string chunk;
  std::uint64_t chunk_start_time = 0;
  std::uint64_t chunk_end_time = 0;
  bool chunk_has_messages = false;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_messages;

  std::uint64_t message_count = 0;
  std::uint64_t start_time = 0;
  std::uint64_t end_time = 0;
  std::map<std::uint16_t, std::uint64_t> channel_message_counts;
  std::uint32_t chunk_count = 0;
  std::string chunk_indexes;     // the ChunkIndex records of the summary
  std::string metadata_indexes;  // the MetadataIndex records of the summary
  std::uint32_t metadata_count = 0;

  // Writes `bytes` and adds them to the data section's CRC (from `crc`, their CRC32, when known).
  void emit(std::string_view bytes, std::optional<std::uint32_t> crc = std::nullopt) {
    out->write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!*out) {
      throw Error(name + ": writing " + std::to_string(bytes.size()) + " bytes at byte " +
                  std::to_string(position) + " failed");
    }
    position += bytes.size();
    data_crc = crc ? crc32_combine(data_crc, *crc, bytes.size()) : crc32(bytes, data_crc);
  }

  void start() {
    if (!options.compression.empty() && options.compression != "zstd" &&
        options.compression != "lz4") {
      throw Error(name + ": unknown MCAP compression '" + options.compression +
                  "' (\"\", \"zstd\" or \"lz4\")");
    }
    std::string content;
    put_prefixed32(content, options.profile, "the profile");
    put_prefixed32(content, options.library, "the library");
    std::string bytes(kMagic);
    put_record(bytes, kHeader, content);
    emit(bytes);
  }

  // Puts the Schema (if any) and Channel records of `channel_id` into the chunk, once per file.
  void define(std::uint16_t channel_id) {
    if (channels_written.count(channel_id) != 0) return;
    const Channel& ch = channels.at(channel_id);
    if (ch.schema_id != 0 && schemas_written.insert(ch.schema_id).second) {
      chunk += schema_record(schemas.at(ch.schema_id));
    }
    chunk += channel_record(ch);
    channels_written.insert(channel_id);
  }

  void close_chunk() {
    if (chunk.empty()) {
      out->flush();
      return;
    }
    // The records go out as they are (uncompressed) or compressed, without a copy into the
    // record: the chunk's fields, then the records, then the message indexes.
    const std::uint32_t records_crc = crc32(chunk);
    const std::string compressed =
        options.compression.empty() ? std::string() : compress(options.compression, chunk);
    const std::string_view records = options.compression.empty() ? chunk : compressed;
    std::string head;
    put_u64(head, chunk_has_messages ? chunk_start_time : 0);
    put_u64(head, chunk_has_messages ? chunk_end_time : 0);
    put_u64(head, chunk.size());
    put_u32(head, records_crc);
    put_prefixed32(head, options.compression, "the compression");
    put_u64(head, records.size());
    std::string bytes;
    put_u8(bytes, kChunk);
    put_u64(bytes, head.size() + records.size());
    bytes += head;
    const std::uint64_t chunk_offset = position;
    const std::uint64_t chunk_length = bytes.size() + records.size();
    emit(bytes);
    emit(records,
         options.compression.empty() ? std::optional<std::uint32_t>(records_crc) : std::nullopt);
    bytes.clear();

    // One MessageIndex per channel with messages in the chunk, in channel id order.
    std::string index_offsets;  // Map<uint16, uint64> contents
    const std::uint64_t indexes_start = position;
    for (const auto& [channel_id, entries] : chunk_messages) {
      put_u16(index_offsets, channel_id);
      put_u64(index_offsets, position + bytes.size());
      std::string array;
      for (const auto& [log_time, offset] : entries) {
        put_u64(array, log_time);
        put_u64(array, offset);
      }
      std::string index;
      put_u16(index, channel_id);
      put_prefixed32(index, array, "a message index");
      put_record(bytes, kMessageIndex, index);
    }
    const std::uint64_t indexes_length = position + bytes.size() - indexes_start;
    emit(bytes);
    out->flush();
    if (!*out) throw Error(name + ": flushing at byte " + std::to_string(position) + " failed");

    std::string ci;
    put_u64(ci, chunk_has_messages ? chunk_start_time : 0);
    put_u64(ci, chunk_has_messages ? chunk_end_time : 0);
    put_u64(ci, chunk_offset);
    put_u64(ci, chunk_length);
    put_prefixed32(ci, index_offsets, "the message index offsets");
    put_u64(ci, indexes_length);
    put_prefixed32(ci, options.compression, "the compression");
    put_u64(ci, records.size());
    put_u64(ci, chunk.size());
    put_record(chunk_indexes, kChunkIndex, ci);
    ++chunk_count;

    chunk.clear();
    chunk_messages.clear();
    chunk_has_messages = false;
    chunk_start_time = 0;
    chunk_end_time = 0;
  }

  void close() {
    // Channels without messages (and their schemas) are in the data section too.
    for (const auto& entry : channels) define(entry.first);
    close_chunk();

    std::string data_end;
    put_u32(data_end, data_crc);
    std::string bytes;
    put_record(bytes, kDataEnd, data_end);
    emit(bytes);

    // Summary: groups by opcode (Schema, Channel, Statistics, ChunkIndex), each with a
    // SummaryOffset.
    const std::uint64_t summary_start = position;
    std::string summary;
    std::string offsets;
    auto group = [&](std::uint8_t opcode, const std::string& records) {
      if (records.empty()) return;
      std::string so;
      put_u8(so, opcode);
      put_u64(so, summary_start + summary.size());
      put_u64(so, records.size());
      put_record(offsets, kSummaryOffset, so);
      summary += records;
    };
    std::string records;
    for (const auto& entry : schemas) records += schema_record(entry.second);
    group(kSchema, records);
    records.clear();
    for (const auto& entry : channels) records += channel_record(entry.second);
    group(kChannel, records);

    std::string stats;
    put_u64(stats, message_count);
    put_u16(stats, static_cast<std::uint16_t>(schemas.size()));
    put_u32(stats, static_cast<std::uint32_t>(channels.size()));
    put_u32(stats, 0);  // attachments
    put_u32(stats, metadata_count);
    put_u32(stats, chunk_count);
    put_u64(stats, message_count != 0 ? start_time : 0);
    put_u64(stats, message_count != 0 ? end_time : 0);
    std::string counts;
    for (const auto& entry : channels) {
      put_u16(counts, entry.first);
      auto it = channel_message_counts.find(entry.first);
      put_u64(counts, it == channel_message_counts.end() ? 0 : it->second);
    }
    put_prefixed32(stats, counts, "the channel message counts");
    records.clear();
    put_record(records, kStatistics, stats);
    group(kStatistics, records);
    group(kMetadataIndex, metadata_indexes);
    group(kChunkIndex, chunk_indexes);

    const std::uint64_t summary_offset_start = summary_start + summary.size();
    std::string tail = summary + offsets;
    put_u8(tail, kFooter);
    put_u64(tail, kFooterContent);
    put_u64(tail, summary_start);
    put_u64(tail, summary_offset_start);
    put_u32(tail, crc32(tail));  // from the summary's start through summary_offset_start
    tail += kMagic;
    emit(tail);
    out->flush();
    if (!*out) throw Error(name + ": flushing at byte " + std::to_string(position) + " failed");
  }
};

Writer::Writer(std::ostream& out, Options options) : state_(std::make_unique<State>()) {
  state_->out = &out;
  state_->name = "MCAP stream";
  state_->options = std::move(options);
  state_->start();
}

Writer::Writer(const std::string& path, Options options) : state_(std::make_unique<State>()) {
  state_->file.open(path, std::ios::binary | std::ios::out | std::ios::trunc);
  if (!state_->file) {
    throw Error(path + ": cannot create: " + std::strerror(errno));
  }
  state_->out = &state_->file;
  state_->name = path;
  state_->options = std::move(options);
  state_->start();
}

Writer::~Writer() {
  try {
    close();
  } catch (...) {
    // A destructor must not throw: a caller who wants the error calls close().
  }
}

std::uint16_t Writer::add_schema(const std::string& name, const std::string& encoding,
                                 std::vector<std::uint8_t> data) {
  State& s = *state_;
  if (s.closed) throw Error(s.name + ": add_schema after close()");
  if (s.schemas.size() >= std::numeric_limits<std::uint16_t>::max()) {
    throw Error(s.name + ": more than 65535 schemas");
  }
  const auto id = static_cast<std::uint16_t>(s.schemas.size() + 1);
  s.schemas[id] = Schema{id, name, encoding, std::move(data)};
  return id;
}

std::uint16_t Writer::add_channel(std::uint16_t schema_id, const std::string& topic,
                                  const std::string& message_encoding,
                                  const std::map<std::string, std::string>& metadata) {
  State& s = *state_;
  if (s.closed) throw Error(s.name + ": add_channel after close()");
  if (schema_id != 0 && s.schemas.count(schema_id) == 0) {
    throw Error(s.name + ": channel '" + topic + "' on unknown schema " +
                std::to_string(schema_id));
  }
  if (s.channels.size() >= std::numeric_limits<std::uint16_t>::max()) {
    throw Error(s.name + ": more than 65535 channels");
  }
  const auto id = static_cast<std::uint16_t>(s.channels.size() + 1);
  s.channels[id] = Channel{id, schema_id, topic, message_encoding, metadata};
  return id;
}

void Writer::write(const Message& message) {
  write(message.channel_id, message.sequence, message.log_time, message.publish_time,
        as_chars(message.data));
}

void Writer::write(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time,
                   std::uint64_t publish_time, std::string_view data) {
  State& s = *state_;
  if (s.closed) throw Error(s.name + ": write after close()");
  if (s.channels.count(channel_id) == 0) {
    throw Error(s.name + ": message on unknown channel " + std::to_string(channel_id));
  }
  s.define(channel_id);
  s.chunk_messages[channel_id].emplace_back(log_time, s.chunk.size());
  // The Message record straight into the chunk: opcode, length, then its fields.
  put_u8(s.chunk, kMessage);
  put_u64(s.chunk, 22 + data.size());
  put_u16(s.chunk, channel_id);
  put_u32(s.chunk, sequence);
  put_u64(s.chunk, log_time);
  put_u64(s.chunk, publish_time);
  s.chunk.append(data);

  if (!s.chunk_has_messages || log_time < s.chunk_start_time) {
    s.chunk_start_time = log_time;
  }
  if (!s.chunk_has_messages || log_time > s.chunk_end_time) {
    s.chunk_end_time = log_time;
  }
  s.chunk_has_messages = true;
  if (s.message_count == 0 || log_time < s.start_time) s.start_time = log_time;
  if (s.message_count == 0 || log_time > s.end_time) s.end_time = log_time;
  ++s.message_count;
  ++s.channel_message_counts[channel_id];

  if (s.chunk.size() > s.options.chunk_size) s.close_chunk();
}

void Writer::add_metadata(const std::string& name,
                          const std::map<std::string, std::string>& metadata) {
  State& s = *state_;
  if (s.closed) throw Error(s.name + ": add_metadata after close()");
  s.close_chunk();  // a Metadata record is never inside a chunk
  std::string content;
  put_prefixed32(content, name, "the metadata name");
  std::string map;
  for (const auto& [key, value] : metadata) {
    put_prefixed32(map, key, "a metadata key");
    put_prefixed32(map, value, "a metadata value");
  }
  put_prefixed32(content, map, "the metadata");
  std::string bytes;
  put_record(bytes, kMetadata, content);
  std::string index;
  put_u64(index, s.position);
  put_u64(index, bytes.size());
  put_prefixed32(index, name, "the metadata name");
  put_record(s.metadata_indexes, kMetadataIndex, index);
  ++s.metadata_count;
  s.emit(bytes);
}

std::uint64_t Writer::size() const { return state_->position + state_->chunk.size(); }

void Writer::close_chunk() {
  if (state_->closed) return;
  state_->close_chunk();
}

void Writer::close() {
  if (state_->closed) return;
  state_->closed = true;  // also when closing fails: the destructor must not try again
  state_->close();
  if (state_->file.is_open()) {
    state_->file.close();
    if (!state_->file) throw Error(state_->name + ": closing failed");
  }
}

}  // namespace ncqual::mcap
