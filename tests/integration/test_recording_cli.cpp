// SPDX-License-Identifier: Apache-2.0
// `ncqual recording info` and `recording recover` on damaged copies of a committed recording
// (tests/data/recordings/drift-1-machine.mcap): each is refused, or read as far as it can be,
// with a message that names the file, the record and its byte offset; none crashes the command.
// The MCAP library's own tests damage files at every byte (tests/unit/common/mcap_test.cpp); this
// is what a person at the command line sees of the same damage.
#include "cli_runner.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace ncqual {
namespace {

namespace fs = std::filesystem;

using testing_cli::Capture;
using testing_cli::run_cli;
using testing_cli::TempDir;

const std::string kRecording = NCQUAL_SOURCE_DIR "/tests/data/recordings/drift-1-machine.mcap";

std::vector<char> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& path, const std::vector<char>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::uint64_t u64_at(const std::vector<char>& b, std::size_t at) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b.at(at + i));
  return v;
}

// The byte offset of the first record with `opcode` in the data section, walking the records'
// framing (opcode u8, length u64 little-endian) from the end of the 8-byte magic, as the
// specification lays them out (mcap.dev, "Records").
std::size_t first_record(const std::vector<char>& b, unsigned char opcode) {
  std::size_t at = 8;
  while (at + 9 <= b.size()) {
    if (static_cast<unsigned char>(b[at]) == opcode) return at;
    at += 9 + u64_at(b, at + 1);
  }
  throw std::runtime_error("no record with that opcode");
}

class RecordingCli : public ::testing::Test {
 protected:
  RecordingCli() : dir_("ncqual-recording-cli"), original_(read_bytes(kRecording)) {}

  // `recording info` of `bytes` written as `name`: it ends by itself, 0 or 1.
  testing_cli::CliRun info(const std::string& name, const std::vector<char>& bytes) {
    const fs::path file = dir_.path() / name;
    write_bytes(file, bytes);
    auto r = run_cli({"recording", "info", file.string()}, Capture::Separate);
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1)
        << name << ": exit " << r.exit_code << " (a crash?)\n"
        << r.err;
    return r;
  }

  TempDir dir_;
  std::vector<char> original_;
};

TEST_F(RecordingCli, TheCommittedFileIsWholeAndIndexed) {
  const auto r = info("whole.mcap", original_);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_NE(r.out.find("ncqual/CheckResult"), std::string::npos) << r.out;
}

TEST_F(RecordingCli, AFileThatIsNotMcapIsRefusedAtByteZero) {
  std::vector<char> magic = original_;
  magic[1] = 'X';  // \x89XCAP0\r\n
  for (const auto& [name, bytes] : std::vector<std::pair<std::string, std::vector<char>>>{
           {"magic.mcap", magic},
           {"text.mcap", {'h', 'e', 'l', 'l', 'o', '\n'}},
           {"empty.mcap", {}}}) {
    const auto r = info(name, bytes);
    EXPECT_EQ(r.exit_code, 1) << name;
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("Magic at byte 0"), std::string::npos) << r.err;
    const bool empty = bytes.empty();
    EXPECT_NE(r.err.find(empty ? "shorter than the magic" : "not an MCAP file"), std::string::npos)
        << r.err;
  }
}

TEST_F(RecordingCli, AChunkWhoseLengthRunsPastTheEndIsRefusedNamingIt) {
  const std::size_t chunk = first_record(original_, 0x06);
  std::vector<char> bytes = original_;
  for (int i = 0; i < 8; ++i) bytes[chunk + 1 + i] = i < 6 ? '\xff' : '\0';  // 2^48 - 1 bytes
  const auto r = info("long-chunk.mcap", bytes);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("long-chunk.mcap"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("at byte " + std::to_string(chunk)), std::string::npos) << r.err;
}

TEST_F(RecordingCli, AChunkWhoseCrcDoesNotMatchIsRefusedNamingIt) {
  // Chunk: message_start_time u64, message_end_time u64, uncompressed_size u64,
  // uncompressed_crc u32, ... (after the opcode and the record's length).
  const std::size_t chunk = first_record(original_, 0x06);
  std::vector<char> bytes = original_;
  bytes[chunk + 9 + 24] = static_cast<char>(bytes[chunk + 9 + 24] ^ 0x01);
  const auto r = info("crc.mcap", bytes);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("Chunk at byte " + std::to_string(chunk)), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("CRC"), std::string::npos) << r.err;
}

TEST_F(RecordingCli, ACutFileIsReadToItsLastCompleteChunkAndRecovered) {
  std::vector<char> cut(original_.begin(),
                        original_.begin() + static_cast<std::ptrdiff_t>(original_.size() / 2));
  const auto r = info("cut.mcap", cut);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("cut.mcap"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("without the closing magic"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("complete chunks"), std::string::npos) << r.err;

  const fs::path recovered = dir_.path() / "recovered.mcap";
  const auto recover =
      run_cli({"recording", "recover", (dir_.path() / "cut.mcap").string(), recovered.string()});
  ASSERT_EQ(recover.exit_code, 0) << recover.out;
  const auto again = run_cli({"recording", "info", recovered.string()}, Capture::Separate);
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.err, "") << "the recovered file is whole";
  EXPECT_NE(again.out.find("indexed"), std::string::npos) << again.out;
}

}  // namespace
}  // namespace ncqual
