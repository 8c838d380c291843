// SPDX-License-Identifier: Apache-2.0
// Benchmark of recordings and replay (docs/recordings.md): what the MCAP recording and the
// replay cost, side by side with the plainest way to do the same work.
//
//   (a) writing a recording: --sets MeasurementSets of 216 tracker points (the patent's monthly
//       grid, 9 x 6 points on 4 planes; the simulator's grid set of deploy/machines/pm1.yaml cut
//       to its first 216 points), serialized as on the wire, written by the recording library
//       (RecordingWriter: chunks, message indexes, CRCs, summary) uncompressed, lz4 and zstd,
//       beside a raw fwrite of the same bytes to a file (fopen, fwrite each, fclose). The median
//       of --repeat runs; files in a temporary directory, no fsync for either.
//   (b) the live recorder: the same sets published by a raw Fast DDS writer (RawWriter, the
//       MeasurementSet topic's profile QoS, one writer per machine's partition; as the profile's
//       KEEP_LAST history requires, each waits for its readers' acknowledgements after half its
//       history depth, with the heartbeat period of a fast replay) to a real `ncqual record`
//       process (zstd, as the recorder service writes).
//   (c) the replay: a recording of the same sets (zstd) read, selected and replayed as fast as
//       the readers acknowledge (recording::Replayer, as `ncqual replay --fast` does, file
//       reading included) to the same `ncqual record`, beside (b)'s raw publish of the payloads;
//       (b) and (c) alternately, --repeat times each, the median of each.
// At the end the recorder's file must hold every set published in (b) and replayed in (c).
//
// Prints figures with targets and PASS/MISS beside them; exits 0 once measured (whatever the
// figures), 1 when the recorder did not get every set, 2 for bad usage.
#include "harness.hpp"
#include "bench_support.hpp"
#include "test_participant.hpp"

#include "ncqual/common/config.hpp"
#include "ncqual/dds/convert.hpp"
#include "ncqual/dds/raw.hpp"
#include "ncqual/dds/serialized.hpp"
#include "ncqual/dds/topics.hpp"
#include "ncqual/mcap/mcap.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/recording/recording.hpp"
#include "ncqual/recording/replayer.hpp"
#include "ncqual/sim/tracker_simulator.hpp"
#include "ncqual/common/version.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace ncqual;
using Clock = std::chrono::steady_clock;
using Bytes = std::vector<std::uint8_t>;
namespace fs = std::filesystem;

// Targets: the recording library writes at least half as fast as a raw fwrite of the same bytes
// (the chunking, indexes and CRCs may cost, the format must not be the bottleneck of a recorder),
// and the replay publishes at least half as fast as a raw DDS publish of the same payloads (the
// file reading, ordering and pacing may cost, not dominate). Both are the (#16).
constexpr double kTargetRatio = 0.5;
constexpr std::size_t kPointsPerSet = 216;

struct Options {
  int sets = 2000;
  int machines = 10;
  int repeat = 3;
};

// The bench's command line: what it does and Options.
void add_options(CLI::App& app, Options& options) {
  app.description(
      "The cost of recordings: the MCAP recording beside a raw fwrite of the same bytes, the "
      "replay beside a raw Fast DDS publish of the same payloads.");
  bench::add_bounded(app, "--sets", options.sets, "MeasurementSets of 216 points in each run", 1,
                     100000);
  // The durable topics keep the last 500 samples per machine; the writers wait for their
  // readers every 100 samples, so any number of sets per machine is fine.
  bench::add_bounded(app, "--machines", options.machines,
                     "machines the sets are spread over (at most 200, the QoS's instances)", 1,
                     200);
  bench::add_bounded(app, "--repeat", options.repeat, "runs of (a) whose median is shown", 1, 100);
}

struct Payload {
  std::string machine_id;
  Bytes bytes;
};

// --sets serialized 216-point MeasurementSets over --machines machines, each with its own
// request id, so that every payload is distinct.
std::vector<Payload> make_payloads(const Options& o) {
  const MachineConfig machine =
      load_machine_config(std::string(NCQUAL_SOURCE_DIR) + "/deploy/machines/pm1.yaml");
  const sim::TrackerSimulator simulator(machine, machine.simulator);
  CheckRequest request;
  request.machine_id = machine.machine_id;
  request.request_id = "bench-grid";
  request.kind = CheckKind::GlobalGrid;
  MeasurementSet set = simulator.perform(request, 0);
  if (set.tracker_points.size() < kPointsPerSet) {
    throw std::runtime_error("the simulated grid set has only " +
                             std::to_string(set.tracker_points.size()) + " tracker points");
  }
  set.tracker_points.resize(kPointsPerSet);
  const std::vector<TrackerPoint> simulated = set.tracker_points;
  // Each set measured anew: 1 um of noise on every coordinate, so that the sets differ in every
  // value as real ones do (and compress as real ones would, not as copies of one set).
  std::mt19937_64 random(216);
  std::normal_distribution<double> noise_mm(0.0, 0.001);
  std::vector<Payload> out;
  for (int i = 0; i < o.sets; ++i) {
    for (std::size_t k = 0; k < kPointsPerSet; ++k) {
      for (int a = 0; a < 3; ++a) {
        set.tracker_points[k].measured_mm[a] = simulated[k].measured_mm[a] + noise_mm(random);
      }
    }
    set.machine_id = "b" + std::to_string(100 + i % o.machines);
    set.request_id = set.machine_id + "-grid-" + std::to_string(i);
    set.time_ns = 1'800'000'000'000'000'000 + std::int64_t{i} * 1'000'000;
    out.push_back({set.machine_id, ncqual::dds::serialize<ncqual::dds::MeasurementSetTopic>(
                                       ncqual::dds::to_wire(set))});
  }
  return out;
}

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

const char* verdict(bool ok) { return ok ? "PASS" : "MISS"; }

struct Rate {
  double msgs_per_s = 0;
  double mb_per_s = 0;  // payload bytes, 10^6
};

Rate rate_of(std::size_t messages, std::uint64_t bytes, double seconds) {
  return {static_cast<double>(messages) / seconds, static_cast<double>(bytes) / 1e6 / seconds};
}

void print_rate(const std::string& what, const Rate& r, const Rate* baseline, const char* target,
                bool judged = true) {
  std::printf("    %-34s %9.0f msgs/s %8.1f MB/s", what.c_str(), r.msgs_per_s, r.mb_per_s);
  if (baseline) {
    const double ratio = r.msgs_per_s / baseline->msgs_per_s;
    std::printf("  %5.0f %% %s%s%s", 100 * ratio, target, judged ? "  " : "",
                judged ? verdict(ratio >= kTargetRatio) : "");
  }
  std::printf("\n");
}

// The median time of `repeat` runs of `write` into a fresh file of `dir`.
double median_seconds(int repeat, const fs::path& dir,
                      const std::function<void(std::string)>& write, std::uint64_t* file_bytes) {
  std::vector<double> times;
  for (int k = 0; k < repeat; ++k) {
    const fs::path file = dir / ("bench-" + std::to_string(k) + ".bin");
    fs::remove(file);
    const auto t0 = Clock::now();
    write(file.string());
    times.push_back(seconds_since(t0));
    *file_bytes = fs::file_size(file);
    fs::remove(file);
  }
  return bench::quantile(times, 0.5);
}

recording::FileOptions file_options(const std::string& compression) {
  recording::FileOptions f;
  f.library = "ncqual_recording_bench";
  f.compression = compression;
  f.overwrite = true;
  return f;
}

void write_recording(const std::string& path, const std::string& compression,
                     const std::vector<Payload>& payloads) {
  recording::RecordingWriter writer(path, file_options(compression));
  const ncqual::dds::TopicInfo& topic = *ncqual::dds::find_topic("MeasurementSet");
  writer.add_topic(topic, {});
  std::int64_t t = 1'800'000'000'000'000'000;
  for (const auto& p : payloads) {
    t += 1'000'000;
    writer.write(topic.name, t, t, p.bytes);
  }
  writer.close();
}

// (a): the recording library beside fwrite.
void bench_file(const Options& o, const std::vector<Payload>& payloads, std::uint64_t total,
                const fs::path& dir) {
  std::printf(
      "(a) writing %zu MeasurementSets of %zu points (%.1f KiB each, %.1f MB) to a file, "
      "median of %d runs\n",
      payloads.size(), kPointsPerSet, static_cast<double>(payloads.front().bytes.size()) / 1024,
      static_cast<double>(total) / 1e6, o.repeat);
  std::uint64_t raw_size = 0;
  const double raw_s = median_seconds(
      o.repeat, dir,
      [&](const std::string& path) {
        std::FILE* f = std::fopen(path.c_str(), "wb");
        if (!f) throw std::runtime_error("cannot create " + path);
        for (const auto& p : payloads) std::fwrite(p.bytes.data(), 1, p.bytes.size(), f);
        std::fclose(f);
      },
      &raw_size);
  const Rate raw = rate_of(payloads.size(), total, raw_s);
  print_rate("raw fwrite of the payloads", raw, nullptr, "");
  for (const char* compression : {"", "lz4", "zstd"}) {
    std::uint64_t size = 0;
    const double s = median_seconds(
        o.repeat, dir,
        [&](const std::string& path) { write_recording(path, compression, payloads); }, &size);
    const std::string c = compression;
    // The target compares the same bytes written; a compressed recording writes fewer and spends
    // the CPU of its compression, shown beside it, not judged.
    print_rate(c.empty() ? "recording, uncompressed" : ("recording, " + c).c_str(),
               rate_of(payloads.size(), total, s), &raw,
               c.empty() ? "of fwrite [target >= 50 %]" : "of fwrite [compressed: not judged]",
               c.empty());
    std::printf("    %-34s file %.1f MB (%.0f %% of the payloads)%s\n", "",
                static_cast<double>(size) / 1e6,
                100.0 * static_cast<double>(size) / static_cast<double>(raw_size),
                c == "zstd" ? "; the recorder's default" : "");
  }
}

int run(const Options& o) {
  using testing::Plant;
  Plant plant("recording-bench", testing::TestDomain::RecordingBench);
  plant.write_plant();
  const std::vector<Payload> payloads = make_payloads(o);
  std::uint64_t total = 0;
  for (const auto& p : payloads) total += p.bytes.size();
  std::printf("ncqual recording bench (%s), domain %d\n\n",
              version_line("ncqual_recording_bench").c_str(), plant.domain());

  bench_file(o, payloads, total, plant.dir());

  // The recording (c) replays, written before the recorder starts.
  const std::string replay_file = (plant.dir() / "to-replay.mcap").string();
  write_recording(replay_file, "zstd", payloads);
  const std::string live = (plant.dir() / "live.mcap").string();
  testing::Process recorder(
      testing::Launch({NCQUAL_CLI_EXE, "record", "--plant", plant.plant_file(), "--out", live,
                       "--topics", "MeasurementSet"})
          .log_to((plant.dir() / "record.log").string()));

  ncqual::dds::Participant participant(testing::test_participant(plant, "recording-bench"));
  const ncqual::dds::TopicInfo& topic = *ncqual::dds::find_topic("MeasurementSet");
  std::set<std::string> machines;
  for (const auto& p : payloads) machines.insert(p.machine_id);

  // (b) a raw publish of the payloads to the recorder, with the flow control any publisher of
  // them through the profile's KEEP_LAST writers needs, as the replay has it (replayer.hpp): each
  // machine's writer waits for its readers' acknowledgements after half its history depth, and
  // sends heartbeats as often as a fast replay's.
  const recording::ReplayOptions replay_defaults;
  ncqual::dds::RawWriterOptions writer_options;
  writer_options.heartbeat_period = replay_defaults.fast_heartbeat;
  ncqual::dds::RawWriter raw_writer(participant, topic, writer_options);
  for (const auto& m : machines) {
    if (!raw_writer.wait_for_readers(m, 1, std::chrono::seconds(30))) {
      std::fprintf(stderr, "the recorder's reader did not match in 30 s\n%s",
                   plant.log("record").c_str());
      return 1;
    }
  }
  const int window = std::max(1, raw_writer.history_depth() / 2);
  std::size_t sent = 0;  // by both, for the check of the recorder's file
  bool acknowledged = true;
  const auto publish_raw = [&] {
    const auto t0 = Clock::now();
    std::size_t written = 0;
    std::map<std::string, int> since_ack;
    for (const auto& p : payloads) {
      if (raw_writer.write(p.bytes, p.machine_id)) ++written;
      if (int& n = since_ack[p.machine_id]; ++n >= window) {
        n = 0;
        raw_writer.wait_for_acknowledgments(p.machine_id, std::chrono::seconds(30));
      }
    }
    acknowledged = raw_writer.wait_for_acknowledgments(std::chrono::seconds(60)) && acknowledged;
    sent += written;
    return seconds_since(t0);
  };

  // (c) the replay of the recording, its first set of each machine first (not timed: the
  // replayer's writers made and matched, as the raw writer's were above).
  recording::ReplayOptions ro;
  ro.rate = 0;
  ro.readers = 1;
  recording::Replayer replayer(participant, ro);
  {
    const mcap::Recording r = mcap::read_file(replay_file);
    recording::Selection warm = recording::select(r, {}, replay_file);
    std::set<std::string> seen;
    std::vector<recording::Sample> first;
    for (const auto& s : warm.samples) {
      if (seen.insert(s.machine_id).second) first.push_back(s);
    }
    warm.samples = first;
    sent += replayer.run(warm, {}).written;
  }
  std::uint64_t not_written = 0;
  const auto replay = [&] {
    const auto t0 = Clock::now();
    const mcap::Recording r = mcap::read_file(replay_file);
    const recording::Selection selection = recording::select(r, {}, replay_file);
    const recording::ReplayReport report = replayer.run(selection, {});
    acknowledged = report.acknowledged && acknowledged;
    not_written += report.not_written;
    sent += report.written;
    return seconds_since(t0);
  };
  // Alternately, --repeat times each, so that both see the same state of the machine.
  std::vector<double> raw_s, replay_s;
  for (int k = 0; k < o.repeat; ++k) {
    raw_s.push_back(publish_raw());
    replay_s.push_back(replay());
  }
  const Rate raw = rate_of(payloads.size(), total, bench::quantile(raw_s, 0.5));
  const Rate replayed = rate_of(payloads.size(), total, bench::quantile(replay_s, 0.5));

  std::printf(
      "\n(b) the live recorder: the sets published by a raw Fast DDS writer to `ncqual "
      "record` (zstd)\n");
  std::printf("    (median of %d runs each, alternating)\n", o.repeat);
  print_rate("raw publish, recorded", raw, nullptr, "");
  std::printf(
      "\n(c) replaying a recording of the sets (zstd; reading it included), as fast as "
      "the recorder acknowledges\n");
  print_rate("ncqual replay --fast", replayed, &raw, "of raw publish [target >= 50 %]");

  // Every set published and replayed is in the recorder's file.
  recorder.terminate();
  if (recorder.wait() != 0) {
    std::fprintf(stderr, "ncqual record failed\n%s", plant.log("record").c_str());
    return 1;
  }
  const mcap::Recording got = mcap::read_file(live);
  const std::size_t expected = sent;
  std::printf("\n    the recorder's file holds %zu sets of the %zu published and replayed: %s\n",
              got.messages.size(), expected, got.messages.size() == expected ? "all" : "NOT ALL");
  if (got.messages.size() != expected || !acknowledged || not_written != 0) {
    std::fprintf(
        stderr, "sets were lost (all acknowledged: %d, not written by the replay: %llu)\n%s",
        acknowledged, static_cast<unsigned long long>(not_written), plant.log("record").c_str());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::bench_main(argc, argv, "ncqual_recording_bench", add_options, run);
}
