// SPDX-License-Identifier: Apache-2.0
// The acquisition's stations without DDS: each request measured once (also across a restart,
// through a real state file), old requests on the wall clock left alone, post-calibrations that
// wait for the correction they verify, malformed requests answered, nothing recorded that was
// not published.
#include "ncqual/acquisition/station.hpp"

#include "ncqual/common/check_kinds.hpp"

#include <gtest/gtest.h>

#include <utility>

#include <unistd.h>

#include <filesystem>

namespace ncqual::acquisition {
namespace {

namespace fs = std::filesystem;

// Instruments that record what they were asked: the station's logic is under test here, the
// physics is the simulator's (tested on its own, and below once through SimulatedInstruments).
struct Recorder {
  std::vector<std::string> measured;  // request ids, in order
  std::vector<std::string> applied;   // correction targets, in order
  std::vector<std::string> restored;  // correction targets restored at start, in order
  // Asynchronous instruments (a control running programs): measure() hands over, and what the
  // test moves into `finished` comes back from the next poll().
  bool asynchronous = false;
  std::vector<MeasurementSet> finished;
  DataOrigin origin = DataOrigin::Measured;  // what the driver says its sets are
};
class RecordingInstruments : public Instruments {
 public:
  explicit RecordingInstruments(Recorder& r) : r_(r) {}
  std::optional<MeasurementSet> measure(const CheckRequest& request,
                                        std::int64_t time_ns) override {
    r_.measured.push_back(request.request_id);
    if (r_.asynchronous) return std::nullopt;
    return unmeasured(request, time_ns, "");
  }
  std::vector<MeasurementSet> poll() override { return std::exchange(r_.finished, {}); }
  std::string apply(const Correction& correction) override {
    r_.applied.push_back(correction.target);
    return "";
  }
  std::string restore(const Correction& correction) override {
    r_.restored.push_back(correction.target);
    return "";
  }
  DataOrigin origin() const override { return r_.origin; }

 private:
  Recorder& r_;
};

constexpr std::int64_t kSecond = 1'000'000'000;
constexpr std::int64_t kNow = 1'800'000'000 * kSecond;

CheckRequest request(const std::string& id, std::int64_t time_ns = kNow,
                     CheckKind kind = CheckKind::MonumentPositioning) {
  CheckRequest r;
  r.machine_id = "m1";
  r.request_id = id;
  r.kind = kind;
  r.time_ns = time_ns;
  return r;
}

class StationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = fs::temp_directory_path() /
            ("ncqual-station-" + std::to_string(::getpid()) + "-" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".db");
    fs::remove(path_);
    state_ = std::make_unique<storage::StateFile>(storage::StateFile::open(path_.string()));
  }
  void TearDown() override {
    state_.reset();
    for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(path_.string() + suffix);
  }

  // A station as a (re)started process builds it: its performed requests read from the file.
  std::unique_ptr<Station> station(StationOptions options = {}, std::size_t capacity = 1000,
                                   bool publish_ok = true) {
    PerformedRequests performed(*state_, "m1", capacity);
    performed.load(state_->load());
    return std::make_unique<Station>(
        "m1", std::make_unique<RecordingInstruments>(recorder_), std::move(performed), options,
        [this, publish_ok](const MeasurementSet& set) {
          if (publish_ok) published_.push_back(set);
          return publish_ok;
        },
        [](const MeasurementSet& set) {
          return std::vector<storage::OutboxEntry>{{"ncqual/MeasurementSet",
                                                    set.request_id,
                                                    "h-" + set.request_id,
                                                    set.machine_id,
                                                    {1, 2},
                                                    {"historian", "solver"},
                                                    set.time_ns}};
        });
  }

  fs::path path_;
  std::unique_ptr<storage::StateFile> state_;
  Recorder recorder_;
  std::vector<MeasurementSet> published_;
};

TEST_F(StationTest, ARequestIsMeasuredOnceEvenAfterARestart) {
  auto s = station();
  s->on_request(request("r1"), "", kNow);
  s->on_request(request("r1"), "", kNow);  // redelivered
  s->on_request(request("r2"), "", kNow);
  EXPECT_EQ(recorder_.measured, (std::vector<std::string>{"r1", "r2"}));
  ASSERT_EQ(published_.size(), 2u);
  EXPECT_EQ(published_[0].request_id, "r1");

  // A restart is replayed the durable history: r1 and r2 are in the state file.
  s = station();
  s->on_request(request("r1"), "", kNow);
  s->on_request(request("r2"), "", kNow);
  s->on_request(request("r3"), "", kNow);
  EXPECT_EQ(recorder_.measured, (std::vector<std::string>{"r1", "r2", "r3"}));
}

TEST_F(StationTest, OnlyTheNewestRequestsAreRemembered) {
  auto s = station({}, 3);
  for (const char* id : {"a", "b", "c", "d"}) s->on_request(request(id), "", kNow);
  EXPECT_EQ(state_->load().size(), 3u);
  s = station({}, 3);
  s->on_request(request("a"), "", kNow);  // forgotten: measured again
  s->on_request(request("d"), "", kNow);  // remembered
  EXPECT_EQ(recorder_.measured, (std::vector<std::string>{"a", "b", "c", "d", "a"}));
}

// The set is in the outbox, in the transaction that records its request as performed, before it
// is written: when the write fails (or the process dies right after the record), the outbox sends
// it again and a restarted station does not move the machine again.
TEST_F(StationTest, AMeasurementIsRecordedWithItsOutboxEntryBeforeItIsWritten) {
  auto s = station({}, 1000, /*publish_ok=*/false);
  s->on_request(request("r1"), "", kNow);
  const auto index = state_->outbox_index();
  ASSERT_EQ(index.size(), 1u);
  EXPECT_EQ(index[0].sample_id, "r1");
  EXPECT_EQ(index[0].awaiting, (std::vector<std::string>{"historian", "solver"}));
  s = station();
  s->on_request(request("r1"), "", kNow);
  EXPECT_EQ(recorder_.measured, (std::vector<std::string>{"r1"}));
  EXPECT_TRUE(published_.empty());
}

TEST_F(StationTest, OnTheWallClockOldRequestsAreHistoryNotWork) {
  StationOptions wall;
  wall.max_request_age_ns = 600 * kSecond;
  auto s = station(wall);
  s->on_request(request("old", kNow - 601 * kSecond), "", kNow);
  s->on_request(request("young", kNow - 599 * kSecond), "", kNow);
  EXPECT_EQ(recorder_.measured, (std::vector<std::string>{"young"}));
  ASSERT_EQ(published_.size(), 1u);
  EXPECT_EQ(published_[0].time_ns, kNow);  // measured now
}

TEST_F(StationTest, OnASimulatedClockAMeasurementTakesItsInstrumentsTime) {
  StationOptions simulated;
  simulated.simulated_clock = true;
  simulated.max_request_age_ns = 1;
  auto s = station(simulated);
  const std::int64_t asked = kNow - 3600 * kSecond;  // an hour ago on the wall: not history
  s->on_request(request("g", asked, CheckKind::GlobalGrid), "", kNow);
  ASSERT_EQ(published_.size(), 1u);
  // The grid takes 90 minutes (the check-kind table).
  EXPECT_EQ(published_[0].time_ns, asked + 90 * 60 * kSecond);
}

TEST_F(StationTest, APostCalibrationWaitsForTheCorrectionItVerifies) {
  auto s = station();
  CheckRequest post = request("post", kNow, CheckKind::FixturePostCalibration);
  post.verifies_correction_of = "pre";
  s->on_request(post, "", kNow);
  EXPECT_TRUE(recorder_.measured.empty());
  EXPECT_EQ(s->waiting(), 1u);

  Compensation other;
  other.machine_id = "m1";
  other.request_id = "another-pre";
  other.correction.target = "fixture:F1";
  s->on_compensation(other, kNow);
  EXPECT_TRUE(recorder_.measured.empty());

  Compensation c = other;
  c.request_id = "pre";
  s->on_compensation(c, kNow + kSecond);
  s->on_compensation(c, kNow + 2 * kSecond);  // replayed after a restart of the writer: once
  EXPECT_EQ(recorder_.applied, (std::vector<std::string>{"fixture:F1", "fixture:F1"}));
  EXPECT_EQ(recorder_.measured, (std::vector<std::string>{"post"}));
  EXPECT_EQ(s->waiting(), 0u);
  ASSERT_EQ(published_.size(), 1u);
  EXPECT_EQ(published_[0].time_ns, kNow + kSecond);

  // A correction already applied lets its post-calibration through at once.
  CheckRequest again = post;
  again.request_id = "post-2";
  s->on_request(again, "", kNow);
  EXPECT_EQ(recorder_.measured.back(), "post-2");
}

TEST_F(StationTest, AMalformedRequestIsAnsweredWithAnErrorAndOtherMachinesAreNotOurs) {
  auto s = station();
  s->on_request(request("bad"), "CheckRequest.kind = 99 is not a check kind", kNow);
  CheckRequest theirs = request("theirs");
  theirs.machine_id = "m2";
  s->on_request(theirs, "", kNow);
  EXPECT_TRUE(recorder_.measured.empty());
  ASSERT_EQ(published_.size(), 1u);
  EXPECT_EQ(published_[0].error,
            "malformed CheckRequest: CheckRequest.kind = 99 is not a check kind");
}

// What the station settles is what the executable acknowledges to the sender: a request once it
// is measured and recorded (or was, or is history), not while it waits for its correction; a
// compensation once applied and recorded. An applied compensation survives a restart: restored
// into the instruments, never applied twice, and its post-calibration goes through at once.
TEST_F(StationTest, SettledSamplesAreRecordedAndCompensationsAreRestoredAfterARestart) {
  auto s = station();
  CheckRequest post = request("post", kNow, CheckKind::FixturePostCalibration);
  post.verifies_correction_of = "pre";
  EXPECT_FALSE(s->on_request(post, "", kNow));  // waits: the sender keeps it
  EXPECT_FALSE(s->on_request(post, "", kNow));  // sent again while it waits
  EXPECT_TRUE(s->on_request(request("r1"), "", kNow));
  EXPECT_TRUE(s->on_request(request("r1"), "", kNow));  // sent again: already settled

  Compensation c;
  c.machine_id = "m1";
  c.request_id = "pre";
  c.correction.target = "fixture:F1";
  c.correction.offsets = {{"C1R1.dz", 0.02, "mm"}};
  EXPECT_TRUE(s->on_compensation(c, kNow));
  EXPECT_EQ(recorder_.measured, (std::vector<std::string>{"r1", "post"}));
  EXPECT_TRUE(s->on_request(post, "", kNow));  // sent again once measured: settled

  s = station();  // a restart
  EXPECT_EQ(recorder_.restored, (std::vector<std::string>{"fixture:F1"}));
  EXPECT_TRUE(s->on_compensation(c, kNow));  // sent again: settled, not applied twice
  EXPECT_EQ(recorder_.applied, (std::vector<std::string>{"fixture:F1"}));
  CheckRequest post2 = post;
  post2.request_id = "post-2";
  EXPECT_TRUE(s->on_request(post2, "", kNow));
  EXPECT_EQ(recorder_.measured.back(), "post-2");

  StationOptions wall;
  wall.max_request_age_ns = 600 * kSecond;
  s = station(wall);
  EXPECT_TRUE(s->on_request(request("old", kNow - 601 * kSecond), "", kNow));  // history
  EXPECT_TRUE(s->on_request(request("old", kNow - 601 * kSecond), "", kNow));
  EXPECT_EQ(recorder_.measured.back(), "post-2");
}

// Instruments that measure outside the call (a control running a program): the request is not
// settled while it runs and a resend does not start it again; poll() brings the set back, which
// is recorded and published like any other, stamped with the instrument's time on a simulated
// clock; the request is settled when it is sent again. A set the instruments never were asked
// for is not published.
TEST_F(StationTest, AMeasurementHandedToAControlIsPublishedWhenItComesBack) {
  recorder_.asynchronous = true;
  StationOptions simulated;
  simulated.simulated_clock = true;
  auto s = station(simulated);
  const std::int64_t asked = kNow - 3600 * kSecond;
  EXPECT_FALSE(s->on_request(request("r1", asked), "", kNow));
  EXPECT_FALSE(s->on_request(request("r1", asked), "", kNow + kSecond));  // sent again
  EXPECT_FALSE(s->on_request(request("r2", asked), "", kNow));
  EXPECT_EQ(recorder_.measured, (std::vector<std::string>{"r1", "r2"}));
  EXPECT_EQ(s->running(), 2u);
  EXPECT_EQ(s->poll(kNow), 0u);
  EXPECT_TRUE(published_.empty());
  EXPECT_TRUE(state_->outbox_index().empty());

  recorder_.finished.push_back(unmeasured(request("r2", asked), kNow + 5 * kSecond, ""));
  recorder_.finished.push_back(unmeasured(request("stranger", asked), kNow, ""));
  EXPECT_EQ(s->poll(kNow + 6 * kSecond), 1u);
  ASSERT_EQ(published_.size(), 1u);
  EXPECT_EQ(published_[0].request_id, "r2");
  // Daily check 3 takes 6 minutes (the check-kind table), on the simulated clock.
  EXPECT_EQ(published_[0].time_ns, asked + 6 * 60 * kSecond);
  ASSERT_EQ(state_->outbox_index().size(), 1u);
  EXPECT_EQ(s->running(), 1u);
  EXPECT_TRUE(s->on_request(request("r2", asked), "", kNow));   // sent again: settled now
  EXPECT_FALSE(s->on_request(request("r1", asked), "", kNow));  // still running
  EXPECT_EQ(recorder_.measured, (std::vector<std::string>{"r1", "r2"}));

  // A restart while r1 runs: it was not performed, so it is handed over again.
  s = station(simulated);
  EXPECT_FALSE(s->on_request(request("r1", asked), "", kNow));
  EXPECT_TRUE(s->on_request(request("r2", asked), "", kNow));
  EXPECT_EQ(recorder_.measured, (std::vector<std::string>{"r1", "r2", "r1"}));
}

// Every set a station publishes carries its driver's origin, whatever the driver put in the set:
// measured at once, collected later from a control, or never measured (a malformed request).
TEST_F(StationTest, EverySetCarriesTheOriginItsDriverSays) {
  for (const DataOrigin origin : {DataOrigin::Simulated, DataOrigin::Measured}) {
    published_.clear();
    recorder_ = Recorder{};
    recorder_.origin = origin;
    const std::string tag(to_string(origin));
    auto s = station();
    s->on_request(request("now-" + tag), "", kNow);
    s->on_request(request("bad-" + tag), "kind out of range", kNow);
    recorder_.asynchronous = true;
    s->on_request(request("later-" + tag), "", kNow);
    MeasurementSet later = unmeasured(request("later-" + tag), kNow, "");
    ASSERT_EQ(later.origin, DataOrigin::Unknown);  // the driver did not say; the station does
    recorder_.finished.push_back(later);
    EXPECT_EQ(s->poll(kNow), 1u);
    ASSERT_EQ(published_.size(), 3u);
    for (const MeasurementSet& set : published_) {
      EXPECT_EQ(set.origin, origin) << set.request_id;
    }
  }
}

// The simulated instruments behind a station: the example machine's fixture and tracker
// measure their checks; a machine without those sections says so in the set.
TEST(SimulatedInstruments, EachKindGoesToItsInstrumentOrSaysWhyNot) {
  MachineConfig pm1 = load_machine_config(NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml");
  SimulatedInstruments full(pm1);
  for (const auto& row : check_kinds()) {
    CheckRequest r = request(std::string("r-") + std::string(row.name), kNow, row.kind);
    r.machine_id = "pm1";
    if (row.kind == CheckKind::FixturePostCalibration) continue;  // needs its pre-calibration's set
    if (row.kind == CheckKind::FixturePreCalibration)
      r.parameters.push_back({"fixture_configuration", 0, ""});
    const MeasurementSet set = full.measure(r, kNow).value();
    EXPECT_TRUE(set.error.empty()) << row.name << ": " << set.error;
    EXPECT_EQ(set.origin, DataOrigin::Simulated) << row.name;
    EXPECT_FALSE(set.touches.empty() && set.tracker_points.empty()) << row.name;
  }
  MachineConfig bare = pm1;
  bare.fixture.reset();
  bare.global_check.reset();
  SimulatedInstruments monument_only(bare);
  const MeasurementSet unmeasurable =
      monument_only.measure(request("f", kNow, CheckKind::FixturePreCalibration), kNow).value();
  EXPECT_EQ(unmeasurable.error, "machine 'pm1' has no fixture: section to probe");
  EXPECT_EQ(unmeasurable.origin, DataOrigin::Simulated);  // it still says it is the simulator's
  EXPECT_EQ(monument_only.measure(request("g", kNow, CheckKind::GlobalGrid), kNow)->error,
            "machine 'pm1' has no global_check: section for the laser tracker");
  Correction zero;
  zero.target = "fixture:UHF1";
  EXPECT_EQ(monument_only.apply(zero),
            "zero offsets for fixture:UHF1 but machine 'pm1' has no fixture");
  zero.target = "machine:work_offset";
  EXPECT_EQ(monument_only.apply(zero), "");  // not the instruments' to apply
}

}  // namespace
}  // namespace ncqual::acquisition
