// SPDX-License-Identifier: Apache-2.0
// ncqual_mcap (mcap/): round trips through every compression, a whole file's layout worked
// out by hand from the specification (not from the writer), the CRC32 check value, and bad files:
// cut at every byte, wrong magic, corrupt chunks, lengths past the end, unknown channels.
#include "ncqual/mcap/mcap.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace mcap = ncqual::mcap;

namespace {

using Bytes = std::vector<std::uint8_t>;

// A temporary directory, removed with its files.
struct TempDir {
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "ncqual-mcap-XXXXXX").string();
    path = mkdtemp(pattern.data());
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::filesystem::path path;
};

// What a round trip writes: schemas, channels (one without schema, one with metadata) and
// messages of varied sizes and times (not in log_time order) on all of them.
struct Sample {
  std::vector<mcap::Message> messages;
};

std::string write_sample(const mcap::Options& options, Sample& sample, int message_count) {
  std::ostringstream out;
  mcap::Writer writer(out, options);
  const auto s1 = writer.add_schema("ncqual::Touch", "omgidl", Bytes{'s', 't', 'r', 'u', 'c', 't'});
  const auto s2 = writer.add_schema("ncqual::Empty", "", Bytes{});
  const std::vector<std::uint16_t> channels = {
      writer.add_channel(s1, "/ncqual/touch", "cdr", {{"qos", "reliable"}, {"offered", "1"}}),
      writer.add_channel(s2, "/ncqual/empty", "cdr"),
      writer.add_channel(0, "/ncqual/raw", "json"),
      writer.add_channel(s1, "/ncqual/touch2", "cdr"),
  };
  std::mt19937 random(42);
  for (int i = 0; i < message_count; ++i) {
    mcap::Message m;
    m.channel_id = channels[random() % channels.size()];
    m.sequence = static_cast<std::uint32_t>(i);
    m.log_time = 1'700'000'000'000'000'000ULL + static_cast<std::uint64_t>(i) * 1'000'000 +
                 random() % 5'000'000;  // overlapping: not sorted
    m.publish_time = m.log_time - random() % 1000;
    m.data.resize(random() % 300);
    for (auto& b : m.data) b = static_cast<std::uint8_t>(random());
    writer.write(m);
    sample.messages.push_back(m);
  }
  writer.close();
  return out.str();
}

void expect_messages_equal(const std::vector<mcap::Message>& expected,
                           const std::vector<mcap::Message>& actual, std::size_t count) {
  ASSERT_GE(expected.size(), count);
  ASSERT_EQ(actual.size(), count);
  for (std::size_t i = 0; i < count; ++i) {
    SCOPED_TRACE("message " + std::to_string(i));
    EXPECT_EQ(actual[i].channel_id, expected[i].channel_id);
    EXPECT_EQ(actual[i].sequence, expected[i].sequence);
    EXPECT_EQ(actual[i].log_time, expected[i].log_time);
    EXPECT_EQ(actual[i].publish_time, expected[i].publish_time);
    EXPECT_EQ(actual[i].data, expected[i].data);
  }
}

class McapRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(McapRoundTrip, EveryMessageSchemaAndChannelComesBack) {
  mcap::Options options;
  options.profile = "ncqual";
  options.library = "ncqual test";
  options.compression = GetParam();
  options.chunk_size = 4096;  // several chunks
  Sample sample;
  const std::string bytes = write_sample(options, sample, 600);
  const mcap::Recording r = mcap::read(bytes, "round.mcap");

  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  EXPECT_TRUE(r.indexed);
  EXPECT_EQ(r.header.profile, "ncqual");
  EXPECT_EQ(r.header.library, "ncqual test");
  EXPECT_EQ(r.compression, std::set<std::string>{GetParam()});
  EXPECT_GT(r.chunks.size(), 5U);
  ASSERT_EQ(r.schemas.size(), 2U);
  EXPECT_EQ(r.schemas.at(1).name, "ncqual::Touch");
  EXPECT_EQ(r.schemas.at(1).encoding, "omgidl");
  EXPECT_EQ(r.schemas.at(1).data, (Bytes{'s', 't', 'r', 'u', 'c', 't'}));
  EXPECT_EQ(r.schemas.at(2).name, "ncqual::Empty");
  EXPECT_TRUE(r.schemas.at(2).data.empty());
  ASSERT_EQ(r.channels.size(), 4U);
  EXPECT_EQ(r.channels.at(1).topic, "/ncqual/touch");
  EXPECT_EQ(r.channels.at(1).schema_id, 1);
  EXPECT_EQ(r.channels.at(1).message_encoding, "cdr");
  EXPECT_EQ(r.channels.at(1).metadata,
            (std::map<std::string, std::string>{{"qos", "reliable"}, {"offered", "1"}}));
  EXPECT_EQ(r.channels.at(3).schema_id, 0);
  EXPECT_EQ(r.channels.at(3).message_encoding, "json");
  EXPECT_EQ(r.channels.at(4).topic, "/ncqual/touch2");
  expect_messages_equal(sample.messages, r.messages, sample.messages.size());

  ASSERT_TRUE(r.statistics.has_value());
  EXPECT_EQ(r.statistics->message_count, 600U);
  EXPECT_EQ(r.statistics->schema_count, 2);
  EXPECT_EQ(r.statistics->channel_count, 4U);
  EXPECT_EQ(r.statistics->chunk_count, r.chunks.size());
  std::uint64_t first = UINT64_MAX;
  std::uint64_t last = 0;
  std::map<std::uint16_t, std::uint64_t> counts;
  for (const auto& m : sample.messages) {
    first = std::min(first, m.log_time);
    last = std::max(last, m.log_time);
    ++counts[m.channel_id];
  }
  EXPECT_EQ(r.statistics->message_start_time, first);
  EXPECT_EQ(r.statistics->message_end_time, last);
  EXPECT_EQ(r.statistics->channel_message_counts, counts);
  std::size_t in_chunks = 0;
  for (const auto& c : r.chunks) {
    in_chunks += c.message_count;
    EXPECT_EQ(c.compression, GetParam());
    if (!GetParam().empty()) {
      EXPECT_LT(c.compressed_size, c.uncompressed_size);
    }
  }
  EXPECT_EQ(in_chunks, 600U);
}

INSTANTIATE_TEST_SUITE_P(Compression, McapRoundTrip, ::testing::Values("", "zstd", "lz4"),
                         [](const auto& info) {
                           return info.param.empty() ? std::string("none") : info.param;
                         });

TEST(Mcap, Crc32CheckValue) {
  EXPECT_EQ(mcap::crc32("123456789"), 0xCBF43926U);
  EXPECT_EQ(mcap::crc32(""), 0U);
  EXPECT_EQ(mcap::crc32("6789", mcap::crc32("12345")), 0xCBF43926U);  // chained as zlib's
}

// The CRC (carry-less folding where the CPU has it, from 64 bytes on; zlib's for the rest)
// against the definition, bit by bit, at every length up to 300 bytes and 16 alignments (the
// folding's 64-byte steps, its 16-byte steps, the tails left to zlib and their joins), and
// against Python's zlib.crc32 of the same 1 MiB pattern (0x5dcba3c7; of its bytes 3..999:
// 0xe98c4b83).
std::uint32_t crc32_bitwise(std::string_view bytes) {
  std::uint32_t c = 0xFFFFFFFFU;
  for (const char ch : bytes) {
    c ^= static_cast<std::uint8_t>(ch);
    for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? (c >> 1) ^ 0xEDB88320U : c >> 1;
  }
  return ~c;
}

TEST(Mcap, Crc32IsTheBitwiseDefinitionAtEveryLengthAndAlignment) {
  std::string pattern(1 << 20, '\0');
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    pattern[i] = static_cast<char>((i * 131 + 7) % 251);
  }
  for (std::size_t from = 0; from < 16; ++from) {
    for (std::size_t n = 0; n <= 300; ++n) {
      const std::string_view part(pattern.data() + from, n);
      ASSERT_EQ(mcap::crc32(part), crc32_bitwise(part)) << "bytes " << from << ".." << from + n;
      ASSERT_EQ(mcap::crc32(part.substr(n / 3), mcap::crc32(part.substr(0, n / 3))),
                crc32_bitwise(part))
          << "chained at " << n / 3;
    }
  }
  EXPECT_EQ(mcap::crc32(pattern), 0x5dcba3c7U);
  EXPECT_EQ(mcap::crc32(std::string_view(pattern).substr(3, 997)), 0xe98c4b83U);
}

TEST(Mcap, Crc32CombinedIsTheCrcOfTheWhole) {
  std::string pattern(1 << 20, '\0');
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    pattern[i] = static_cast<char>((i * 7 + 3) % 253);
  }
  const std::string_view all(pattern);
  for (const std::size_t split : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{4096},
                                  pattern.size() - 1, pattern.size()}) {
    const std::string_view a = all.substr(0, split), b = all.substr(split);
    EXPECT_EQ(mcap::crc32_combine(mcap::crc32(a), mcap::crc32(b), b.size()), mcap::crc32(all))
        << "split at " << split;
  }
  // "12345" + "6789": the check value.
  EXPECT_EQ(mcap::crc32_combine(mcap::crc32("12345"), mcap::crc32("6789"), 4), 0xCBF43926U);
}

// ---- the layout, by hand --------------------------------------------------------------------

void le(Bytes& out, std::uint64_t v, int size) {
  for (int i = 0; i < size; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void raw(Bytes& out, std::initializer_list<int> bytes) {
  for (int b : bytes) out.push_back(static_cast<std::uint8_t>(b));
}
std::uint32_t crc_of(const Bytes& b, std::size_t from, std::size_t to) {
  return mcap::crc32(std::string_view(reinterpret_cast<const char*>(b.data()) + from, to - from));
}

// The records a tiny file's chunk holds, built from the specification's tables; every length
// counted by hand. Schema 1 "S"/"enc"/{AA}, channel 1 on it "/t"/"cdr" without metadata, and one
// message on it: sequence 7, log_time 0x0102030405060708, publish_time 9, data DE AD.
constexpr std::uint64_t kLogTime = 0x0102030405060708ULL;
Bytes tiny_records() {
  Bytes r;
  // Schema: opcode 0x03, length 19 = id 2 + name 4+1 + encoding 4+3 + data 4+1 (28 bytes).
  raw(r, {0x03,           19, 0, 0, 0,   0,   0,   0, 0,
          /*id*/ 1,       0,
          /*name*/ 1,     0,  0, 0, 'S',
          /*encoding*/ 3, 0,  0, 0, 'e', 'n', 'c',
          /*data*/ 1,     0,  0, 0, 0xAA});
  // Channel: opcode 0x04, length 21 = id 2 + schema_id 2 + topic 4+2 + encoding 4+3 + empty
  // metadata map 4 (30 bytes).
  raw(r, {0x04,
          21,
          0,
          0,
          0,
          0,
          0,
          0,
          0,
          /*id*/ 1,
          0,
          /*schema_id*/ 1,
          0,
          /*topic*/ 2,
          0,
          0,
          0,
          '/',
          't',
          /*message_encoding*/ 3,
          0,
          0,
          0,
          'c',
          'd',
          'r',
          /*metadata*/ 0,
          0,
          0,
          0});
  // Message at offset 58: opcode 0x05, length 24 = channel 2 + sequence 4 + log_time 8 +
  // publish_time 8 + data 2 (33 bytes).
  raw(r, {0x05,
          24,
          0,
          0,
          0,
          0,
          0,
          0,
          0,
          /*channel_id*/ 1,
          0,
          /*sequence*/ 7,
          0,
          0,
          0,
          /*log_time*/ 8,
          7,
          6,
          5,
          4,
          3,
          2,
          1,
          /*publish_time*/ 9,
          0,
          0,
          0,
          0,
          0,
          0,
          0,
          /*data*/ 0xDE,
          0xAD});
  return r;  // 91 bytes
}

// The whole file the writer must make of the above (compression "", profile "x", library "ncq").
Bytes tiny_file() {
  Bytes e;
  raw(e, {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'});  // magic, bytes 0-7
  // Header at 8: opcode 0x01, length 12 = profile 4+1 + library 4+3 (21 bytes, to 29).
  raw(e, {0x01, 12, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 'x', 3, 0, 0, 0, 'n', 'c', 'q'});
  // Chunk at 29: length 131 = start 8 + end 8 + uncompressed_size 8 + crc 4 + compression 4+0 +
  // records 8+91 (140 bytes, to 169).
  const Bytes records = tiny_records();
  raw(e, {0x06, 131, 0, 0, 0, 0, 0, 0, 0});
  le(e, kLogTime, 8);
  le(e, kLogTime, 8);
  le(e, 91, 8);
  le(e, mcap::crc32(std::string(records.begin(), records.end())), 4);
  le(e, 0, 4);
  le(e, 91, 8);
  e.insert(e.end(), records.begin(), records.end());
  // MessageIndex at 169: length 22 = channel 2 + array 4+16 (31 bytes, to 200).
  raw(e, {0x07, 22, 0, 0, 0, 0, 0, 0, 0, 1, 0, 16, 0, 0, 0});
  le(e, kLogTime, 8);
  le(e, 58, 8);
  // DataEnd at 200: length 4, the CRC32 of bytes 0-199 (13 bytes, to 213).
  raw(e, {0x0F, 4, 0, 0, 0, 0, 0, 0, 0});
  le(e, crc_of(e, 0, 200), 4);
  // Summary at 213. Schema copy (28 bytes, to 241), Channel copy (30, to 271).
  e.insert(e.end(), records.begin(), records.begin() + 58);
  // Statistics at 271: length 56 = message_count 8 + schema_count 2 + channel_count 4 +
  // attachments 4 + metadata 4 + chunks 4 + start 8 + end 8 + map 4+(2+8) (65 bytes, to 336).
  raw(e, {0x0B, 56, 0, 0, 0, 0, 0, 0, 0});
  le(e, 1, 8);
  le(e, 1, 2);
  le(e, 1, 4);
  le(e, 0, 4);
  le(e, 0, 4);
  le(e, 1, 4);
  le(e, kLogTime, 8);
  le(e, kLogTime, 8);
  raw(e, {10, 0, 0, 0, /*channel*/ 1, 0, /*count*/ 1, 0, 0, 0, 0, 0, 0, 0});
  // ChunkIndex at 336: length 74 = start 8 + end 8 + offset 8 + length 8 + map 4+(2+8) +
  // message_index_length 8 + compression 4+0 + compressed 8 + uncompressed 8 (83, to 419).
  raw(e, {0x08, 74, 0, 0, 0, 0, 0, 0, 0});
  le(e, kLogTime, 8);
  le(e, kLogTime, 8);
  le(e, 29, 8);   // chunk_start_offset
  le(e, 140, 8);  // chunk_length
  raw(e, {10, 0, 0, 0, /*channel*/ 1, 0});
  le(e, 169, 8);  // its MessageIndex
  le(e, 31, 8);   // message_index_length
  le(e, 0, 4);    // compression ""
  le(e, 91, 8);
  le(e, 91, 8);
  // Summary offsets at 419: one per group, length 17 = opcode 1 + start 8 + length 8 (26 each).
  const std::uint64_t groups[4][3] = {
      {0x03, 213, 28}, {0x04, 241, 30}, {0x0B, 271, 65}, {0x08, 336, 83}};
  for (const auto& g : groups) {
    raw(e, {0x0E, 17, 0, 0, 0, 0, 0, 0, 0, static_cast<int>(g[0])});
    le(e, g[1], 8);
    le(e, g[2], 8);
  }
  // Footer at 523: length 20; summary_start 213, summary_offset_start 419, then the CRC32 of
  // bytes 213 up to and including summary_offset_start (to 523 + 9 + 16 = 548).
  raw(e, {0x02, 20, 0, 0, 0, 0, 0, 0, 0});
  le(e, 213, 8);
  le(e, 419, 8);
  le(e, crc_of(e, 213, 548), 4);
  raw(e, {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'});  // 552-559
  return e;
}

TEST(Mcap, LayoutOfATinyFileMatchesTheSpecificationByHand) {
  std::ostringstream out;
  mcap::Options options;
  options.profile = "x";
  options.library = "ncq";
  {
    mcap::Writer writer(out, options);
    const auto schema = writer.add_schema("S", "enc", Bytes{0xAA});
    const auto channel = writer.add_channel(schema, "/t", "cdr");
    writer.write(mcap::Message{channel, 7, kLogTime, 9, Bytes{0xDE, 0xAD}});
    writer.close();
  }
  const std::string written = out.str();
  const Bytes actual(written.begin(), written.end());
  const Bytes expected = tiny_file();
  ASSERT_EQ(expected.size(), 560U);
  // The first bytes, spelled out: magic, Header opcode, length 12, "x", "ncq".
  const Bytes start = {0x89, 0x4D, 0x43, 0x41, 0x50, 0x30, 0x0D, 0x0A, 0x01, 0x0C,
                       0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00,
                       0x00, 0x78, 0x03, 0x00, 0x00, 0x00, 0x6E, 0x63, 0x71, 0x06};
  ASSERT_GE(actual.size(), start.size());
  EXPECT_EQ(Bytes(actual.begin(), actual.begin() + 30), start);
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    ASSERT_EQ(static_cast<int>(actual[i]), static_cast<int>(expected[i])) << "byte " << i;
  }
}

TEST(Mcap, ReadsTheHandBuiltFile) {
  const Bytes e = tiny_file();
  const mcap::Recording r = mcap::read(std::string(e.begin(), e.end()), "tiny.mcap");
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_TRUE(r.indexed);
  EXPECT_EQ(r.header.profile, "x");
  EXPECT_EQ(r.header.library, "ncq");
  ASSERT_EQ(r.messages.size(), 1U);
  EXPECT_EQ(r.messages[0].log_time, kLogTime);
  EXPECT_EQ(r.messages[0].publish_time, 9U);
  EXPECT_EQ(r.messages[0].sequence, 7U);
  EXPECT_EQ(r.messages[0].data, (Bytes{0xDE, 0xAD}));
  ASSERT_EQ(r.chunks.size(), 1U);
  EXPECT_EQ(r.chunks[0].offset, 29U);
  EXPECT_EQ(r.chunks[0].length, 140U);
}

// Magic, Header, then `records` outside any chunk, then DataEnd (no CRC), a Footer without a
// summary, and the magic.
std::string unchunked(const Bytes& records) {
  Bytes e;
  raw(e, {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'});
  raw(e, {0x01, 8, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});  // empty profile and library
  e.insert(e.end(), records.begin(), records.end());
  raw(e, {0x0F, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  raw(e, {0x02, 20, 0, 0, 0, 0, 0, 0, 0});
  le(e, 0, 20);
  raw(e, {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'});
  return {e.begin(), e.end()};
}

TEST(Mcap, ReadsRecordsOutsideChunksAndSkipsUnknownOpcodes) {
  Bytes records = tiny_records();
  // A private record (0x80) and a reserved, undefined one (0x70) before the message.
  records.insert(records.begin() + 58,
                 {0x80, 2, 0, 0, 0, 0, 0, 0, 0, 'h', 'i', 0x70, 0, 0, 0, 0, 0, 0, 0, 0});
  const mcap::Recording r = mcap::read(unchunked(records), "flat.mcap");
  ASSERT_EQ(r.messages.size(), 1U);
  EXPECT_EQ(r.messages[0].data, (Bytes{0xDE, 0xAD}));
  EXPECT_EQ(r.channels.at(1).topic, "/t");
  EXPECT_FALSE(r.indexed);
  EXPECT_TRUE(r.chunks.empty());
}

// ---- bad files ------------------------------------------------------------------------------

// The message of the mcap::Error that reading `bytes` throws ("" when it does not throw).
std::string read_error(const std::string& bytes, const std::string& name = "bad.mcap") {
  try {
    mcap::read(bytes, name);
  } catch (const mcap::Error& e) {
    return e.what();
  }
  return "";
}

TEST(Mcap, AMessageOnAnUnknownChannelIsAnError) {
  Bytes records = tiny_records();
  records.erase(records.begin(), records.begin() + 58);  // the message alone: channel 1 unknown
  EXPECT_EQ(read_error(unchunked(records), "lost.mcap"),
            "lost.mcap: Message at byte 25: message on channel 1, which no Channel record before "
            "it defines");
}

TEST(Mcap, WrongMagicIsAnErrorNamingTheMagic) {
  Bytes e = tiny_file();
  e[1] = 'N';
  EXPECT_EQ(read_error(std::string(e.begin(), e.end()), "run.mcap"),
            "run.mcap: Magic at byte 0: not an MCAP file (its first 8 bytes are not the MCAP "
            "magic \\x89MCAP0\\r\\n)");
  EXPECT_NE(read_error(""), "");
  EXPECT_NE(read_error("PK\x03\x04 a zip file"), "");
}

class McapCorruption : public ::testing::TestWithParam<std::string> {
 protected:
  std::string write() {
    mcap::Options options;
    options.compression = GetParam();
    options.chunk_size = 2048;
    return write_sample(options, sample_, 60);
  }
  Sample sample_;
};

TEST_P(McapCorruption, AFlippedByteInsideAChunkIsAnErrorNamingTheChunk) {
  std::string bytes = write();
  const mcap::Recording good = mcap::read(bytes, "run.mcap");
  ASSERT_GE(good.chunks.size(), 2U);
  const mcap::ChunkInfo& chunk = good.chunks[1];
  // The last byte of the records: message data (uncompressed) or the compressed stream.
  bytes[chunk.offset + chunk.length - 1] ^= 0x10;
  const std::string error = read_error(bytes, "run.mcap");
  EXPECT_EQ(error.rfind("run.mcap: Chunk at byte " + std::to_string(chunk.offset) + ": ", 0), 0U)
      << error;
  if (GetParam().empty()) {
    EXPECT_NE(error.find("uncompressed_crc"), std::string::npos) << error;
  }
}

TEST_P(McapCorruption, AChunkLengthPastTheEndIsAnError) {
  std::string bytes = write();
  const mcap::Recording good = mcap::read(bytes, "run.mcap");
  const std::uint64_t at = good.chunks[0].offset;
  bytes[at + 4] = '\x01';  // length + 2^24
  EXPECT_EQ(read_error(bytes, "run.mcap"),
            "run.mcap: Chunk at byte " + std::to_string(at) + ": length " +
                std::to_string(good.chunks[0].length - 9 + (1ULL << 24)) +
                " runs past the end of the file (" + std::to_string(bytes.size()) + " bytes)");
  bytes[at + 8] = '\x7F';  // a huge length: no overflow
  EXPECT_NE(read_error(bytes, "run.mcap").find("Chunk at byte " + std::to_string(at) + ": length"),
            std::string::npos);
}

TEST_P(McapCorruption, RecordsLengthPastTheChunkIsAnError) {
  std::string bytes = write();
  const mcap::Recording good = mcap::read(bytes, "run.mcap");
  // records length: after opcode+length 9, times 16, uncompressed_size 8, crc 4, compression.
  const std::uint64_t chunk = good.chunks[0].offset;
  const std::uint64_t at = chunk + 9 + 28 + 4 + GetParam().size();
  bytes[at + 3] = '\x01';
  const std::string error = read_error(bytes, "run.mcap");
  EXPECT_EQ(
      error.rfind("run.mcap: Chunk at byte " + std::to_string(chunk) + ": records length ", 0), 0U)
      << error;
  EXPECT_NE(error.find("runs past the end of the record"), std::string::npos) << error;
}

TEST_P(McapCorruption, AFlippedByteInTheSummaryIsASummaryCrcError) {
  std::string bytes = write();
  bytes[bytes.size() - 8 - 29 - 30] ^= 0x01;  // in the summary offsets
  EXPECT_NE(read_error(bytes, "run.mcap").find("Footer at byte"), std::string::npos);
  EXPECT_NE(read_error(bytes, "run.mcap").find("summary_crc"), std::string::npos);
}

TEST_P(McapCorruption, AFlippedByteInAMessageIndexIsADataSectionCrcError) {
  std::string bytes = write();
  const mcap::Recording good = mcap::read(bytes, "run.mcap");
  const auto& c = good.chunks[0];
  bytes[c.offset + c.length + 9] ^= 0x01;  // the first MessageIndex's channel id
  const std::string error = read_error(bytes, "run.mcap");
  EXPECT_NE(error.find("DataEnd at byte"), std::string::npos) << error;
  EXPECT_NE(error.find("data_section_crc"), std::string::npos) << error;
}

// Every prefix of a file: an error naming the Magic or Header when the cut is inside them;
// otherwise the messages of every complete chunk, not one more, and a warning; never a crash.
TEST_P(McapCorruption, AFileCutAtEveryByteGivesItsCompleteChunksOrAnError) {
  const std::string bytes = write();
  const mcap::Recording good = mcap::read(bytes, "run.mcap");
  ASSERT_GE(good.chunks.size(), 3U);
  for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
    SCOPED_TRACE("cut at " + std::to_string(cut));
    const std::string prefix = bytes.substr(0, cut);
    try {
      const mcap::Recording r = mcap::read(prefix, "cut.mcap");
      std::size_t expected = 0;
      for (const auto& c : good.chunks) {
        if (c.offset + c.length <= cut) expected += c.message_count;
      }
      EXPECT_FALSE(r.indexed);
      ASSERT_FALSE(r.warnings.empty());
      EXPECT_NE(r.warnings.back().find("cut.mcap: the summary and footer are missing"),
                std::string::npos);
      expect_messages_equal(sample_.messages, r.messages, expected);
    } catch (const mcap::Error& e) {
      const std::string what = e.what();
      EXPECT_TRUE(what.rfind("cut.mcap: Magic at byte 0: ", 0) == 0 ||
                  what.rfind("cut.mcap: Header at byte 8: ", 0) == 0)
          << what;
      EXPECT_LT(cut, good.chunks[0].offset) << what;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Compression, McapCorruption, ::testing::Values("", "zstd", "lz4"),
                         [](const auto& info) {
                           return info.param.empty() ? std::string("none") : info.param;
                         });

// A chunk whose compression this reader does not know ("Qstd"): an error, not a guess.
TEST(Mcap, UnknownCompressionIsAnError) {
  Sample sample;
  std::string bytes = write_sample(mcap::Options{"", "", "zstd", 2048}, sample, 10);
  const std::uint64_t chunk = mcap::read(bytes, "run.mcap").chunks.at(0).offset;
  ASSERT_EQ(bytes.substr(chunk + 9 + 28 + 4, 4), "zstd");  // after the fields and the length 4
  bytes[chunk + 9 + 28 + 4] = 'Q';
  EXPECT_EQ(read_error(bytes, "run.mcap"), "run.mcap: Chunk at byte " + std::to_string(chunk) +
                                               ": unknown compression 'Qstd' (this reader knows "
                                               "zstd, lz4)");
}

// ---- the writer ----------------------------------------------------------------------------

TEST(McapWriter, AClosedChunkIsOnDiskAndReadableBeforeClose) {
  TempDir dir;
  const auto path = dir.path / "live.mcap";
  mcap::Writer writer(path.string(), mcap::Options{"", "ncqual", "zstd", 1 << 20});
  const auto channel = writer.add_channel(0, "/a", "cdr");
  for (std::uint32_t i = 0; i < 10; ++i) writer.write({channel, i, i, i, Bytes(10, 1)});
  writer.close_chunk();
  writer.write({channel, 10, 10, 10, Bytes(10, 2)});  // still in memory
  // What a reader sees if the process is killed now: the first chunk, no summary.
  const mcap::Recording r = mcap::read_file(path.string());
  EXPECT_EQ(r.messages.size(), 10U);
  EXPECT_FALSE(r.indexed);
  ASSERT_EQ(r.warnings.size(), 1U);
  EXPECT_NE(r.warnings[0].find("summary and footer are missing"), std::string::npos);
  writer.close();
  const mcap::Recording all = mcap::read_file(path.string());
  EXPECT_EQ(all.messages.size(), 11U);
  EXPECT_TRUE(all.indexed);
  EXPECT_EQ(all.chunks.size(), 2U);
}

TEST(McapWriter, TheDestructorClosesTheFile) {
  TempDir dir;
  const auto path = dir.path / "scoped.mcap";
  {
    mcap::Writer writer(path.string(), mcap::Options{"", "", "lz4", 100});
    const auto channel = writer.add_channel(0, "/a", "cdr");
    for (std::uint32_t i = 0; i < 20; ++i) writer.write({channel, i, i, i, Bytes(30, 3)});
  }
  const mcap::Recording r = mcap::read_file(path.string());
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(r.messages.size(), 20U);
  EXPECT_GE(r.chunks.size(), 5U);
}

TEST(McapWriter, AnEmptyRecordingIsValid) {
  std::ostringstream out;
  mcap::Writer writer(out);
  writer.add_channel(0, "/quiet", "cdr");  // a channel without messages is still written
  writer.close();
  writer.close();  // idempotent
  const mcap::Recording r = mcap::read(out.str(), "empty.mcap");
  EXPECT_TRUE(r.messages.empty());
  EXPECT_EQ(r.channels.at(1).topic, "/quiet");
  ASSERT_TRUE(r.statistics.has_value());
  EXPECT_EQ(r.statistics->message_count, 0U);
  EXPECT_EQ(r.statistics->message_start_time, 0U);
}

TEST(McapWriter, RefusesWhatItCannotWrite) {
  std::ostringstream out;
  EXPECT_THROW(mcap::Writer(out, mcap::Options{"", "", "brotli", 1024}), mcap::Error);
  mcap::Writer writer(out);
  EXPECT_THROW(writer.add_channel(3, "/a", "cdr"), mcap::Error);  // no schema 3
  EXPECT_THROW(writer.write({9, 0, 0, 0, {}}), mcap::Error);      // no channel 9
  writer.close();
  EXPECT_THROW(writer.write({1, 0, 0, 0, {}}), mcap::Error);
  EXPECT_THROW(mcap::Writer("/nonexistent-dir/x.mcap"), mcap::Error);
  EXPECT_THROW(mcap::read_file("/nonexistent-dir/x.mcap"), mcap::Error);
}

}  // namespace
