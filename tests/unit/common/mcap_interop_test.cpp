// SPDX-License-Identifier: Apache-2.0
// McapInterop.*: files written by ncqual_mcap, read by an independent implementation, Foxglove's
// @mcap/core (tests/interop/mcap/read.mjs under node): its indexed reader (footer, summary, chunk
// and message indexes) for complete files of every compression, its stream reader for the same
// files and for a recording cut after a chunk. Every schema, channel and message (bytes and
// times) must match what was written. Skipped, saying why, without node or the npm packages.
#include "cli_runner.hpp"
#include "harness.hpp"
#include "ncqual/mcap/mcap.hpp"
#include "ncqual/recording/recording.hpp"
#include "process.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace mcap = ncqual::mcap;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const fs::path kInterop = fs::path(NCQUAL_SOURCE_DIR) / "tests" / "interop" / "mcap";

// node's path in PATH, or "".
std::string find_node() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path != nullptr ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / "node";
    if (access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return "";
}

// Why the independent reader cannot run here, or "".
std::string missing_reader() {
  if (find_node().empty()) {
    return "node is not installed (deploy/install-deps.sh --test, or apt-get install nodejs npm), "
           "then: npm ci --prefix tests/interop/mcap";
  }
  if (!fs::exists(kInterop / "node_modules" / "@mcap" / "core")) {
    return "tests/interop/mcap/node_modules is missing: npm ci --prefix tests/interop/mcap "
           "(deploy/test.sh runs it)";
  }
  return "";
}

struct TempDir {
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "ncqual-mcap-interop-XXXXXX").string();
    path = mkdtemp(pattern.data());
  }
  ~TempDir() { fs::remove_all(path); }
  fs::path path;
};

std::string hex(const std::vector<std::uint8_t>& bytes) {
  static const char* const digits = "0123456789abcdef";
  std::string s;
  for (const std::uint8_t b : bytes) {
    s += digits[b >> 4];
    s += digits[b & 0xFU];
  }
  return s;
}

// `node read.mjs [--stream] file`, its JSON.
json independent_read(const fs::path& file, bool stream) {
  std::vector<std::string> argv = {find_node(), (kInterop / "read.mjs").string()};
  if (stream) argv.emplace_back("--stream");
  argv.push_back(file.string());
  const auto outcome = ncqual::testing::run(ncqual::testing::Launch(argv));
  EXPECT_EQ(outcome.exit_code, 0) << outcome.err;
  if (outcome.exit_code != 0) return json::object();
  return json::parse(outcome.out);
}

// What is written: the schemas and channels of a DDS recording and messages on all channels.
struct Written {
  std::vector<mcap::Schema> schemas;
  std::vector<mcap::Channel> channels;
  std::vector<mcap::Message> messages;
};

void add_definitions(mcap::Writer& writer, Written& w) {
  const mcap::Schema schemas[] = {
      {0, "ncqual::TouchPoint", "omgidl", {'s', 't', 'r', 'u', 'c', 't', ' ', 'T', '{', '}', ';'}},
      {0, "ncqual::Status", "omgidl", {'e', 'n', 'u', 'm'}},
  };
  for (auto s : schemas) {
    s.id = writer.add_schema(s.name, s.encoding, s.data);
    w.schemas.push_back(s);
  }
  const mcap::Channel channels[] = {
      {0, w.schemas[0].id, "rt/ncqual/touch", "cdr", {{"offered_qos_profiles", "reliable"}}},
      {0, w.schemas[1].id, "rt/ncqual/status", "cdr", {}},
      {0, 0, "rt/ncqual/raw", "cdr", {{"a", "1"}, {"b", "zwei"}}},
  };
  for (auto c : channels) {
    c.id = writer.add_channel(c.schema_id, c.topic, c.message_encoding, c.metadata);
    w.channels.push_back(c);
  }
}

void add_messages(mcap::Writer& writer, Written& w, int count, std::uint32_t first_sequence) {
  std::mt19937 random(first_sequence + 7);
  for (int i = 0; i < count; ++i) {
    mcap::Message m;
    m.channel_id = w.channels[random() % w.channels.size()].id;
    m.sequence = first_sequence + static_cast<std::uint32_t>(i);
    // Beyond 2^53: the times must survive as 64-bit integers, not doubles.
    m.log_time = 1'750'000'000'123'456'789ULL + m.sequence * 1'000'003ULL;
    m.publish_time = m.log_time - random() % 100'000;
    m.data.resize(random() % 200);
    for (auto& b : m.data) b = static_cast<std::uint8_t>(random());
    writer.write(m);
    w.messages.push_back(m);
  }
}

void expect_definitions(const json& r, const Written& w, const mcap::Options& options) {
  EXPECT_EQ(r.at("profile"), options.profile);
  EXPECT_EQ(r.at("library"), options.library);
  ASSERT_EQ(r.at("schemas").size(), w.schemas.size());
  std::map<int, json> schemas;
  for (const auto& s : r.at("schemas")) schemas[s.at("id").get<int>()] = s;
  for (const auto& s : w.schemas) {
    ASSERT_EQ(schemas.count(s.id), 1U) << "schema " << s.id;
    EXPECT_EQ(schemas[s.id].at("name"), s.name);
    EXPECT_EQ(schemas[s.id].at("encoding"), s.encoding);
    EXPECT_EQ(schemas[s.id].at("dataHex"), hex(s.data));
  }
  ASSERT_EQ(r.at("channels").size(), w.channels.size());
  std::map<int, json> channels;
  for (const auto& c : r.at("channels")) channels[c.at("id").get<int>()] = c;
  for (const auto& c : w.channels) {
    ASSERT_EQ(channels.count(c.id), 1U) << "channel " << c.id;
    const json& j = channels[c.id];
    EXPECT_EQ(j.at("topic"), c.topic);
    EXPECT_EQ(j.at("messageEncoding"), c.message_encoding);
    EXPECT_EQ(j.at("schemaId"), c.schema_id);
    const std::string schema_name = c.schema_id == 0 ? "" : w.schemas.at(c.schema_id - 1).name;
    EXPECT_EQ(j.at("schemaName"), schema_name);
    const auto metadata = j.at("metadata").get<std::map<std::string, std::string>>();
    EXPECT_EQ(metadata, c.metadata);
  }
}

// The messages `r` holds equal `expected`: in the same order (`in_order`, the stream reader's
// file order) or matched by sequence (the indexed reader yields them in log_time order).
void expect_messages(const json& r, const std::vector<mcap::Message>& expected, bool in_order) {
  ASSERT_EQ(r.at("messageCount").get<std::size_t>(), expected.size());
  std::map<std::uint32_t, json> by_sequence;
  const json& messages = r.at("messages");
  for (std::size_t i = 0; i < messages.size(); ++i) {
    const auto sequence = messages[i].at("sequence").get<std::uint32_t>();
    by_sequence[sequence] = messages[i];
    if (in_order && i < expected.size()) {
      EXPECT_EQ(sequence, expected[i].sequence) << "message " << i;
    }
  }
  ASSERT_EQ(by_sequence.size(), expected.size());
  for (const auto& m : expected) {
    ASSERT_EQ(by_sequence.count(m.sequence), 1U) << "sequence " << m.sequence;
    const json& j = by_sequence[m.sequence];
    EXPECT_EQ(j.at("channel"), m.channel_id) << "sequence " << m.sequence;
    EXPECT_EQ(j.at("logTime"), std::to_string(m.log_time)) << "sequence " << m.sequence;
    EXPECT_EQ(j.at("publishTime"), std::to_string(m.publish_time)) << "sequence " << m.sequence;
    EXPECT_EQ(j.at("dataHex"), hex(m.data)) << "sequence " << m.sequence;
  }
}

// A file ncqual read (`ours`) as the independent reader read it (`theirs`, indexed): the same
// schemas, channels, header profile and library, and messages (matched by sequence).
void expect_read_as_ours(const json& theirs, const mcap::Recording& ours) {
  Written w;
  for (const auto& [id, s] : ours.schemas) w.schemas.push_back(s);
  for (const auto& [id, c] : ours.channels) w.channels.push_back(c);
  mcap::Options options;
  options.profile = ours.header.profile;
  options.library = ours.header.library;
  expect_definitions(theirs, w, options);
  expect_messages(theirs, ours.messages, false);
}

class McapInterop : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    const std::string why = missing_reader();
    if (!why.empty()) GTEST_SKIP() << why;
  }
};

TEST_P(McapInterop, FoxgloveReadersReadEveryMessage) {
  TempDir dir;
  const fs::path file = dir.path / "interop.mcap";
  mcap::Options options{"ncqual", "ncqual interop test", GetParam(), 4096};
  Written w;
  {
    mcap::Writer writer(file.string(), options);
    add_definitions(writer, w);
    add_messages(writer, w, 400, 1);
    writer.close();
  }
  ASSERT_GT(mcap::read_file(file.string()).chunks.size(), 3U);

  const json indexed = independent_read(file, false);
  ASSERT_FALSE(indexed.empty());
  EXPECT_EQ(indexed.at("reader"), "indexed");
  expect_definitions(indexed, w, options);
  expect_messages(indexed, w.messages, false);

  const json stream = independent_read(file, true);
  ASSERT_FALSE(stream.empty());
  EXPECT_EQ(stream.at("complete"), true);
  expect_definitions(stream, w, options);
  expect_messages(stream, w.messages, true);
}

// A recorder killed after a chunk: the stream reader sees that chunk; ncqual's reader too, and
// what it read, written again (`ncqual recording recover`), is a complete indexed file.
TEST_P(McapInterop, ACutRecordingAndItsRecovery) {
  TempDir dir;
  const fs::path file = dir.path / "killed.mcap";
  mcap::Options options{"", "ncqual interop test", GetParam(), 1 << 20};
  Written w;
  mcap::Writer writer(file.string(), options);
  add_definitions(writer, w);
  add_messages(writer, w, 50, 1);
  writer.close_chunk();
  Written lost;
  lost.channels = w.channels;
  add_messages(writer, lost, 20, 1000);  // in memory, not yet in the file

  const json stream = independent_read(file, true);
  ASSERT_FALSE(stream.empty());
  EXPECT_EQ(stream.at("complete"), false);
  expect_messages(stream, w.messages, true);

  const mcap::Recording cut = mcap::read_file(file.string());
  EXPECT_FALSE(cut.indexed);
  ASSERT_EQ(cut.messages.size(), 50U);
  const fs::path recovered = dir.path / "recovered.mcap";
  {
    mcap::Writer again(recovered.string(), options);
    std::map<std::uint16_t, std::uint16_t> schema_ids;
    for (const auto& [id, s] : cut.schemas)
      schema_ids[id] = again.add_schema(s.name, s.encoding, s.data);
    for (const auto& [id, c] : cut.channels) {
      EXPECT_EQ(again.add_channel(c.schema_id == 0 ? 0 : schema_ids.at(c.schema_id), c.topic,
                                  c.message_encoding, c.metadata),
                id);
    }
    for (const auto& m : cut.messages) again.write(m);
    again.close();
  }
  const json indexed = independent_read(recovered, false);
  ASSERT_FALSE(indexed.empty());
  expect_definitions(indexed, w, options);
  expect_messages(indexed, w.messages, false);
  writer.close();
}

INSTANTIATE_TEST_SUITE_P(Compression, McapInterop, ::testing::Values("", "zstd", "lz4"),
                         [](const auto& info) {
                           return info.param.empty() ? std::string("none") : info.param;
                         });

}  // namespace

// The committed recordings (tests/data/recordings, made by ncqual record from a plant's traffic):
// Foxglove's indexed reader reads every schema, channel and message as ncqual's reader does.
TEST(McapInteropRecordings, FoxgloveReadsEveryCommittedRecording) {
  const std::string why = missing_reader();
  if (!why.empty()) GTEST_SKIP() << why;
  const fs::path dir = fs::path(NCQUAL_SOURCE_DIR) / "tests" / "data" / "recordings";
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".mcap") continue;
    ++files;
    const mcap::Recording ours = mcap::read_file(entry.path().string());
    ASSERT_TRUE(ours.indexed) << entry.path();
    const json theirs = independent_read(entry.path(), false);
    ASSERT_FALSE(theirs.empty()) << entry.path();
    expect_read_as_ours(theirs, ours);
  }
  EXPECT_GT(files, 0U) << "no recording in " << dir;
}

// A file the live recorder wrote: the committed drift recording's producer topics replayed by
// `ncqual replay --fast` into a private domain where `ncqual record` records them (its own
// readers, chunking, flushes and summary, lz4 as the plant's recorder may write). Foxglove reads
// every schema, channel and message as ncqual does, and the messages are the replayed ones, byte
// for byte: the committed recording's samples as the replay writes them, in the current wire
// contract's layout (it was recorded in contract 1; docs/architecture.md, "Changing the wire
// contract").
TEST(McapInteropRecordings, FoxgloveReadsWhatTheLiveRecorderWrote) {
  using namespace ncqual::testing;
  using ncqual::testing_cli::run_cli;
  const std::string why = missing_reader();
  if (!why.empty()) GTEST_SKIP() << why;
  const std::string source =
      (fs::path(NCQUAL_SOURCE_DIR) / "tests" / "data" / "recordings" / "drift-1-machine.mcap")
          .string();
  const std::string topics = "CheckRequest,MeasurementSet,CheckResult,Compensation,MachineStatus";
  const std::set<std::string> topic_names = {"ncqual/CheckRequest", "ncqual/MeasurementSet",
                                             "ncqual/CheckResult", "ncqual/Compensation",
                                             "ncqual/MachineStatus"};
  std::multiset<std::vector<std::uint8_t>> replayed;
  const mcap::Recording from = mcap::read_file(source);
  ncqual::recording::Filter filter;
  filter.topics = topic_names;
  const ncqual::recording::Selection selection = ncqual::recording::select(from, filter, source);
  ASSERT_TRUE(selection.skipped.empty()) << selection.skipped.front();
  for (const auto& s : selection.samples) replayed.insert(s.bytes());
  ASSERT_GT(replayed.size(), 100U);
  // Recorded in contract 1: every sample of the two topics that changed is written in contract 2.
  ASSERT_GT(selection.upgraded.count("ncqual/CheckResult"), 0U);

  Plant plant("mcap-interop-live", TestDomain::RecordingInterop);
  plant.write_plant("[]");
  const std::string out = (plant.dir() / "live.mcap").string();
  Process recorder(
      Launch({NCQUAL_CLI_EXE, "record", "--plant", plant.plant_file(), "--out", out, "--topics",
              topics, "--compression", "lz4", "--stop-after", std::to_string(replayed.size())})
          .log_to((plant.dir() / "record.log").string()));
  std::vector<std::string> replay = {"replay",   source, "--fast",    "--plant", plant.plant_file(),
                                     "--topics", topics, "--readers", "1"};
  if (!plant.test_identity().empty()) {
    replay.insert(replay.end(), {"--identity", plant.test_identity()});
  }
  const auto run = run_cli(replay);
  ASSERT_EQ(run.exit_code, 0) << run.out;
  ASSERT_TRUE(recorder.wait_for(std::chrono::seconds(60))) << plant.log("record");
  ASSERT_EQ(recorder.wait(), 0) << plant.log("record");

  const mcap::Recording ours = mcap::read_file(out);
  ASSERT_TRUE(ours.indexed);
  EXPECT_EQ(ours.compression, (std::set<std::string>{"lz4"}));
  std::multiset<std::vector<std::uint8_t>> recorded;
  for (const auto& m : ours.messages) recorded.insert(m.data);
  EXPECT_TRUE(recorded == replayed)
      << recorded.size() << " recorded, " << replayed.size() << " replayed";
  const json theirs = independent_read(out, false);
  ASSERT_FALSE(theirs.empty());
  expect_read_as_ours(theirs, ours);
}
