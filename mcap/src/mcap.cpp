// SPDX-License-Identifier: Apache-2.0
// The MCAP writer and reader of ncqual/mcap/mcap.hpp: record layouts as in the specification
// (https://mcap.dev/spec), chunk compression with libzstd (one zstd frame) and liblz4 (the LZ4
// frame format), CRC32 of the reflected polynomial 0xEDB88320 (carry-less multiplication where
// the CPU has it, else eight bytes a step from tables).
#include "ncqual/mcap/mcap.hpp"

#include <lz4frame.h>
#include <zstd.h>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <new>
#include <ostream>
#include <utility>

namespace ncqual::mcap {
namespace {

constexpr std::string_view kMagic{"\x89MCAP0\r\n", 8};
// opcode (1) + content length (8)
constexpr std::uint64_t kRecordPrefix = 9;
// The Footer record: prefix + summary_start (8) + summary_offset_start (8) + summary_crc (4).
constexpr std::uint64_t kFooterContent = 20;
constexpr std::uint64_t kFooterRecord = kRecordPrefix + kFooterContent;
// The largest uncompressed chunk the reader accepts (ncqual writes 1 MiB chunks): a corrupt
// uncompressed_size must not make it allocate without bound.
constexpr std::uint64_t kMaxUncompressedChunk = std::uint64_t{1} << 30;

enum Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// Slicing-by-8 (Kounavis and Berry, "A Systematic Approach to Building High Performance
// Software-based CRC Generators", 2005): table[0] is the classic byte table, table[k][b] the CRC
// of byte b followed by k zero bytes, so eight bytes are folded in per step. About six times the
// byte-at-a-time loop, which a recorder's every byte passes through twice (a chunk's records,
// the data section).
using CrcTables = std::array<std::array<std::uint32_t, 256>, 8>;
CrcTables make_crc_tables() {
  CrcTables t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1) : c >> 1;
    t[0][i] = c;
  }
  for (std::uint32_t i = 0; i < 256; ++i) {
    for (std::size_t k = 1; k < 8; ++k) t[k][i] = (t[k - 1][i] >> 8) ^ t[0][t[k - 1][i] & 0xFFU];
  }
  return t;
}

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

namespace {

// The CRC register (not inverted) after `n` bytes at `p`, eight bytes a step.
std::uint32_t crc32_tables(std::uint32_t c, const unsigned char* p, std::size_t n) {
  static const CrcTables t = make_crc_tables();
  for (; n >= 8; n -= 8, p += 8) {
    // The eight bytes as two little-endian words, whatever the host's byte order.
    const std::uint32_t lo = c ^ (std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 |
                                  std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24);
    const std::uint32_t hi = std::uint32_t{p[4]} | std::uint32_t{p[5]} << 8 |
                             std::uint32_t{p[6]} << 16 | std::uint32_t{p[7]} << 24;
    c = t[7][lo & 0xFFU] ^ t[6][(lo >> 8) & 0xFFU] ^ t[5][(lo >> 16) & 0xFFU] ^ t[4][lo >> 24] ^
        t[3][hi & 0xFFU] ^ t[2][(hi >> 8) & 0xFFU] ^ t[1][(hi >> 16) & 0xFFU] ^ t[0][hi >> 24];
  }
  for (; n > 0; --n, ++p) c = t[0][(c ^ *p) & 0xFFU] ^ (c >> 8);
  return c;
}

#if defined(__x86_64__)
// Folding with carry-less multiplication (Gopal et al., Intel, "Fast CRC Computation for Generic
// Polynomials Using PCLMULQDQ Instruction", 2009), for the reflected polynomial: four 128-bit
// lanes folded 64 bytes a step, then into one lane, then 128 -> 64 bits and a Barrett reduction
// to 32. The constants are x^k mod P for the fold distances, bit-reflected and shifted as the
// paper gives them for P = 0x104C11DB7: k1 = x^(4*128+32), k2 = x^(4*128-32), k3 = x^(128+32),
// k4 = x^(128-32), k5 = x^64, and mu = floor(x^64 / P). Several times the table's speed on a
// CPU that has the instruction; `n` is at least 64, the last n % 16 bytes are left to the caller.
__attribute__((target("pclmul,sse4.1"))) __m128i load(const unsigned char* at) {
  return _mm_loadu_si128(reinterpret_cast<const __m128i*>(at));
}
// x folded forward by the distance whose constants k holds, onto `next`.
__attribute__((target("pclmul,sse4.1"))) __m128i fold(__m128i x, __m128i k, __m128i next) {
  return _mm_xor_si128(
      _mm_xor_si128(_mm_clmulepi64_si128(x, k, 0x00), _mm_clmulepi64_si128(x, k, 0x11)), next);
}

__attribute__((target("pclmul,sse4.1"))) std::uint32_t crc32_folded(std::uint32_t c,
                                                                    const unsigned char* p,
                                                                    std::size_t n) {
  __m128i x1 = _mm_xor_si128(load(p), _mm_cvtsi32_si128(static_cast<int>(c)));
  __m128i x2 = load(p + 16);
  __m128i x3 = load(p + 32);
  __m128i x4 = load(p + 48);
  p += 64;
  n -= 64;
  const __m128i k1k2 = _mm_set_epi64x(0x01c6e41596LL, 0x0154442bd4LL);
  for (; n >= 64; n -= 64, p += 64) {
    x1 = fold(x1, k1k2, load(p));
    x2 = fold(x2, k1k2, load(p + 16));
    x3 = fold(x3, k1k2, load(p + 32));
    x4 = fold(x4, k1k2, load(p + 48));
  }
  const __m128i k3k4 = _mm_set_epi64x(0x00ccaa009eLL, 0x01751997d0LL);
  x1 = fold(x1, k3k4, x2);
  x1 = fold(x1, k3k4, x3);
  x1 = fold(x1, k3k4, x4);
  for (; n >= 16; n -= 16, p += 16) x1 = fold(x1, k3k4, load(p));
  // 128 -> 64 bits.
  const __m128i low32 = _mm_setr_epi32(-1, 0, -1, 0);
  x1 = _mm_xor_si128(_mm_srli_si128(x1, 8), _mm_clmulepi64_si128(x1, k3k4, 0x10));
  const __m128i k5 = _mm_set_epi64x(0, 0x0163cd6124LL);
  x1 = _mm_xor_si128(_mm_clmulepi64_si128(_mm_and_si128(x1, low32), k5, 0x00),
                     _mm_srli_si128(x1, 4));
  // Barrett reduction, 64 -> 32 bits.
  const __m128i poly_mu = _mm_set_epi64x(0x01f7011641LL, 0x01db710641LL);
  __m128i t = _mm_clmulepi64_si128(_mm_and_si128(x1, low32), poly_mu, 0x10);
  t = _mm_clmulepi64_si128(_mm_and_si128(t, low32), poly_mu, 0x00);
  return static_cast<std::uint32_t>(_mm_extract_epi32(_mm_xor_si128(x1, t), 1));
}

bool cpu_folds() {
  static const bool folds = __builtin_cpu_supports("pclmul") && __builtin_cpu_supports("sse4.1");
  return folds;
}
#endif

}  // namespace

std::uint32_t crc32(std::string_view bytes, std::uint32_t previous) {
  std::uint32_t c = ~previous;
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  std::size_t n = bytes.size();
#if defined(__x86_64__)
  if (n >= 64 && cpu_folds()) {
    const std::size_t folded = n - n % 16;
    c = crc32_folded(c, p, folded);
    p += folded;
    n -= folded;
  }
#endif
  return ~crc32_tables(c, p, n);
}

std::uint32_t crc32_portable(std::string_view bytes, std::uint32_t previous) {
  return ~crc32_tables(~previous, reinterpret_cast<const unsigned char*>(bytes.data()),
                       bytes.size());
}

namespace {

// CRC arithmetic in GF(2)[x] modulo the CRC polynomial, in the reflected representation (bit 31
// is x^0): the product of two residues, and x^(8 n), the effect of n zero bytes. With them the
// CRC of a + b follows from the CRCs of a and of b and b's length alone (crc32_combine), so the
// data section's CRC need not read a chunk's records a second time.
std::uint32_t multiply_mod_p(std::uint32_t a, std::uint32_t b) {
  std::uint32_t product = 0;
  for (std::uint32_t bit = 0x80000000U; bit != 0; bit >>= 1) {
    if ((a & bit) != 0) product ^= b;
    b = (b & 1U) != 0 ? (b >> 1) ^ 0xEDB88320U : b >> 1;  // b * x
  }
  return product;
}

std::uint32_t x_to_8n_mod_p(std::uint64_t n) {
  std::uint32_t result = 0x80000000U;  // x^0
  std::uint32_t square = 0x00800000U;  // x^8, then x^16, x^32, ...: x^(8 * 2^k)
  for (; n != 0; n >>= 1) {
    if ((n & 1U) != 0) result = multiply_mod_p(square, result);
    square = multiply_mod_p(square, square);
  }
  return result;
}

}  // namespace

std::uint32_t crc32_combine(std::uint32_t crc_a, std::uint32_t crc_b, std::uint64_t length_b) {
  return multiply_mod_p(x_to_8n_mod_p(length_b), crc_a) ^ crc_b;
}

std::string opcode_name(std::uint8_t opcode) {
  switch (opcode) {
    case kHeader: return "Header";
    case kFooter: return "Footer";
    case kSchema: return "Schema";
    case kChannel: return "Channel";
    case kMessage: return "Message";
    case kChunk: return "Chunk";
    case kMessageIndex: return "MessageIndex";
    case kChunkIndex: return "ChunkIndex";
    case kAttachment: return "Attachment";
    case kAttachmentIndex: return "AttachmentIndex";
    case kStatistics: return "Statistics";
    case kMetadata: return "Metadata";
    case kMetadataIndex: return "MetadataIndex";
    case kSummaryOffset: return "SummaryOffset";
    case kDataEnd: return "DataEnd";
    default: break;
  }
  static const char* const hex = "0123456789ABCDEF";
  return std::string("record 0x") + hex[opcode >> 4] + hex[opcode & 0xFU];
}

// ---- Writer ----------------------------------------------------------------------------------

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

// ---- Reader ----------------------------------------------------------------------------------

namespace {

// Where a record is, for errors: "Chunk at byte 1234" or "Message at byte 56 of the Chunk at
// byte 1234".
struct Place {
  const std::string* file;
  std::string record;

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(*file + ": " + record + ": " + what);
  }
};

std::string describe(std::uint8_t opcode, std::uint64_t offset, const std::string& within = "") {
  std::string s = opcode_name(opcode) + " at byte " + std::to_string(offset);
  if (!within.empty()) s += " of the " + within;
  return s;
}

std::uint64_t get_le(std::string_view bytes, std::size_t at, int size) {
  std::uint64_t v = 0;
  for (int i = size - 1; i >= 0; --i) {
    v = (v << 8) | static_cast<std::uint8_t>(bytes[at + static_cast<std::size_t>(i)]);
  }
  return v;
}

// The fields of one record's content, read in order, each checked against the content's end.
class Fields {
 public:
  Fields(std::string_view content, const Place& place) : content_(content), place_(place) {}

  std::uint8_t u8(const char* field) { return static_cast<std::uint8_t>(fixed(1, field)); }
  std::uint16_t u16(const char* field) { return static_cast<std::uint16_t>(fixed(2, field)); }
  std::uint32_t u32(const char* field) { return static_cast<std::uint32_t>(fixed(4, field)); }
  std::uint64_t u64(const char* field) { return fixed(8, field); }
  // uint32 length-prefixed: String, Bytes, and the contents of an Array or a Map.
  std::string_view prefixed32(const char* field) { return take(u32(field), field); }
  // uint64 length-prefixed Bytes.
  std::string_view prefixed64(const char* field) { return take(u64(field), field); }
  std::string_view rest() {
    std::string_view r = content_.substr(pos_);
    pos_ = content_.size();
    return r;
  }
  bool done() const { return pos_ == content_.size(); }
  std::size_t position() const { return pos_; }

  std::string_view take(std::uint64_t n, const char* field) {
    if (n > content_.size() - pos_) {
      place_.fail(std::string(field) + ": " + std::to_string(n) + " bytes at byte " +
                  std::to_string(pos_) + " of the record run past its end (" +
                  std::to_string(content_.size()) + " bytes of content)");
    }
    std::string_view v = content_.substr(pos_, static_cast<std::size_t>(n));
    pos_ += static_cast<std::size_t>(n);
    return v;
  }

 private:
  std::uint64_t fixed(int size, const char* field) {
    std::string_view b = take(static_cast<std::uint64_t>(size), field);
    return get_le(b, 0, size);
  }

  std::string_view content_;
  const Place& place_;
  std::size_t pos_ = 0;
};

std::map<std::string, std::string> string_map(std::string_view bytes, const Place& place,
                                              const char* field) {
  std::map<std::string, std::string> m;
  Fields f(bytes, place);
  while (!f.done()) {
    std::string key(f.prefixed32(field));
    m[key] = std::string(f.prefixed32(field));
  }
  return m;
}

std::string decompress(const std::string& compression, std::string_view src,
                       std::uint64_t uncompressed_size, const Place& place) {
  if (uncompressed_size > kMaxUncompressedChunk) {
    place.fail("uncompressed_size " + std::to_string(uncompressed_size) +
               " is larger than this reader accepts (" + std::to_string(kMaxUncompressedChunk) +
               " bytes)");
  }
  std::string out;
  try {
    out.resize(static_cast<std::size_t>(uncompressed_size));
  } catch (const std::bad_alloc&) {
    place.fail("cannot allocate uncompressed_size " + std::to_string(uncompressed_size));
  }
  if (compression == "zstd") {
    const unsigned long long frame = ZSTD_getFrameContentSize(src.data(), src.size());
    if (frame == ZSTD_CONTENTSIZE_ERROR) place.fail("records are not a zstd frame");
    if (frame != ZSTD_CONTENTSIZE_UNKNOWN && frame != uncompressed_size) {
      place.fail("the zstd frame holds " + std::to_string(frame) +
                 " bytes, uncompressed_size says " + std::to_string(uncompressed_size));
    }
    const std::size_t n = ZSTD_decompress(out.data(), out.size(), src.data(), src.size());
    if (ZSTD_isError(n) != 0U) {
      place.fail(std::string("zstd decompression failed: ") + ZSTD_getErrorName(n));
    }
    if (n != uncompressed_size) {
      place.fail("zstd decompressed to " + std::to_string(n) + " bytes, uncompressed_size says " +
                 std::to_string(uncompressed_size));
    }
    return out;
  }
  // lz4 (the caller has checked the name): LZ4 frames.
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION)) != 0U) {
    place.fail("cannot create an lz4 decompression context");
  }
  std::unique_ptr<LZ4F_dctx, LZ4F_errorCode_t (*)(LZ4F_dctx*)> context(
      raw, &LZ4F_freeDecompressionContext);
  std::size_t in = 0;
  std::size_t done = 0;
  std::size_t hint = 1;
  while (in < src.size()) {
    std::size_t out_size = out.size() - done;
    std::size_t in_size = src.size() - in;
    hint = LZ4F_decompress(context.get(), out.data() + done, &out_size, src.data() + in, &in_size,
                           nullptr);
    if (LZ4F_isError(hint) != 0U) {
      place.fail(std::string("lz4 decompression failed: ") + LZ4F_getErrorName(hint));
    }
    in += in_size;
    done += out_size;
    if (in_size == 0 && out_size == 0) break;  // no progress: the output is full
  }
  if (hint != 0 || in != src.size()) {
    place.fail("the lz4 frame is incomplete or holds more than uncompressed_size " +
               std::to_string(uncompressed_size) + " bytes");
  }
  if (done != uncompressed_size) {
    place.fail("lz4 decompressed to " + std::to_string(done) + " bytes, uncompressed_size says " +
               std::to_string(uncompressed_size));
  }
  return out;
}

class Parser {
 public:
  Parser(std::string_view file, const std::string& name) : file_(file), name_(name) {}

  Recording run() {
    const std::uint64_t size = file_.size();
    Place magic{&name_, "Magic at byte 0"};
    if (size < kMagic.size()) {
      if (file_ == kMagic.substr(0, file_.size())) {
        magic.fail("the file is " + std::to_string(size) + " bytes, shorter than the magic");
      }
      magic.fail("not an MCAP file (its first bytes are not the MCAP magic)");
    }
    if (file_.substr(0, kMagic.size()) != kMagic) {
      magic.fail("not an MCAP file (its first 8 bytes are not the MCAP magic \\x89MCAP0\\r\\n)");
    }
    const bool complete = size >= kMagic.size() + kRecordPrefix + kFooterRecord + kMagic.size() &&
                          file_.substr(size - kMagic.size()) == kMagic;

    std::uint64_t data_end = size;  // where the data section's records must end
    std::uint64_t footer_at = 0;
    std::uint64_t summary_start = 0;
    std::uint64_t summary_offset_start = 0;
    if (complete) {
      footer_at = size - kMagic.size() - kFooterRecord;
      Place place{&name_, describe(kFooter, footer_at)};
      const auto opcode = static_cast<std::uint8_t>(file_[footer_at]);
      const std::uint64_t length = get_le(file_, footer_at + 1, 8);
      if (opcode != kFooter || length != kFooterContent) {
        place.fail(
            "the file ends with the magic but not after a Footer record (opcode 0x02, "
            "length 20) : found " +
            opcode_name(opcode) + " of length " + std::to_string(length));
      }
      Fields f(file_.substr(footer_at + kRecordPrefix, kFooterContent), place);
      summary_start = f.u64("summary_start");
      summary_offset_start = f.u64("summary_offset_start");
      const std::uint32_t summary_crc = f.u32("summary_crc");
      if (summary_start != 0 && (summary_start < kMagic.size() || summary_start > footer_at)) {
        place.fail("summary_start " + std::to_string(summary_start) +
                   " is outside the file's sections (the Footer is at byte " +
                   std::to_string(footer_at) + ")");
      }
      if (summary_offset_start != 0 &&
          (summary_offset_start < summary_start || summary_offset_start > footer_at)) {
        place.fail("summary_offset_start " + std::to_string(summary_offset_start) +
                   " is outside the summary (" + std::to_string(summary_start) + " to " +
                   std::to_string(footer_at) + ")");
      }
      if (summary_crc != 0 && summary_start != 0) {
        const std::uint64_t crc_end = footer_at + kRecordPrefix + 16;
        const std::uint32_t actual = crc32(file_.substr(summary_start, crc_end - summary_start));
        if (actual != summary_crc) {
          place.fail("summary_crc " + hex(summary_crc) + " does not match the summary's CRC32 " +
                     hex(actual));
        }
      }
      data_end = summary_start != 0 ? summary_start : footer_at;
    }

    // The Header: the first record, complete in any file that is read at all.
    std::uint64_t pos = kMagic.size();
    {
      const Slice header = slice(pos, data_end, "");
      if (!header.ok || header.opcode != kHeader) {
        Place place{&name_, header.ok ? describe(header.opcode, pos) : "Header at byte 8"};
        if (!header.ok) place.fail(header.problem);
        place.fail("the first record after the magic is not a Header");
      }
      Place place{&name_, describe(kHeader, pos)};
      Fields f(header.content, place);
      result_.header.profile = std::string(f.prefixed32("profile"));
      result_.header.library = std::string(f.prefixed32("library"));
      pos += kRecordPrefix + header.content.size();
    }

    // The data section, up to DataEnd.
    bool data_end_seen = false;
    while (pos < data_end) {
      const Slice r = slice(pos, data_end, "");
      if (!r.ok) {
        if (!complete) {
          warn("the file ends inside a record: " + r.problem_place + ": " + r.problem +
               "; it is left out");
          break;
        }
        Place{&name_, r.problem_place}.fail(r.problem);
      }
      Place place{&name_, describe(r.opcode, pos)};
      if (r.opcode == kDataEnd) {
        Fields f(r.content, place);
        const std::uint32_t crc = f.u32("data_section_crc");
        if (crc != 0) {
          const std::uint32_t actual = crc32(file_.substr(0, pos));
          if (actual != crc) {
            place.fail("data_section_crc " + hex(crc) + " does not match the CRC32 " + hex(actual) +
                       " of the bytes before it");
          }
        }
        data_end_seen = true;
        pos += kRecordPrefix + r.content.size();
        break;
      }
      data_record(r.opcode, r.content, place, pos);
      pos += kRecordPrefix + r.content.size();
    }

    if (!complete) {
      warn("the summary and footer are missing (the file ends at byte " + std::to_string(size) +
           " without the closing magic: a truncated recording?); read " +
           std::to_string(result_.chunks.size()) + " complete chunks, " +
           std::to_string(result_.messages.size()) + " messages");
      return std::move(result_);
    }
    if (!data_end_seen) warn("the data section has no DataEnd record");

    if (summary_start != 0) {
      const std::uint64_t end = summary_offset_start != 0 ? summary_offset_start : footer_at;
      summary(summary_start, end);
      // The summary offset section: only checked to be well-formed records.
      for (std::uint64_t p = end; p < footer_at;) {
        const Slice r = slice(p, footer_at, "");
        if (!r.ok) Place{&name_, r.problem_place}.fail(r.problem);
        p += kRecordPrefix + r.content.size();
      }
    } else {
      warn("the file has no summary section (not indexed)");
    }
    if (result_.statistics && result_.statistics->message_count != result_.messages.size()) {
      warn("the Statistics count " + std::to_string(result_.statistics->message_count) +
           " messages, the data section holds " + std::to_string(result_.messages.size()));
    }
    return std::move(result_);
  }

 private:
  // One record of `buffer` at `pos`, checked to end before `end`.
  struct Slice {
    bool ok = false;
    std::uint8_t opcode = 0;
    std::string_view content;
    std::string problem_place;  // when !ok
    std::string problem;
  };

  // `within` is empty for the file's own records, else the chunk whose records `buffer` holds.
  Slice slice(std::uint64_t pos, std::uint64_t end, const std::string& within,
              std::string_view buffer = {}) const {
    const std::string_view buf = within.empty() ? file_ : buffer;
    std::string limit;
    if (!within.empty()) {
      limit = "the chunk's records (" + std::to_string(end) + " bytes)";
    } else if (end == file_.size()) {
      limit = "the file (" + std::to_string(end) + " bytes)";
    } else {
      limit = "its section, which ends at byte " + std::to_string(end);
    }
    Slice s;
    if (end - pos < kRecordPrefix) {
      s.problem_place = "record at byte " + std::to_string(pos);
      if (!within.empty()) s.problem_place += " of the " + within;
      s.problem = "its opcode and length (9 bytes) run past the end of " + limit;
      return s;
    }
    s.opcode = static_cast<std::uint8_t>(buf[pos]);
    const std::uint64_t length = get_le(buf, static_cast<std::size_t>(pos) + 1, 8);
    s.problem_place = describe(s.opcode, pos, within);
    if (s.opcode == 0) {
      s.problem = "opcode 0x00 is not a valid record opcode";
      return s;
    }
    if (length > end - pos - kRecordPrefix) {
      if (within.empty() && length > file_.size() - pos - kRecordPrefix) {
        limit = "the file (" + std::to_string(file_.size()) + " bytes)";
      }
      s.problem = "length " + std::to_string(length) + " runs past the end of " + limit;
      return s;
    }
    s.ok = true;
    s.content =
        buf.substr(static_cast<std::size_t>(pos + kRecordPrefix), static_cast<std::size_t>(length));
    return s;
  }

  void warn(const std::string& what) { result_.warnings.push_back(name_ + ": " + what); }

  static std::string hex(std::uint32_t v) {
    static const char* const digits = "0123456789abcdef";
    std::string s = "0x";
    for (int i = 7; i >= 0; --i) s += digits[(v >> (4 * i)) & 0xFU];
    return s;
  }

  void schema(std::string_view content, const Place& place, bool in_summary) {
    Fields f(content, place);
    Schema s;
    s.id = f.u16("id");
    s.name = std::string(f.prefixed32("name"));
    s.encoding = std::string(f.prefixed32("encoding"));
    const std::string_view data = f.prefixed32("data");
    s.data.assign(data.begin(), data.end());
    if (s.id == 0) return;  // invalid, ignored as the specification says
    auto it = result_.schemas.find(s.id);
    if (it == result_.schemas.end()) {
      if (in_summary) warn("schema " + std::to_string(s.id) + " is only in the summary");
      result_.schemas.emplace(s.id, std::move(s));
    } else if (it->second.name != s.name || it->second.encoding != s.encoding ||
               it->second.data != s.data) {
      warn(place.record + ": schema " + std::to_string(s.id) +
           " differs from its first definition, which is kept");
    }
  }

  void channel(std::string_view content, const Place& place, bool in_summary) {
    Fields f(content, place);
    Channel c;
    c.id = f.u16("id");
    c.schema_id = f.u16("schema_id");
    c.topic = std::string(f.prefixed32("topic"));
    c.message_encoding = std::string(f.prefixed32("message_encoding"));
    c.metadata = string_map(f.prefixed32("metadata"), place, "metadata");
    if (c.schema_id != 0 && result_.schemas.count(c.schema_id) == 0) {
      warn(place.record + ": channel " + std::to_string(c.id) + " refers to schema " +
           std::to_string(c.schema_id) + ", not defined before it");
    }
    auto it = result_.channels.find(c.id);
    if (it == result_.channels.end()) {
      if (in_summary) warn("channel " + std::to_string(c.id) + " is only in the summary");
      result_.channels.emplace(c.id, std::move(c));
    } else if (it->second.schema_id != c.schema_id || it->second.topic != c.topic ||
               it->second.message_encoding != c.message_encoding ||
               it->second.metadata != c.metadata) {
      warn(place.record + ": channel " + std::to_string(c.id) +
           " differs from its first definition, which is kept");
    }
  }

  // `chunk_offset`: of the Chunk record holding the message (0: none); `record_offset`: of the
  // Message record in the chunk's records, or in the file.
  void message(std::string_view content, const Place& place, std::uint64_t chunk_offset,
               std::uint64_t record_offset) {
    Fields f(content, place);
    Message m;
    m.channel_id = f.u16("channel_id");
    m.sequence = f.u32("sequence");
    m.log_time = f.u64("log_time");
    m.publish_time = f.u64("publish_time");
    if (result_.channels.count(m.channel_id) == 0) {
      place.fail("message on channel " + std::to_string(m.channel_id) +
                 ", which no Channel record before it defines");
    }
    const std::string_view data = f.rest();
    m.data.assign(data.begin(), data.end());
    m.chunk_offset = chunk_offset;
    m.record_offset = record_offset;
    result_.messages.push_back(std::move(m));
  }

  void metadata(std::string_view content, const Place& place) {
    Fields f(content, place);
    Metadata m;
    m.name = std::string(f.prefixed32("name"));
    m.metadata = string_map(f.prefixed32("metadata"), place, "metadata");
    result_.metadata.push_back(std::move(m));
  }

  void data_record(std::uint8_t opcode, std::string_view content, const Place& place,
                   std::uint64_t pos) {
    switch (opcode) {
      case kSchema: schema(content, place, false); break;
      case kChannel: channel(content, place, false); break;
      case kMessage: message(content, place, 0, pos); break;
      case kChunk: chunk(content, place, pos); break;
      case kMetadata: metadata(content, place); break;
      case kHeader: warn(place.record + ": a second Header, ignored"); break;
      case kFooter: place.fail("a Footer inside the data section");
      default: break;  // MessageIndex, Attachment, private or unknown records
    }
  }

  void chunk(std::string_view content, const Place& place, std::uint64_t pos) {
    Fields f(content, place);
    ChunkInfo info;
    info.offset = pos;
    info.length = kRecordPrefix + content.size();
    info.message_start_time = f.u64("message_start_time");
    info.message_end_time = f.u64("message_end_time");
    info.uncompressed_size = f.u64("uncompressed_size");
    const std::uint32_t crc = f.u32("uncompressed_crc");
    info.compression = std::string(f.prefixed32("compression"));
    const std::uint64_t records_length = f.u64("records length");
    if (records_length > content.size() - f.position()) {
      place.fail("records length " + std::to_string(records_length) +
                 " runs past the end of the record (" + std::to_string(content.size()) +
                 " bytes of content)");
    }
    const std::string_view stored = f.take(records_length, "records");
    info.compressed_size = stored.size();
    std::string decompressed;
    std::string_view records;
    if (info.compression.empty()) {
      if (stored.size() != info.uncompressed_size) {
        place.fail("uncompressed records of " + std::to_string(stored.size()) +
                   " bytes, uncompressed_size says " + std::to_string(info.uncompressed_size));
      }
      records = stored;
    } else if (info.compression == "zstd" || info.compression == "lz4") {
      decompressed = decompress(info.compression, stored, info.uncompressed_size, place);
      records = decompressed;
    } else {
      place.fail("unknown compression '" + info.compression + "' (this reader knows zstd, lz4)");
    }
    if (crc != 0) {
      const std::uint32_t actual = crc32(records);
      if (actual != crc) {
        place.fail("uncompressed_crc " + hex(crc) + " does not match the records' CRC32 " +
                   hex(actual));
      }
    }
    const std::size_t before = result_.messages.size();
    const std::string within = place.record;
    for (std::uint64_t p = 0; p < records.size();) {
      const Slice r = slice(p, records.size(), within, records);
      if (!r.ok) Place{&name_, r.problem_place}.fail(r.problem);
      Place inner{&name_, describe(r.opcode, p, within)};
      switch (r.opcode) {
        case kSchema: schema(r.content, inner, false); break;
        case kChannel: channel(r.content, inner, false); break;
        case kMessage: message(r.content, inner, pos, p); break;
        default: break;  // other records in a chunk are skipped
      }
      p += kRecordPrefix + r.content.size();
    }
    info.message_count = result_.messages.size() - before;
    result_.compression.insert(info.compression);
    result_.chunks.push_back(std::move(info));
  }

  void summary(std::uint64_t begin, std::uint64_t end) {
    std::size_t chunk_indexes = 0;
    for (std::uint64_t p = begin; p < end;) {
      const Slice r = slice(p, end, "");
      if (!r.ok) Place{&name_, r.problem_place}.fail(r.problem);
      Place place{&name_, describe(r.opcode, p)};
      switch (r.opcode) {
        case kSchema: schema(r.content, place, true); break;
        case kChannel: channel(r.content, place, true); break;
        case kChunkIndex: {
          // Checked to be well-formed; the reader reads the chunks themselves in order.
          Fields f(r.content, place);
          f.u64("message_start_time");
          f.u64("message_end_time");
          f.u64("chunk_start_offset");
          f.u64("chunk_length");
          f.prefixed32("message_index_offsets");
          f.u64("message_index_length");
          f.prefixed32("compression");
          f.u64("compressed_size");
          f.u64("uncompressed_size");
          ++chunk_indexes;
          break;
        }
        case kStatistics: {
          if (result_.statistics) place.fail("a second Statistics record");
          Fields f(r.content, place);
          Statistics s;
          s.message_count = f.u64("message_count");
          s.schema_count = f.u16("schema_count");
          s.channel_count = f.u32("channel_count");
          s.attachment_count = f.u32("attachment_count");
          s.metadata_count = f.u32("metadata_count");
          s.chunk_count = f.u32("chunk_count");
          s.message_start_time = f.u64("message_start_time");
          s.message_end_time = f.u64("message_end_time");
          Fields counts(f.prefixed32("channel_message_counts"), place);
          while (!counts.done()) {
            const std::uint16_t id = counts.u16("channel_message_counts");
            s.channel_message_counts[id] = counts.u64("channel_message_counts");
          }
          result_.statistics = std::move(s);
          break;
        }
        default: break;
      }
      p += kRecordPrefix + r.content.size();
    }
    result_.indexed = chunk_indexes == result_.chunks.size();
    if (chunk_indexes != result_.chunks.size()) {
      warn("the summary indexes " + std::to_string(chunk_indexes) +
           " chunks, the data section holds " + std::to_string(result_.chunks.size()));
    }
  }

  std::string_view file_;
  const std::string& name_;
  Recording result_;
};

}  // namespace

std::string location(const Message& message) {
  std::string text = "Message at byte " + std::to_string(message.record_offset);
  if (message.chunk_offset != 0) {
    text += " of the Chunk at byte " + std::to_string(message.chunk_offset);
  }
  return text;
}

Recording read(std::string_view bytes, const std::string& file_name) {
  return Parser(bytes, file_name).run();
}

Recording read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open: " + std::strerror(errno));
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(path + ": reading failed");
  return read(bytes, path);
}

}  // namespace ncqual::mcap
