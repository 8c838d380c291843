// SPDX-License-Identifier: Apache-2.0
// The recording library (recording/include/ncqual/recording/recording.hpp), without DDS:
// samples are the generated types' CDR bytes (ncqual/dds/serialized.hpp), files are written with
// RecordingWriter (or, for another system's recordings, straight with mcap::Writer) and read back
// with mcap::read_file. Times, offsets and file splits are worked out by hand.
#include "ncqual/recording/recording.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/dds/convert.hpp"
#include "ncqual/dds/serialized.hpp"
#include "ncqual/dds/topics.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual::recording {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

constexpr std::int64_t kSecond = 1'000'000'000;

// A temporary directory, removed with its files.
struct TempDir {
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "ncqual-recording-XXXXXX").string();
    const char* made = mkdtemp(pattern.data());
    if (made != nullptr) path = made;
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string file(const std::string& name) const { return (path / name).string(); }
  fs::path path;
};

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

const dds::TopicInfo& topic(const std::string& name) {
  const dds::TopicInfo* t = dds::find_topic(name);
  if (t == nullptr) throw std::logic_error("no topic " + name);
  return *t;
}

const std::string kResult = "ncqual/CheckResult";
const std::string kStatus = "ncqual/MachineStatus";

// A CheckResult of `machine` as on the wire; `reason` pads it as wanted.
Bytes result_bytes(const std::string& machine, const std::string& request,
                   const std::string& reason = "") {
  CheckResult r;
  r.machine_id = machine;
  r.request_id = request;
  r.kind = CheckKind::MonumentPositioning;
  r.verdict = Verdict::Fail;
  r.reason = reason;
  Metric m;
  m.name = "x_dev_mm";
  m.value = 0.002;
  m.unit = "mm";
  m.lower = -0.01;
  m.upper = 0.01;
  m.pass = true;
  r.metrics.push_back(m);
  r.time_ns = 1'700'000'000 * kSecond;
  Bytes bytes = dds::serialize<dds::CheckResultTopic>(dds::to_wire(r));
  if (bytes.empty()) throw std::logic_error("CheckResult did not serialize");
  return bytes;
}

Bytes status_bytes(const std::string& machine, const std::string& detail = "") {
  MachineStatus s;
  s.machine_id = machine;
  s.state = MachineState::Qualified;
  s.detail = detail;
  s.time_ns = 1'700'000'000 * kSecond;
  Bytes bytes = dds::serialize<dds::MachineStatusTopic>(dds::to_wire(s));
  if (bytes.empty()) throw std::logic_error("MachineStatus did not serialize");
  return bytes;
}

Bytes idl_bytes() {
  const std::string_view idl = idl_text();
  return Bytes(idl.begin(), idl.end());
}

FileOptions file_options() {
  FileOptions o;
  o.library = "ncqual 9.9.9 (git unit-test)";
  o.metadata = {{"recorder", "unit test"}, {"plant", "p1"}, {"domain", "42"}};
  return o;
}

// One message as written, to compare with what is read back.
struct Written {
  std::string topic;
  std::int64_t log_ns = 0;
  std::int64_t publish_ns = 0;
  Bytes bytes;
};

void put(RecordingWriter& writer, std::vector<Written>& written, const Written& w) {
  writer.write(w.topic, w.log_ns, w.publish_ns, w.bytes);
  written.push_back(w);
}

const mcap::Channel* channel_named(const mcap::Recording& r, const std::string& topic_name) {
  for (const auto& [id, c] : r.channels) {
    if (c.topic == topic_name) return &c;
  }
  return nullptr;
}

// `messages` of `r` are `expected`, in order: topic, times and bytes.
void expect_messages(const mcap::Recording& r, const std::vector<mcap::Message>& messages,
                     const std::vector<Written>& expected) {
  ASSERT_EQ(messages.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    SCOPED_TRACE("message " + std::to_string(i));
    const auto channel = r.channels.find(messages[i].channel_id);
    ASSERT_NE(channel, r.channels.end());
    EXPECT_EQ(channel->second.topic, expected[i].topic);
    EXPECT_EQ(messages[i].log_time, static_cast<std::uint64_t>(expected[i].log_ns));
    EXPECT_EQ(messages[i].publish_time, static_cast<std::uint64_t>(expected[i].publish_ns));
    EXPECT_EQ(messages[i].data, expected[i].bytes);
  }
}

std::string what_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

// ---- parse_duration_ns, schedule, topics_named, metadata -------------------------------------

TEST(ParseDuration, UnitsAndPlainSeconds) {
  EXPECT_EQ(parse_duration_ns("90s"), 90 * kSecond);
  EXPECT_EQ(parse_duration_ns("15m"), std::int64_t{15} * 60 * kSecond);
  EXPECT_EQ(parse_duration_ns("1h"), 3600 * kSecond);
  EXPECT_EQ(parse_duration_ns("1d"), 86400 * kSecond);
  EXPECT_EQ(parse_duration_ns("30"), 30 * kSecond);
  EXPECT_EQ(parse_duration_ns("1s"), kSecond);
  // The largest number of days that fits in int64 ns: 9223372036854775807 / 86400e9 = 106751.99.
  EXPECT_EQ(parse_duration_ns("106751d"), std::int64_t{106751} * 86400 * kSecond);
}

TEST(ParseDuration, Refusals) {
  for (const char* text :
       {"", "0", "0s", "-1s", "-5", "1x", "h", "s", "m", "d", "1 h", " 1h", "1h ", "1hh",
        "999999999999d", "106752d", "9223372036854775807s", "99999999999999999999"}) {
    SCOPED_TRACE(std::string("'") + text + "'");
    EXPECT_FALSE(parse_duration_ns(text).has_value()) << *parse_duration_ns(text);
  }
}

std::vector<Sample> samples_at(const std::vector<std::int64_t>& log_times) {
  std::vector<Sample> out;
  for (const auto t : log_times) {
    Sample s;
    s.log_time_ns = t;
    out.push_back(s);
  }
  return out;
}

TEST(Schedule, RecordedPaceDividedByTheRate) {
  const auto samples = samples_at({1000, 1500, 3000, 3000, 7000});
  EXPECT_EQ(schedule(samples, 1), (std::vector<std::int64_t>{0, 500, 2000, 2000, 6000}));
  EXPECT_EQ(schedule(samples, 2), (std::vector<std::int64_t>{0, 250, 1000, 1000, 3000}));
  EXPECT_EQ(schedule(samples, 0.5), (std::vector<std::int64_t>{0, 1000, 4000, 4000, 12000}));
  // 500 / 3 = 166.67, 2000 / 3 = 666.67, 6000 / 3 = 2000: rounded to the nearest ns.
  EXPECT_EQ(schedule(samples, 3), (std::vector<std::int64_t>{0, 167, 667, 667, 2000}));
}

TEST(Schedule, RateZeroOrLessIsAsFastAsPossible) {
  const auto samples = samples_at({1000, 1500, 3000});
  EXPECT_EQ(schedule(samples, 0), (std::vector<std::int64_t>{0, 0, 0}));
  EXPECT_EQ(schedule(samples, -1), (std::vector<std::int64_t>{0, 0, 0}));
  EXPECT_EQ(schedule(samples, std::numeric_limits<double>::quiet_NaN()),
            (std::vector<std::int64_t>{0, 0, 0}));
  EXPECT_TRUE(schedule({}, 1).empty());
  EXPECT_EQ(schedule(samples_at({5}), 1), (std::vector<std::int64_t>{0}));
}

TEST(TopicsNamed, ShortFullAndAnyCase) {
  const dds::TopicInfo* result = &topic(kResult);
  const dds::TopicInfo* status = &topic(kStatus);
  using List = std::vector<const dds::TopicInfo*>;
  EXPECT_EQ(topics_named({"CheckResult"}), List{result});
  EXPECT_EQ(topics_named({"ncqual/CheckResult"}), List{result});
  EXPECT_EQ(topics_named({"checkresult"}), List{result});
  EXPECT_EQ(topics_named({"NCQUAL/CHECKRESULT"}), List{result});
  EXPECT_EQ(topics_named({"CheckResult,MachineStatus"}), (List{result, status}));
  EXPECT_EQ(topics_named({"MachineStatus", "CheckResult"}), (List{status, result}));
  EXPECT_EQ(topics_named({}), List{});
}

TEST(TopicsNamed, DuplicatesOnce) {
  const dds::TopicInfo* result = &topic(kResult);
  const dds::TopicInfo* status = &topic(kStatus);
  using List = std::vector<const dds::TopicInfo*>;
  EXPECT_EQ(topics_named({"CheckResult", "ncqual/checkresult,CheckResult", "CHECKRESULT"}),
            List{result});
  EXPECT_EQ(topics_named({"CheckResult,MachineStatus,checkresult", "machinestatus"}),
            (List{result, status}));
  EXPECT_EQ(topics_named({"CheckResult,,", ","}), List{result});
}

TEST(TopicsNamed, UnknownNameThrowsNamingItAndTheKnownOnes) {
  try {
    topics_named({"CheckResult,Bogus"});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("Bogus"), std::string::npos) << what;
    for (const auto& t : dds::ncqual_topics()) {
      const std::string short_name = t.name.substr(t.name.find('/') + 1);
      EXPECT_NE(what.find(short_name), std::string::npos) << short_name << " in: " << what;
    }
  }
  EXPECT_THROW(topics_named({"ncqual/"}), std::invalid_argument);
  EXPECT_THROW(topics_named({"/tf"}), std::invalid_argument);
}

TEST(Metadata, ChannelMetadataOfAKeyedTopic) {
  const auto m = channel_metadata(topic(kResult));
  EXPECT_EQ(m.at("type"), "ncqual::msg::v2::CheckResult");
  EXPECT_EQ(m.at("keyed"), "true");
  EXPECT_EQ(m.at("key"), "machine_id");
  EXPECT_EQ(m.at("writer_profile"), topic(kResult).writer_profile);
  EXPECT_EQ(m.at("reader_profile"), topic(kResult).reader_profile);
}

TEST(Metadata, RecordingMetadataSaysWhoWhereAndWhen) {
  const std::int64_t started = 1'700'000'000 * kSecond;
  const auto m = recording_metadata("ncqual record", 7, "plant-a", started);
  char buffer[32];
  EXPECT_EQ(m.at("recorder"), "ncqual record");
  EXPECT_EQ(m.at("domain"), "7");
  EXPECT_EQ(m.at("plant"), "plant-a");
  EXPECT_EQ(m.at("started"), std::string(format_iso8601(started, buffer)));
  EXPECT_NE(m.at("version"), "");
  EXPECT_NE(m.at("host"), "");
}

TEST(IdlText, IsTheWholeIdlWithoutIncludes) {
  const std::string idl(idl_text());
  EXPECT_NE(idl.find("module ncqual"), std::string::npos);
  EXPECT_NE(idl.find("struct CheckResult"), std::string::npos);
  EXPECT_EQ(idl.find("#include"), std::string::npos);
}

// ---- RecordingWriter -------------------------------------------------------------------------

TEST(RecordingWriter, FileLayoutAsRead) {
  TempDir dir;
  const std::string path = dir.file("run.mcap");
  const FileOptions options = file_options();
  const std::map<std::string, std::string> result_qos = {{"reliability", "RELIABLE"},
                                                         {"durability", "TRANSIENT_LOCAL"}};
  const std::map<std::string, std::string> status_qos = {{"reliability", "BEST_EFFORT"},
                                                         {"history", "KEEP_LAST 5"}};
  std::vector<Written> written;
  {
    RecordingWriter writer(path, options);
    writer.add_topic(topic(kResult), result_qos);
    writer.add_topic(topic(kStatus), status_qos);
    writer.add_topic(topic("Heartbeat"), {});  // never written
    put(writer, written, {kResult, 1'000, 900, result_bytes("pm1", "r1")});
    put(writer, written, {kStatus, 2'000, 1'950, status_bytes("pm1")});
    put(writer, written, {kResult, 3'000, 2'999, result_bytes("pm2", "r2")});
    put(writer, written, {kResult, 2'500, 2'400, result_bytes("pm1", "r3")});  // late
    EXPECT_EQ(writer.messages(), 4U);
    writer.close();
    writer.close();  // idempotent
    EXPECT_EQ(writer.files(), std::vector<std::string>{path});
    EXPECT_EQ(writer.bytes(), fs::file_size(path));
  }
  const mcap::Recording r = mcap::read_file(path);
  EXPECT_TRUE(r.indexed);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  EXPECT_EQ(r.header.profile, "ncqual");
  EXPECT_EQ(r.header.library, options.library);
  ASSERT_EQ(r.metadata.size(), 1U);
  EXPECT_EQ(r.metadata[0].name, "ncqual");
  EXPECT_EQ(r.metadata[0].metadata, options.metadata);

  // One schema per type, each the whole IDL.
  EXPECT_EQ(r.schemas.size(), 3U);
  ASSERT_EQ(r.channels.size(), 3U);
  const std::map<std::string, std::map<std::string, std::string>> qos = {
      {kResult, result_qos}, {kStatus, status_qos}, {"ncqual/Heartbeat", {}}};
  for (const auto& [name, topic_qos] : qos) {
    SCOPED_TRACE(name);
    const mcap::Channel* c = channel_named(r, name);
    ASSERT_NE(c, nullptr) << "a topic added has its channel, messages or not";
    EXPECT_EQ(c->message_encoding, "cdr");
    const auto schema = r.schemas.find(c->schema_id);
    ASSERT_NE(schema, r.schemas.end());
    EXPECT_EQ(schema->second.encoding, "omgidl");
    EXPECT_EQ(schema->second.name, topic(name).type_name);
    EXPECT_EQ(schema->second.data, idl_bytes());
    EXPECT_EQ(c->metadata.at("type"), topic(name).type_name);
    EXPECT_EQ(c->metadata.at("keyed"), "true");
    EXPECT_EQ(c->metadata.at("key"), "machine_id");
    auto expected = channel_metadata(topic(name));
    for (const auto& [key, value] : topic_qos) {
      EXPECT_EQ(c->metadata.at(key), value) << key;
      expected[key] = value;
    }
    EXPECT_EQ(c->metadata, expected);
  }
  EXPECT_EQ(r.schemas.at(channel_named(r, kResult)->schema_id).name,
            "ncqual::msg::v2::CheckResult");
  expect_messages(r, r.messages, written);
}

TEST(RecordingWriter, WriteToATopicNotAddedThrows) {
  TempDir dir;
  RecordingWriter writer(dir.file("run.mcap"), file_options());
  writer.add_topic(topic(kResult), {});
  EXPECT_THROW(writer.write(kStatus, 1, 1, status_bytes("pm1")), mcap::Error);
}

TEST(RecordingWriter, ExistingFileRefusedWithoutOverwrite) {
  TempDir dir;
  const std::string path = dir.file("run.mcap");
  {
    RecordingWriter first(path, file_options());
    first.add_topic(topic(kResult), {});
    first.write(kResult, 1, 1, result_bytes("pm1", "r1"));
  }
  const std::string before = read_bytes(path);
  const std::string what = what_of([&] { RecordingWriter second(path, file_options()); });
  EXPECT_NE(what.find(path), std::string::npos) << what;
  EXPECT_THROW((RecordingWriter{path, file_options()}), mcap::Error);
  EXPECT_TRUE(read_bytes(path) == before) << "the refused file is left as it was";

  FileOptions overwrite = file_options();
  overwrite.overwrite = true;
  {
    RecordingWriter again(path, overwrite);
    again.add_topic(topic(kStatus), {});
    again.write(kStatus, 5, 5, status_bytes("pm9"));
  }
  const mcap::Recording r = mcap::read_file(path);
  ASSERT_EQ(r.messages.size(), 1U);
  EXPECT_EQ(r.channels.at(r.messages[0].channel_id).topic, kStatus);
  EXPECT_EQ(channel_named(r, kResult), nullptr);
}

TEST(RecordingWriter, FileThatCannotBeCreatedThrows) {
  TempDir dir;
  const std::string path = dir.file("no-such-directory/run.mcap");
  const std::string what = what_of([&] { RecordingWriter writer(path, file_options()); });
  EXPECT_NE(what.find(path), std::string::npos) << what;
  EXPECT_THROW((RecordingWriter{path, file_options()}), mcap::Error);
}

TEST(RecordingWriter, UnknownCompressionThrows) {
  TempDir dir;
  FileOptions o = file_options();
  o.compression = "gzip";
  EXPECT_THROW((RecordingWriter{dir.file("run.mcap"), o}), mcap::Error);
}

// Each file of a rotated recording: named run-000N.mcap, complete and indexed, with the
// Metadata record (and its part number) and every topic's channel.
void expect_parts(const std::vector<std::string>& files, const TempDir& dir, std::size_t first,
                  const FileOptions& options) {
  for (std::size_t i = 0; i < files.size(); ++i) {
    SCOPED_TRACE(files[i]);
    char name[32];
    std::snprintf(name, sizeof name, "run-%04zu.mcap", first + i);
    EXPECT_EQ(files[i], dir.file(name));
    const mcap::Recording r = mcap::read_file(files[i]);
    EXPECT_TRUE(r.indexed);
    EXPECT_TRUE(r.warnings.empty());
    EXPECT_EQ(r.header.profile, "ncqual");
    ASSERT_EQ(r.metadata.size(), 1U);
    auto expected = options.metadata;
    expected["part"] = std::to_string(first + i);
    EXPECT_EQ(r.metadata[0].metadata, expected);
    EXPECT_NE(channel_named(r, kResult), nullptr);
    EXPECT_NE(channel_named(r, kStatus), nullptr);
  }
}

TEST(RecordingWriter, RotationBySize) {
  TempDir dir;
  const std::string path = dir.file("run.mcap");
  FileOptions options = file_options();
  // Each file holds the IDL twice (one schema per type): a file is full a few messages past it.
  options.max_size_bytes = 2 * idl_text().size() + 4000;
  const std::string padding(600, 'x');
  std::vector<Written> written;
  std::vector<std::string> files;
  std::uint64_t bytes = 0;
  {
    RecordingWriter writer(path, options);
    writer.add_topic(topic(kResult), {});
    writer.add_topic(topic(kStatus), {});
    for (std::int64_t i = 0; i < 40; ++i) {
      const std::string machine = i % 3 == 0 ? "pm1" : "pm2";
      put(writer, written,
          {i % 2 == 0 ? kResult : kStatus, 1'000 * (i + 1), 1'000 * (i + 1) - 1,
           i % 2 == 0 ? result_bytes(machine, "r" + std::to_string(i), padding)
                      : status_bytes(machine, padding)});
    }
    writer.close();
    files = writer.files();
    bytes = writer.bytes();
    EXPECT_EQ(writer.messages(), 40U);
  }
  ASSERT_GE(files.size(), 3U);
  EXPECT_FALSE(fs::exists(path)) << "a rotated recording has numbered files only";
  expect_parts(files, dir, 1, options);
  std::uint64_t total = 0;
  std::vector<Written> remaining = written;
  for (std::size_t i = 0; i < files.size(); ++i) {
    SCOPED_TRACE(files[i]);
    total += fs::file_size(files[i]);
    if (i + 1 < files.size()) {
      EXPECT_GE(fs::file_size(files[i]), options.max_size_bytes);
    }
    const mcap::Recording r = mcap::read_file(files[i]);
    ASSERT_FALSE(r.messages.empty()) << "every part holds a message";
    ASSERT_LE(r.messages.size(), remaining.size());
    const std::vector<Written> part(
        remaining.begin(), remaining.begin() + static_cast<std::ptrdiff_t>(r.messages.size()));
    expect_messages(r, r.messages, part);
    remaining.erase(remaining.begin(),
                    remaining.begin() + static_cast<std::ptrdiff_t>(r.messages.size()));
  }
  EXPECT_TRUE(remaining.empty()) << remaining.size() << " messages in no file";
  EXPECT_EQ(bytes, total);
}

// split 60 s, times 0, 10, 61, 62, 130 s: 61 - 0 >= 60 opens part 2 (first 61), 130 - 61 >= 60
// opens part 3: {0, 10}, {61, 62}, {130}.
std::vector<std::string> write_split_recording(const std::string& path,
                                               const FileOptions& options) {
  RecordingWriter writer(path, options);
  writer.add_topic(topic(kResult), {});
  writer.add_topic(topic(kStatus), {});
  for (const std::int64_t s : {0, 10, 61, 62, 130}) {
    writer.write(s % 2 == 0 ? kResult : kStatus, s * kSecond, s * kSecond,
                 s % 2 == 0 ? result_bytes("pm1", "r" + std::to_string(s)) : status_bytes("pm1"));
  }
  writer.close();
  return writer.files();
}

std::vector<std::uint64_t> log_times_of(const std::string& file) {
  std::vector<std::uint64_t> out;
  for (const auto& m : mcap::read_file(file).messages) out.push_back(m.log_time);
  return out;
}

TEST(RecordingWriter, RotationByLogTime) {
  TempDir dir;
  FileOptions options = file_options();
  options.split_every_ns = 60 * kSecond;
  const auto files = write_split_recording(dir.file("run.mcap"), options);
  ASSERT_EQ(files.size(), 3U);
  expect_parts(files, dir, 1, options);
  const std::uint64_t s = kSecond;
  EXPECT_EQ(log_times_of(files[0]), (std::vector<std::uint64_t>{0, 10 * s}));
  EXPECT_EQ(log_times_of(files[1]), (std::vector<std::uint64_t>{61 * s, 62 * s}));
  EXPECT_EQ(log_times_of(files[2]), (std::vector<std::uint64_t>{130 * s}));
}

// Two writers one after the other on run.mcap in a fresh directory, each splitting every minute
// into three parts (write_split_recording). `between(first, options)` runs after the first (it may
// move parts away or change the options) and returns the files, with their bytes, that must stay as
// they are; the second writer, other metadata, must go on at run-0004.mcap and leave them alone.
void expect_second_writer_overwrites_nothing(
    const std::function<std::map<std::string, std::string>(const std::vector<std::string>& first,
                                                           FileOptions& options)>& between) {
  const TempDir dir;
  const std::string path = dir.file("run.mcap");
  FileOptions options = file_options();
  options.split_every_ns = 60 * kSecond;
  const auto first = write_split_recording(path, options);
  ASSERT_EQ(first.size(), 3U);
  const std::map<std::string, std::string> before = between(first, options);
  options.metadata["session"] = "second";  // other bytes: an overwritten part would show
  const auto second = write_split_recording(path, options);
  ASSERT_EQ(second.size(), 3U);
  expect_parts(second, dir, 4, options);
  for (const auto& [file, bytes] : before) {
    EXPECT_TRUE(read_bytes(file) == bytes) << file << " was overwritten";
  }
}

TEST(RecordingWriter, SecondWriterContinuesNumbering) {
  expect_second_writer_overwrites_nothing(
      [](const std::vector<std::string>& first, FileOptions& options) {
        std::map<std::string, std::string> before;
        for (const auto& f : first) before[f] = read_bytes(f);
        options.overwrite = true;  // not a licence to overwrite a rotated recording's parts
        return before;
      });
}

TEST(RecordingWriter, RestartAfterTheFirstPartsWereMovedAwayOverwritesNothing) {
  // When run-0001.mcap is gone (archived) but run-0002.mcap and run-0003.mcap are there, a
  // restarted writer goes on at run-0004.mcap and overwrites nothing (found by this test: the
  // writer used to start at the first gap and overwrite the later parts).
  expect_second_writer_overwrites_nothing([](const std::vector<std::string>& first, FileOptions&) {
    fs::remove(first[0]);
    return std::map<std::string, std::string>{{first[1], read_bytes(first[1])},
                                              {first[2], read_bytes(first[2])}};
  });
}

// ---- recover ---------------------------------------------------------------------------------

TEST(Recover, CutFileGivesACompleteFileOfItsCompleteChunks) {
  TempDir dir;
  const std::string full_path = dir.file("full.mcap");
  FileOptions options = file_options();
  options.compression = "lz4";
  options.chunk_bytes = 2000;
  std::vector<Written> written;
  {
    RecordingWriter writer(full_path, options);
    writer.add_topic(topic(kResult), {{"reliability", "RELIABLE"}});
    writer.add_topic(topic(kStatus), {});
    for (std::int64_t i = 0; i < 24; ++i) {
      put(writer, written,
          {i % 2 == 0 ? kResult : kStatus, 1'000 * i, 1'000 * i,
           i % 2 == 0 ? result_bytes("pm1", "r" + std::to_string(i), std::string(100, 'y'))
                      : status_bytes("pm2")});
      if (i % 3 == 2) writer.flush();
    }
  }
  const std::string full_bytes = read_bytes(full_path);
  const mcap::Recording full = mcap::read_file(full_path);
  ASSERT_GE(full.chunks.size(), 5U);
  // Cut in the middle of chunk k: chunks 0 .. k-1 (and what follows them) are whole.
  const std::size_t k = full.chunks.size() - 2;
  const auto& cut_chunk = full.chunks[k];
  const std::size_t cut = cut_chunk.offset + cut_chunk.length / 2;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < k; ++i) kept += full.chunks[i].message_count;
  ASSERT_GT(kept, 2U);
  ASSERT_LT(kept, written.size());

  const std::string cut_path = dir.file("cut.mcap");
  write_bytes(cut_path, full_bytes.substr(0, cut));
  const mcap::Recording cut_read = mcap::read_file(cut_path);
  EXPECT_FALSE(cut_read.indexed);
  EXPECT_FALSE(cut_read.warnings.empty());

  const std::string out_path = dir.file("recovered.mcap");
  const mcap::Recording returned = recover(cut_path, out_path);
  EXPECT_EQ(returned.messages.size(), kept);
  EXPECT_FALSE(returned.warnings.empty()) << "what was read says what was missing";

  const mcap::Recording out = mcap::read_file(out_path);
  EXPECT_TRUE(out.indexed);
  EXPECT_TRUE(out.warnings.empty()) << out.warnings.front();
  EXPECT_EQ(out.header.profile, "ncqual");
  EXPECT_EQ(out.header.library, options.library);
  EXPECT_EQ(out.compression, std::set<std::string>{"lz4"});
  ASSERT_EQ(out.metadata.size(), 1U);
  EXPECT_EQ(out.metadata[0].name, "ncqual");
  EXPECT_EQ(out.metadata[0].metadata, options.metadata);
  for (const auto& name : {kResult, kStatus}) {
    SCOPED_TRACE(name);
    const mcap::Channel* c = channel_named(out, name);
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->metadata, channel_named(full, name)->metadata);
    EXPECT_EQ(out.schemas.at(c->schema_id).data, idl_bytes());
    EXPECT_EQ(out.schemas.at(c->schema_id).name, topic(name).type_name);
  }
  expect_messages(
      out, out.messages,
      std::vector<Written>(written.begin(), written.begin() + static_cast<std::ptrdiff_t>(kept)));
}

TEST(Recover, IntoTheSameFileIsRefused) {
  TempDir dir;
  const std::string path = dir.file("run.mcap");
  {
    RecordingWriter writer(path, file_options());
    writer.add_topic(topic(kResult), {});
    writer.write(kResult, 1, 1, result_bytes("pm1", "r1"));
  }
  const std::string before = read_bytes(path);
  EXPECT_THROW(recover(path, path), mcap::Error);
  const std::string what = what_of([&] { recover(path, (dir.path / "." / "run.mcap").string()); });
  EXPECT_NE(what.find("another file"), std::string::npos) << what;
  EXPECT_TRUE(read_bytes(path) == before);
}

// ---- inspect ---------------------------------------------------------------------------------

// Another system's channels beside ncqual's, written straight with mcap::Writer:
//   ncqual/CheckResult (ncqual's): pm1 at 100, pm2 at 200, pm1 at 300, garbage at 350
//   ncqual/MachineStatus (ncqual's): pm1 at 250
//   /tf, ros2msg: at 50 and 400
//   ncqual/CheckResult whose schema is ncqual::msg::Other: at 150
//   ncqual/Heartbeat in json, ncqual/Alarm without schema, ncqual/Intervention with a ros2idl
//   schema: no messages
struct MixedFile {
  std::uint16_t result = 0, status = 0, tf = 0, other = 0, json = 0, no_schema = 0, ros2idl = 0;
  Bytes garbage = {'n', 'o', 't', ' ', 'a', ' ', 'C', 'h', 'e', 'c', 'k', 'R', 'e', 's', 'u', 'l'};
};

void write_message(mcap::Writer& w, std::uint16_t channel, std::uint64_t log_time, Bytes data) {
  mcap::Message m;
  m.channel_id = channel;
  m.log_time = log_time;
  m.publish_time = log_time;
  m.data = std::move(data);
  w.write(m);
}

MixedFile write_mixed(const std::string& path) {
  MixedFile f;
  mcap::Options o;
  o.profile = "ros2";
  o.library = "someone else";
  mcap::Writer w(path, o);
  const auto result_schema = w.add_schema("ncqual::msg::v2::CheckResult", "omgidl", idl_bytes());
  const auto status_schema = w.add_schema("ncqual::msg::MachineStatus", "omgidl", idl_bytes());
  const auto tf_schema = w.add_schema("tf2_msgs/msg/TFMessage", "ros2msg",
                                      Bytes{'T', 'r', 'a', 'n', 's', 'f', 'o', 'r', 'm'});
  const auto other_schema = w.add_schema("ncqual::msg::Other", "omgidl", idl_bytes());
  const auto intervention_schema = w.add_schema("ncqual::msg::Intervention", "ros2idl", Bytes{'x'});
  f.result = w.add_channel(result_schema, kResult, "cdr");
  f.status = w.add_channel(status_schema, kStatus, "cdr");
  f.tf = w.add_channel(tf_schema, "/tf", "ros2msg");
  f.other = w.add_channel(other_schema, kResult, "cdr");
  f.json = w.add_channel(0, "ncqual/Heartbeat", "json");
  f.no_schema = w.add_channel(0, "ncqual/Alarm", "cdr");
  f.ros2idl = w.add_channel(intervention_schema, "ncqual/Intervention", "cdr");
  write_message(w, f.tf, 50, {1, 2, 3});
  write_message(w, f.result, 100, result_bytes("pm1", "a"));
  write_message(w, f.other, 150, result_bytes("pm3", "o"));
  write_message(w, f.result, 200, result_bytes("pm2", "b"));
  write_message(w, f.status, 250, status_bytes("pm1"));
  write_message(w, f.result, 300, result_bytes("pm1", "c"));
  write_message(w, f.result, 350, f.garbage);
  write_message(w, f.tf, 400, {4, 5, 6});
  w.close();
  return f;
}

const ChannelInfo* channel_info(const Info& info, std::uint16_t id) {
  for (const auto& c : info.channels) {
    if (c.id == id) return &c;
  }
  return nullptr;
}

TEST(Inspect, CountsAndChannelProblems) {
  TempDir dir;
  const std::string path = dir.file("mixed.mcap");
  const MixedFile f = write_mixed(path);
  const mcap::Recording r = mcap::read_file(path);
  const Info info = inspect(r, path, fs::file_size(path));
  EXPECT_EQ(info.file, path);
  EXPECT_EQ(info.file_bytes, fs::file_size(path));
  EXPECT_EQ(info.header.profile, "ros2");
  EXPECT_TRUE(info.indexed);
  EXPECT_EQ(info.chunks, r.chunks.size());
  EXPECT_EQ(info.messages, 8U);
  EXPECT_EQ(info.start_ns, 50U);
  EXPECT_EQ(info.end_ns, 400U);
  const std::map<std::pair<std::string, std::string>, std::uint64_t> per_machine = {
      {{kResult, "pm1"}, 2}, {{kResult, "pm2"}, 1}, {{kStatus, "pm1"}, 1}};
  EXPECT_EQ(info.per_machine, per_machine);
  ASSERT_EQ(info.channels.size(), 7U);

  const ChannelInfo* result = channel_info(info, f.result);
  ASSERT_NE(result, nullptr);
  EXPECT_EQ(result->topic_info, &topic(kResult));
  EXPECT_EQ(result->problem, "");
  EXPECT_TRUE(result->schema_is_this_build);
  EXPECT_EQ(result->schema_name, "ncqual::msg::v2::CheckResult");
  EXPECT_EQ(result->schema_encoding, "omgidl");
  EXPECT_EQ(result->messages, 4U);
  EXPECT_EQ(channel_info(info, f.status)->messages, 1U);
  EXPECT_EQ(channel_info(info, f.status)->topic_info, &topic(kStatus));

  const ChannelInfo* tf = channel_info(info, f.tf);
  ASSERT_NE(tf, nullptr);
  EXPECT_EQ(tf->topic_info, nullptr);
  EXPECT_EQ(tf->problem, "not an ncqual topic");
  EXPECT_EQ(tf->messages, 2U);
  EXPECT_FALSE(tf->schema_is_this_build);

  const ChannelInfo* other = channel_info(info, f.other);
  ASSERT_NE(other, nullptr);
  EXPECT_EQ(other->topic_info, nullptr);
  EXPECT_NE(other->problem.find("ncqual::msg::Other"), std::string::npos) << other->problem;
  EXPECT_NE(other->problem.find("ncqual::msg::v2::CheckResult"), std::string::npos)
      << other->problem;
  EXPECT_EQ(other->messages, 1U);

  EXPECT_EQ(channel_info(info, f.json)->topic_info, nullptr);
  EXPECT_NE(channel_info(info, f.json)->problem.find("json"), std::string::npos);
  EXPECT_EQ(channel_info(info, f.no_schema)->topic_info, nullptr);
  EXPECT_NE(channel_info(info, f.no_schema)->problem.find("no schema"), std::string::npos);
  EXPECT_EQ(channel_info(info, f.ros2idl)->topic_info, nullptr);
  EXPECT_NE(channel_info(info, f.ros2idl)->problem.find("ros2idl"), std::string::npos);

  EXPECT_EQ(info.unreadable, 1U);
  ASSERT_EQ(info.problems.size(), 1U);
  EXPECT_EQ(info.problems[0].rfind("Message at byte", 0), 0U) << info.problems[0];
  EXPECT_NE(info.problems[0].find(kResult), std::string::npos) << info.problems[0];
}

// A recording an earlier version made, in wire contract 1's layout of CheckResult: listed with its
// contract, and every sample read (and replayed) in contract 2's layout with its origin unknown.
TEST(Inspect, ARecordingOfWireContractOneIsReadInTheCurrentLayout) {
  TempDir dir;
  const std::string path = dir.file("contract1.mcap");
  CheckResult r;
  r.machine_id = "pm1";
  r.request_id = "r1";
  r.verdict = Verdict::Pass;
  r.time_ns = 1'700'000'000 * kSecond;
  const Bytes one = dds::serialize<dds::CheckResultContract1Topic>(dds::to_wire_contract1(r));
  {
    mcap::Options o;
    o.profile = "ncqual";
    mcap::Writer w(path, o);
    const auto schema = w.add_schema("ncqual::msg::CheckResult", "omgidl", Bytes{'x'});
    const auto channel = w.add_channel(schema, kResult, "cdr");
    write_message(w, channel, 100, one);
    write_message(w, channel, 200, Bytes{0, 1, 0, 0, 9});  // not a CheckResult of any layout
    w.close();
  }
  const mcap::Recording rec = mcap::read_file(path);
  const Info info = inspect(rec, path, fs::file_size(path));
  ASSERT_EQ(info.channels.size(), 1U);
  EXPECT_EQ(info.channels[0].topic_info, &topic(kResult));
  ASSERT_NE(info.channels[0].older, nullptr);
  EXPECT_EQ(info.channels[0].older->contract, 1);
  EXPECT_EQ(info.channels[0].problem, "");
  EXPECT_EQ(info.unreadable, 1U);
  EXPECT_NE(nlohmann::json::parse(to_json(info))["channels"][0]["wire_contract"], nullptr);
  EXPECT_EQ(nlohmann::json::parse(to_json(info))["channels"][0]["wire_contract"], 1);

  const Selection s = select(rec, {}, path);
  ASSERT_EQ(s.samples.size(), 1U);
  EXPECT_EQ(s.samples[0].machine_id, "pm1");
  // What this build writes for the same result, its origin unknown.
  EXPECT_EQ(s.samples[0].bytes(), dds::serialize<dds::CheckResultTopic>(dds::to_wire(r)));
  EXPECT_EQ(s.upgraded.at(kResult).at(1), 1U);
  ASSERT_EQ(s.skipped.size(), 1U);
  EXPECT_NE(s.skipped[0].find("wire contract 1"), std::string::npos) << s.skipped[0];
}

TEST(Inspect, RecordingOfThisBuild) {
  TempDir dir;
  const std::string path = dir.file("run.mcap");
  const FileOptions options = file_options();
  {
    RecordingWriter writer(path, options);
    writer.add_topic(topic(kResult), {});
    writer.add_topic(topic(kStatus), {});
    writer.write(kResult, 5 * kSecond, 5 * kSecond, result_bytes("pm1", "r1"));
    writer.write(kResult, 6 * kSecond, 6 * kSecond, result_bytes("pm1", "r2"));
    writer.write(kStatus, 7 * kSecond, 7 * kSecond, status_bytes("pm2"));
  }
  const Info info = inspect(mcap::read_file(path), path, fs::file_size(path));
  EXPECT_EQ(info.header.library, options.library);
  ASSERT_EQ(info.metadata.size(), 1U);
  EXPECT_EQ(info.metadata[0].metadata, options.metadata);
  EXPECT_EQ(info.messages, 3U);
  EXPECT_EQ(info.start_ns, static_cast<std::uint64_t>(5 * kSecond));
  EXPECT_EQ(info.end_ns, static_cast<std::uint64_t>(7 * kSecond));
  EXPECT_EQ(info.unreadable, 0U);
  EXPECT_TRUE(info.problems.empty());
  for (const auto& c : info.channels) {
    EXPECT_NE(c.topic_info, nullptr) << c.topic;
    EXPECT_TRUE(c.schema_is_this_build) << c.topic;
  }
  const std::map<std::pair<std::string, std::string>, std::uint64_t> per_machine = {
      {{kResult, "pm1"}, 2}, {{kStatus, "pm2"}, 1}};
  EXPECT_EQ(info.per_machine, per_machine);
}

TEST(Inspect, ToJsonCarriesTheCounts) {
  TempDir dir;
  const std::string path = dir.file("mixed.mcap");
  write_mixed(path);
  const Info info = inspect(mcap::read_file(path), path, fs::file_size(path));
  const nlohmann::json j = nlohmann::json::parse(to_json(info));
  EXPECT_EQ(j.at("file"), path);
  EXPECT_EQ(j.at("bytes"), fs::file_size(path));
  EXPECT_EQ(j.at("profile"), "ros2");
  EXPECT_EQ(j.at("indexed"), true);
  EXPECT_EQ(j.at("messages"), 8);
  EXPECT_EQ(j.at("start_ns"), 50);
  EXPECT_EQ(j.at("end_ns"), 400);
  char buffer[32];
  EXPECT_EQ(j.at("start"), std::string(format_iso8601(50, buffer)));
  EXPECT_EQ(j.at("unreadable"), 1);
  ASSERT_EQ(j.at("problems").size(), 1U);
  EXPECT_EQ(j.at("channels").size(), 7U);
  std::map<std::string, std::uint64_t> per_machine;
  for (const auto& p : j.at("per_machine")) {
    per_machine[p.at("topic").get<std::string>() + " " + p.at("machine").get<std::string>()] =
        p.at("messages").get<std::uint64_t>();
  }
  EXPECT_EQ(per_machine, (std::map<std::string, std::uint64_t>{
                             {kResult + " pm1", 2}, {kResult + " pm2", 1}, {kStatus + " pm1", 1}}));
  bool tf_seen = false;
  for (const auto& c : j.at("channels")) {
    if (c.at("topic") == "/tf") {
      tf_seen = true;
      EXPECT_EQ(c.at("messages"), 2);
      EXPECT_EQ(c.at("ncqual"), false);
      EXPECT_EQ(c.at("problem"), "not an ncqual topic");
    }
  }
  EXPECT_TRUE(tf_seen);
}

// 25 messages that are not CheckResults and one that is, on ncqual's CheckResult channel.
std::string write_unreadable(const TempDir& dir) {
  std::string path = dir.file("garbage.mcap");
  RecordingWriter writer(path, file_options());
  writer.add_topic(topic(kResult), {});
  for (int i = 0; i < 25; ++i) {
    writer.write(kResult, i, i, Bytes{0, 1, 0, 0, 0xff, 0xff, 0xff, 0x7f});
  }
  writer.write(kResult, 100, 100, result_bytes("pm1", "good"));
  writer.close();
  return path;
}

TEST(Inspect, UnreadableMessagesListedUpToTwentyCountedAll) {
  TempDir dir;
  const std::string path = write_unreadable(dir);
  const Info info = inspect(mcap::read_file(path), path, fs::file_size(path));
  EXPECT_EQ(info.messages, 26U);
  EXPECT_EQ(info.unreadable, 25U);
  EXPECT_EQ(info.problems.size(), 20U);
  for (const auto& p : info.problems) EXPECT_EQ(p.rfind("Message at byte", 0), 0U) << p;
  const std::map<std::pair<std::string, std::string>, std::uint64_t> per_machine = {
      {{kResult, "pm1"}, 1}};
  EXPECT_EQ(info.per_machine, per_machine);
}

TEST(Inspect, CutRecordingIsNotIndexedAndSaysSo) {
  TempDir dir;
  const std::string path = dir.file("run.mcap");
  {
    RecordingWriter writer(path, file_options());
    writer.add_topic(topic(kResult), {});
    writer.write(kResult, 1, 1, result_bytes("pm1", "r1"));
    writer.flush();
    writer.write(kResult, 2, 2, result_bytes("pm1", "r2"));
  }
  const std::string bytes = read_bytes(path);
  const mcap::Recording full = mcap::read_file(path);
  ASSERT_EQ(full.chunks.size(), 2U);
  const std::string cut = dir.file("cut.mcap");
  write_bytes(cut, bytes.substr(0, full.chunks[1].offset + 3));
  const Info info = inspect(mcap::read_file(cut), cut, fs::file_size(cut));
  EXPECT_FALSE(info.indexed);
  EXPECT_FALSE(info.warnings.empty());
  EXPECT_EQ(info.messages, 1U);
  EXPECT_EQ(info.chunks, 1U);
}

// ---- select ----------------------------------------------------------------------------------

// Written out of log-time order: (topic, machine, log time) =
//   0: CheckResult pm1 30   1: CheckResult pm2 10   2: MachineStatus pm1 20
//   3: CheckResult pm1 10   4: MachineStatus pm2 40
struct Ordered {
  std::string path;
  std::vector<Written> written;
};

Ordered write_out_of_order(const TempDir& dir) {
  Ordered o;
  o.path = dir.file("run.mcap");
  RecordingWriter writer(o.path, file_options());
  writer.add_topic(topic(kResult), {});
  writer.add_topic(topic(kStatus), {});
  put(writer, o.written, {kResult, 30, 29, result_bytes("pm1", "r0")});
  put(writer, o.written, {kResult, 10, 9, result_bytes("pm2", "r1")});
  put(writer, o.written, {kStatus, 20, 19, status_bytes("pm1", "s2")});
  put(writer, o.written, {kResult, 10, 8, result_bytes("pm1", "r3")});
  put(writer, o.written, {kStatus, 40, 39, status_bytes("pm2", "s4")});
  return o;
}

// The written indexes of `s`'s samples, checking each sample against what was written.
std::vector<int> indexes(const Selection& s, const mcap::Recording& r,
                         const std::vector<Written>& written) {
  std::vector<int> out;
  for (const auto& sample : s.samples) {
    EXPECT_GE(sample.message, r.messages.data());
    EXPECT_LT(sample.message, r.messages.data() + r.messages.size());
    int found = -1;
    for (std::size_t i = 0; i < written.size(); ++i) {
      if (written[i].bytes == sample.message->data) found = static_cast<int>(i);
    }
    out.push_back(found);
    if (found < 0) continue;
    const Written& w = written[static_cast<std::size_t>(found)];
    EXPECT_EQ(sample.topic, &topic(w.topic));
    EXPECT_EQ(sample.log_time_ns, w.log_ns);
    EXPECT_EQ(sample.publish_time_ns, w.publish_ns);
  }
  return out;
}

TEST(Select, EverythingInLogTimeOrderStableAmongEqualTimes) {
  TempDir dir;
  const Ordered o = write_out_of_order(dir);
  const mcap::Recording r = mcap::read_file(o.path);
  const Selection s = select(r, {}, o.path);
  EXPECT_EQ(indexes(s, r, o.written), (std::vector<int>{1, 3, 2, 0, 4}));
  std::vector<std::string> machines;
  for (const auto& sample : s.samples) machines.push_back(sample.machine_id);
  EXPECT_EQ(machines, (std::vector<std::string>{"pm2", "pm1", "pm1", "pm1", "pm2"}));
  EXPECT_EQ(s.filtered_out, 0U);
  EXPECT_EQ(s.skipped_messages, 0U);
  EXPECT_TRUE(s.skipped.empty());
}

TEST(Select, ByTopicMachineAndTime) {
  TempDir dir;
  const Ordered o = write_out_of_order(dir);
  const mcap::Recording r = mcap::read_file(o.path);

  Filter by_topic;
  by_topic.topics = {kResult};
  Selection s = select(r, by_topic, o.path);
  EXPECT_EQ(indexes(s, r, o.written), (std::vector<int>{1, 3, 0}));
  EXPECT_EQ(s.filtered_out, 2U);

  Filter by_machine;
  by_machine.machines = {"pm2"};
  s = select(r, by_machine, o.path);
  EXPECT_EQ(indexes(s, r, o.written), (std::vector<int>{1, 4}));
  EXPECT_EQ(s.filtered_out, 3U);

  Filter by_time;  // inclusive at both ends
  by_time.from_ns = 20;
  by_time.to_ns = 30;
  s = select(r, by_time, o.path);
  EXPECT_EQ(indexes(s, r, o.written), (std::vector<int>{2, 0}));
  EXPECT_EQ(s.filtered_out, 3U);

  Filter one_instant;
  one_instant.from_ns = 10;
  one_instant.to_ns = 10;
  s = select(r, one_instant, o.path);
  EXPECT_EQ(indexes(s, r, o.written), (std::vector<int>{1, 3}));

  Filter from_only;
  from_only.from_ns = 30;
  s = select(r, from_only, o.path);
  EXPECT_EQ(indexes(s, r, o.written), (std::vector<int>{0, 4}));

  Filter to_only;
  to_only.to_ns = 19;
  s = select(r, to_only, o.path);
  EXPECT_EQ(indexes(s, r, o.written), (std::vector<int>{1, 3}));

  Filter all;
  all.topics = {kResult, kStatus};
  all.machines = {"pm1"};
  all.from_ns = 10;
  all.to_ns = 20;
  s = select(r, all, o.path);
  EXPECT_EQ(indexes(s, r, o.written), (std::vector<int>{3, 2}));
  EXPECT_EQ(s.filtered_out, 3U);

  Filter nothing;
  nothing.machines = {"pm9"};
  s = select(r, nothing, o.path);
  EXPECT_TRUE(s.samples.empty());
  EXPECT_EQ(s.filtered_out, 5U);
}

TEST(Select, ForeignChannelsAndUnreadableMessagesAreSkippedAndReported) {
  TempDir dir;
  const std::string path = dir.file("mixed.mcap");
  write_mixed(path);
  const mcap::Recording r = mcap::read_file(path);
  const Selection s = select(r, {}, path);
  std::vector<std::int64_t> times;
  std::vector<std::string> machines;
  for (const auto& sample : s.samples) {
    times.push_back(sample.log_time_ns);
    machines.push_back(sample.machine_id);
  }
  EXPECT_EQ(times, (std::vector<std::int64_t>{100, 200, 250, 300}));
  EXPECT_EQ(machines, (std::vector<std::string>{"pm1", "pm2", "pm1", "pm1"}));
  // /tf's 2, the other-schema channel's 1, the garbage one.
  EXPECT_EQ(s.skipped_messages, 4U);
  EXPECT_EQ(s.filtered_out, 0U);
  std::string all;
  for (const auto& line : s.skipped) all += line + "\n";
  ASSERT_EQ(s.skipped.size(), 3U) << all;
  const auto has = [&](const std::string& start) {
    return std::any_of(s.skipped.begin(), s.skipped.end(),
                       [&](const std::string& line) { return line.rfind(start, 0) == 0; });
  };
  EXPECT_TRUE(has("/tf (2 messages): not an ncqual topic")) << all;
  EXPECT_TRUE(has(kResult + " (1 messages): schema 'ncqual::msg::Other'")) << all;
  EXPECT_TRUE(has("Message at byte")) << all;
}

TEST(Select, UnreadableMessagesListedUpToTwentyCountedAll) {
  TempDir dir;
  const std::string path = write_unreadable(dir);
  const mcap::Recording r = mcap::read_file(path);
  const Selection s = select(r, {}, path);
  ASSERT_EQ(s.samples.size(), 1U);
  EXPECT_EQ(s.samples[0].machine_id, "pm1");
  EXPECT_EQ(s.skipped_messages, 25U);
  EXPECT_EQ(s.skipped.size(), 20U);
}

TEST(Select, OnlyForeignChannelsThrowsNamingTheFile) {
  TempDir dir;
  const std::string path = dir.file("ros.mcap");
  {
    mcap::Writer w(path);
    const auto tf_schema = w.add_schema("tf2_msgs/msg/TFMessage", "ros2msg", Bytes{'x'});
    const auto other_schema = w.add_schema("ncqual::msg::Other", "omgidl", idl_bytes());
    const auto tf = w.add_channel(tf_schema, "/tf", "ros2msg");
    const auto other = w.add_channel(other_schema, kResult, "cdr");
    write_message(w, tf, 1, {1});
    write_message(w, other, 2, result_bytes("pm1", "x"));
    w.close();
  }
  const mcap::Recording r = mcap::read_file(path);
  const std::string what = what_of([&] { select(r, {}, path); });
  EXPECT_NE(what.find(path), std::string::npos) << what;
  EXPECT_NE(what.find("no ncqual topic"), std::string::npos) << what;
  EXPECT_NE(what.find("/tf"), std::string::npos) << what;
  EXPECT_THROW(select(r, {}, path), mcap::Error);

  const std::string empty_path = dir.file("empty.mcap");
  {
    mcap::Writer w(empty_path);
    w.close();
  }
  const mcap::Recording empty = mcap::read_file(empty_path);
  const std::string empty_what = what_of([&] { select(empty, {}, empty_path); });
  EXPECT_NE(empty_what.find(empty_path), std::string::npos) << empty_what;
  EXPECT_NE(empty_what.find("no ncqual topic"), std::string::npos) << empty_what;
}

}  // namespace
}  // namespace ncqual::recording
