// SPDX-License-Identifier: Apache-2.0
// The MCAP reader of ncqual/mcap/mcap.hpp: a whole file in memory, every record checked against
// the specification's layout and every non-zero CRC, chunks decompressed with libzstd or liblz4.
#include "ncqual/mcap/mcap.hpp"

#include "records.hpp"

#include <lz4frame.h>
#include <zstd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <new>
#include <utility>

namespace ncqual::mcap {

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

namespace {

// The largest uncompressed chunk the reader accepts (ncqual writes 1 MiB chunks): a corrupt
// uncompressed_size must not make it allocate without bound.
constexpr std::uint64_t kMaxUncompressedChunk = std::uint64_t{1} << 30;

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
