// SPDX-License-Identifier: Apache-2.0
// ncqual_mcap: a small writer and reader of MCAP files (https://mcap.dev/spec, major version 0),
// written from the specification, for recording and replaying DDS traffic.
//
// Writer: Magic, Header, then Chunks (uncompressed, zstd or lz4 frame) holding the Schema and
// Channel records before the first message that uses them, and the Message records; after each
// Chunk one MessageIndex per channel in it. close() writes DataEnd (with the data section's
// CRC32), the summary (Schema and Channel copies, Statistics, one ChunkIndex per chunk), the
// summary offsets, the Footer (with the summary CRC32) and the closing Magic. The stream is
// flushed after every chunk, so a killed process leaves every completed chunk readable.
//
// Reader: reads a whole file in memory, every Message of the data section (inside chunks or not)
// in file order, checking every CRC that is not zero. Any malformed input is an mcap::Error whose
// what() names the file, the record and its byte offset:
//   "run.mcap: Chunk at byte 1234: length 99999 runs past the end of the file (5000 bytes)"
// A file without its closing Magic is a truncated recording (a recorder killed mid-way): it is
// read up to its last complete record, with a warning, and `indexed` is false.
//
// Times are uint64 nanoseconds (MCAP Timestamp); every integer on disk is little-endian.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::mcap {

// Every problem of the writer (an unknown channel, a failed write) and of the reader (a
// malformed file).
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The CRC32 of MCAP (and zlib: reflected polynomial 0xEDB88320), chainable as zlib's:
// crc32(b, crc32(a)) == crc32(a + b). crc32("123456789") == 0xCBF43926.
std::uint32_t crc32(std::string_view bytes, std::uint32_t previous = 0);
// The CRC32 of a + b from crc32(a), crc32(b) and b's length, without reading either again.
std::uint32_t crc32_combine(std::uint32_t crc_a, std::uint32_t crc_b, std::uint64_t length_b);

// The name of a record opcode as the specification spells it ("Chunk", "MessageIndex"), or
// "record 0xNN" for an opcode it does not define.
std::string opcode_name(std::uint8_t opcode);

struct Schema {
  std::uint16_t id = 0;  // never 0
  std::string name;
  std::string encoding;  // e.g. "omgidl", "ros2msg"; empty: no schema
  std::vector<std::uint8_t> data;
};

struct Channel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;  // 0: no schema
  std::string topic;
  std::string message_encoding;  // e.g. "cdr"
  std::map<std::string, std::string> metadata;
};

struct Message {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0;      // ns, when it was recorded
  std::uint64_t publish_time = 0;  // ns, when it was published (log_time when unknown)
  std::vector<std::uint8_t> data;
  // Where the reader found it: the Chunk record holding it (its file offset; 0 when not in a
  // chunk) and the Message record's offset in the chunk's uncompressed records, or in the file.
  // Not written.
  std::uint64_t chunk_offset = 0;
  std::uint64_t record_offset = 0;
};

// "Message at byte 120 of the Chunk at byte 1234" (or "Message at byte 120"), for errors about
// a message's content.
std::string location(const Message& message);

// A Metadata record: a name and string pairs (e.g. who recorded, with which version).
struct Metadata {
  std::string name;
  std::map<std::string, std::string> metadata;
};

// ---- Writer ----------------------------------------------------------------------------------

struct Options {
  std::string profile;      // Header.profile, e.g. "" or "ros2"
  std::string library;      // Header.library, e.g. "ncqual 0.1.0"
  std::string compression;  // of every chunk: "" (none), "zstd" or "lz4"
  // A chunk is closed once its uncompressed records exceed this many bytes.
  std::uint64_t chunk_size = std::uint64_t{1} << 20;  // 1 MiB
};

class Writer {
 public:
  // Writes to `out` (left open by close()); the Magic and Header are written at once. Throws
  // Error for an unknown compression or a failed write.
  Writer(std::ostream& out, Options options = {});
  // Creates (truncates) the file `path`; throws Error when it cannot.
  Writer(const std::string& path, Options options = {});
  // Closes the file if close() was not called; never throws (an error is lost then: call
  // close() to see it).
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // A new schema; its id (1, 2, ...). Written into the data section before the first message of
  // a channel that uses it.
  std::uint16_t add_schema(const std::string& name, const std::string& encoding,
                           std::vector<std::uint8_t> data);
  // A new channel; its id (1, 2, ...). `schema_id` is 0 or an id add_schema() returned (else
  // Error). Written into the data section before its first message (or at close()).
  std::uint16_t add_channel(std::uint16_t schema_id, const std::string& topic,
                            const std::string& message_encoding,
                            const std::map<std::string, std::string>& metadata = {});
  // Appends a message to the current chunk, closing the chunk when it exceeds chunk_size. Error
  // for a channel add_channel() did not return, or after close().
  void write(const Message& message);
  // The same for a message given by its fields, its data not copied but into the chunk.
  void write(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time,
             std::uint64_t publish_time, std::string_view data);
  // A Metadata record, written at once (the current chunk is closed first: Metadata records are
  // never in a chunk) and indexed in the summary.
  void add_metadata(const std::string& name, const std::map<std::string, std::string>& metadata);
  // The bytes written so far, the open chunk's records included (uncompressed).
  std::uint64_t size() const;
  // Writes the current chunk (if it holds any record) and its message indexes, and flushes the
  // stream: everything written so far survives a killed process. For a recorder's timer.
  void close_chunk();
  // Closes the last chunk, writes DataEnd, the summary, the Footer and the Magic, and flushes.
  // Idempotent.
  void close();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// ---- Reader ----------------------------------------------------------------------------------

struct Header {
  std::string profile;
  std::string library;
};

struct Statistics {
  std::uint64_t message_count = 0;
  std::uint16_t schema_count = 0;
  std::uint32_t channel_count = 0;
  std::uint32_t attachment_count = 0;
  std::uint32_t metadata_count = 0;
  std::uint32_t chunk_count = 0;
  std::uint64_t message_start_time = 0;
  std::uint64_t message_end_time = 0;
  std::map<std::uint16_t, std::uint64_t> channel_message_counts;
};

// A Chunk record of the data section, as read.
struct ChunkInfo {
  std::uint64_t offset = 0;  // of the record (its opcode) from the start of the file
  std::uint64_t length = 0;  // of the record, opcode and length prefix included
  std::string compression;   // "" for none
  std::uint64_t compressed_size = 0;
  std::uint64_t uncompressed_size = 0;
  std::uint64_t message_start_time = 0;
  std::uint64_t message_end_time = 0;
  std::size_t message_count = 0;
};

struct Recording {
  Header header;
  std::map<std::uint16_t, Schema> schemas;
  std::map<std::uint16_t, Channel> channels;
  std::vector<Message> messages;      // in file order
  std::vector<Metadata> metadata;     // in file order
  std::vector<ChunkInfo> chunks;      // in file order
  bool indexed = false;               // a summary was read with a ChunkIndex for every chunk read
  std::set<std::string> compression;  // of the chunks ("" for uncompressed ones)
  std::optional<Statistics> statistics;
  std::vector<std::string> warnings;  // e.g. the summary is missing; each names the file
};

// Reads a whole MCAP file held in `bytes`; `file_name` names it in errors and warnings.
Recording read(std::string_view bytes, const std::string& file_name);
// Reads the file `path` (Error when it cannot be opened or read).
Recording read_file(const std::string& path);

}  // namespace ncqual::mcap
