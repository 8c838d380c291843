// SPDX-License-Identifier: Apache-2.0
// The control-files driver (ncqual/acquisition/control_files.hpp) against real folders, with a
// stand-in control (tests/support/control_emulator.hpp) that runs its programs on the simulator,
// and a simulated clock for the timeout:
//  - each dialect: the program is handed over, the results come back as the simulator's touches
//    (to the log's resolution), and both files go to the archive;
//  - results still being written are waited for; a log cut short, no log at all, or a malformed
//    line become a MeasurementSet with an error that names the file and what was found;
//  - what cannot be handed over (a tracker check, an outbox that is not there) says why at once;
//  - a fixture's zero offsets are written for its control unit.
#include "control_emulator.hpp"

#include "ncqual/acquisition/control_files.hpp"
#include "ncqual/acquisition/station.hpp"
#include "ncqual/sim/machine_simulator.hpp"
#include "ncqual/common/text.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace ncqual::acquisition {
namespace {
namespace fs = std::filesystem;

constexpr std::int64_t kSecond = 1'000'000'000;
constexpr std::int64_t kStart = 1'800'000'000 * kSecond;

class ControlFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ncqual-control-files-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "programs");
    fs::create_directories(dir_ / "results");
    machine_ = load_machine_config(NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml");
    machine_.simulator.errors.machine_shift_mm = Eigen::Vector3d(0.030, -0.020, 0.015);
    machine_.instrument.driver = InstrumentDriver::ControlFiles;
    machine_.instrument.outbox = (dir_ / "programs").string();
    machine_.instrument.inbox = (dir_ / "results").string();
    machine_.instrument.archive = (dir_ / "results" / "archive").string();
    machine_.instrument.timeout_s = 60;
  }
  void TearDown() override { fs::remove_all(dir_); }

  CheckRequest request(const std::string& id,
                       CheckKind kind = CheckKind::MonumentPositioning) const {
    CheckRequest r;
    r.machine_id = machine_.machine_id;
    r.request_id = id;
    r.kind = kind;
    r.requested_by = "test";
    r.time_ns = kStart;
    return r;
  }
  std::string results_path(const std::string& id) const {
    return (fs::path(machine_.instrument.inbox) /
            probing::results_file_name(id, machine_.instrument.dialect))
        .string();
  }
  // The simulator's own set for `id`: what the control's log must give back.
  MeasurementSet truth(const std::string& id, CheckKind kind = CheckKind::MonumentPositioning) {
    return SimulatedInstruments(machine_).measure(request(id, kind), kStart).value();
  }

  fs::path dir_;
  MachineConfig machine_;
  SimulatedClock clock_{kStart};
};

TEST_F(ControlFilesTest, EachDialectsResultsComeBackAsTheSimulatorsTouchesAndAreArchived) {
  for (ControlDialect d :
       {ControlDialect::LinuxCnc, ControlDialect::Fanuc, ControlDialect::GenericCsv}) {
    for (bool inch : {false, true}) {
      machine_.instrument.dialect = d;
      machine_.probing.inch = inch;
      const std::string id = "pm1-" + std::string(to_string(d)) + (inch ? "-in" : "-mm");
      ControlFilesInstruments control(machine_, clock_, "ncqual test");
      ASSERT_FALSE(control.measure(request(id), kStart).has_value()) << "handed over";
      const fs::path program =
          fs::path(machine_.instrument.outbox) / probing::program_file_name(id, d);
      ASSERT_TRUE(fs::exists(program)) << program;
      EXPECT_TRUE(control.poll().empty()) << "nothing back yet";

      EXPECT_EQ(testing::answer_programs(machine_, kStart), std::vector<std::string>{id});
      clock_.advance_ns(kSecond);
      const auto back = control.poll();
      ASSERT_EQ(back.size(), 1u) << to_string(d);
      const MeasurementSet& set = back[0];
      EXPECT_EQ(set.error, "");
      EXPECT_EQ(set.request_id, id);
      // The control's probe touched the machine: measured, whatever ran behind the files here.
      EXPECT_EQ(set.origin, DataOrigin::Measured);
      EXPECT_EQ(control.origin(), DataOrigin::Measured);
      const MeasurementSet expected = truth(id);
      EXPECT_EQ(expected.origin, DataOrigin::Simulated);
      ASSERT_EQ(set.touches.size(), expected.touches.size());
      // The log's resolution: 6 decimals, Fanuc's 4 of mm or 5 of inch.
      const double resolution = d == ControlDialect::Fanuc ? (inch ? 0.5e-5 * 25.4 : 0.5e-4)
                                                           : (inch ? 0.5e-6 * 25.4 : 0.5e-6);
      for (std::size_t i = 0; i < set.touches.size(); ++i) {
        EXPECT_EQ(set.touches[i].feature, expected.touches[i].feature);
        EXPECT_NEAR(set.touches[i].axes.x_mm, expected.touches[i].axes.x_mm, resolution * 1.01);
        EXPECT_NEAR(set.touches[i].axes.y_mm, expected.touches[i].axes.y_mm, resolution * 1.01);
        EXPECT_NEAR(set.touches[i].axes.z_mm, expected.touches[i].axes.z_mm, resolution * 1.01);
      }
      EXPECT_FALSE(fs::exists(program)) << "the program leaves the outbox";
      EXPECT_FALSE(fs::exists(results_path(id)));
      EXPECT_TRUE(fs::exists(fs::path(machine_.instrument.archive) / program.filename()));
      EXPECT_TRUE(fs::exists(fs::path(machine_.instrument.archive) /
                             fs::path(results_path(id)).filename()));
      EXPECT_EQ(control.running(), 0u);
      EXPECT_TRUE(control.poll().empty()) << "each set comes back once";
    }
  }
}

TEST_F(ControlFilesTest, ALogCutShortIsAwaitedUntilTheTimeoutThenSaysWhatWasFound) {
  machine_.instrument.dialect = ControlDialect::Fanuc;
  ControlFilesInstruments control(machine_, clock_, "ncqual test");
  ASSERT_FALSE(control.measure(request("short"), kStart));
  const MeasurementSet expected = truth("short");
  const std::string log =
      testing::control_log(ControlDialect::Fanuc, "short", expected.touches, machine_);
  // The header and two touches, and half of the third line: the control is still probing.
  std::size_t cut = 0;
  for (int lines = 0; lines < 3; ++lines) cut = log.find('\n', cut) + 1;
  std::ofstream(results_path("short"), std::ios::binary) << log.substr(0, cut + 5);
  clock_.advance_ns(59 * kSecond);
  EXPECT_TRUE(control.poll().empty()) << "before the timeout it waits";
  clock_.advance_ns(kSecond);
  const auto back = control.poll();
  ASSERT_EQ(back.size(), 1u);
  const std::string& error = back[0].error;
  EXPECT_NE(error.find(results_path("short")), std::string::npos) << error;
  EXPECT_NE(error.find("expected " + std::to_string(expected.touches.size()) + " touches, found 2"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("the first missing is touch 3"), std::string::npos) << error;
  EXPECT_NE(error.find("after 60 s"), std::string::npos) << error;
  EXPECT_TRUE(back[0].touches.empty());
  EXPECT_TRUE(fs::exists(fs::path(machine_.instrument.archive) /
                         fs::path(results_path("short")).filename()))
      << "what came back is kept";
}

TEST_F(ControlFilesTest, NoResultsAtAllTimeOutNamingTheFileAndTheProgram) {
  ControlFilesInstruments control(machine_, clock_, "ncqual test");
  ASSERT_FALSE(control.measure(request("silent"), kStart));
  clock_.advance_ns(60 * kSecond);
  const auto back = control.poll();
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].error,
            "no results from the control after 60 s: " + results_path("silent") +
                " was not written (program " +
                (fs::path(machine_.instrument.outbox) / "ncqual-silent.ngc").string() + ")");
}

TEST_F(ControlFilesTest, AMalformedLineIsAnErrorAtOnceNamingFileLineAndValue) {
  machine_.instrument.dialect = ControlDialect::GenericCsv;
  ControlFilesInstruments control(machine_, clock_, "ncqual test");
  ASSERT_FALSE(control.measure(request("bad"), kStart));
  std::ofstream(results_path("bad"), std::ios::binary)
      << "# request bad\ntouch,x,y,z\n1,1227.0,800.0,495.0\n2,1200.0,8o7.0,495.0\n";
  const auto back = control.poll();
  ASSERT_EQ(back.size(), 1u);
  EXPECT_NE(back[0].error.find(results_path("bad") + ":4:"), std::string::npos) << back[0].error;
  EXPECT_NE(back[0].error.find("8o7.0"), std::string::npos) << back[0].error;
}

// A restarted acquisition hands the program over again; results the control wrote meanwhile are
// taken at the first look.
TEST_F(ControlFilesTest, ResultsWrittenWhileTheAcquisitionWasDownAreTaken) {
  {
    ControlFilesInstruments before(machine_, clock_, "ncqual test");
    ASSERT_FALSE(before.measure(request("r"), kStart));
  }
  EXPECT_EQ(testing::answer_programs(machine_, kStart), std::vector<std::string>{"r"});
  ControlFilesInstruments after(machine_, clock_, "ncqual test");
  ASSERT_FALSE(after.measure(request("r"), kStart));
  const auto back = after.poll();
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].error, "");
  EXPECT_EQ(back[0].touches.size(), truth("r").touches.size());
}

TEST_F(ControlFilesTest, WhatCannotBeHandedOverSaysWhyAtOnce) {
  ControlFilesInstruments control(machine_, clock_, "ncqual test");
  const auto grid = control.measure(request("g", CheckKind::GlobalGrid), kStart);
  ASSERT_TRUE(grid.has_value());
  EXPECT_NE(grid->error.find("the control-files driver cannot hand this check to the control"),
            std::string::npos)
      << grid->error;
  machine_.instrument.outbox = (dir_ / "no-such-share").string();
  ControlFilesInstruments unreachable(machine_, clock_, "ncqual test");
  const auto set = unreachable.measure(request("u"), kStart);
  ASSERT_TRUE(set.has_value());
  EXPECT_NE(
      set->error.find(machine_.instrument.outbox + "/ncqual-u.ngc: No such file or directory"),
      std::string::npos)
      << set->error;
  EXPECT_EQ(control.running(), 0u);
  EXPECT_EQ(unreachable.running(), 0u);
}

TEST_F(ControlFilesTest, AFixturesZeroOffsetsAreWrittenForItsControlUnit) {
  ControlFilesInstruments control(machine_, clock_, "ncqual test");
  Correction c;
  c.target = "fixture:UHF1";
  c.offsets = {{"C1R1.dz", 0.0213, "mm"}, {"C2R1.dx", -0.004, "mm"}};
  EXPECT_EQ(control.apply(c), "");
  std::string why;
  const auto text = read_text_file(
      (fs::path(machine_.instrument.outbox) / "fixture-UHF1-zero-offsets.txt").string(), &why);
  ASSERT_TRUE(text) << why;
  EXPECT_NE(text->find("C1R1.dz 0.021300\nC2R1.dx -0.004000\n"), std::string::npos) << *text;
  c.target = "machine:work_offset";
  EXPECT_EQ(control.apply(c), "");  // the control's own
}

// The control-files driver behind a station, as the service runs it: the request is handed
// over, and the set published once the control answered, stamped when the results came.
TEST_F(ControlFilesTest, BehindAStationTheSetIsPublishedWhenTheControlAnswered) {
  const fs::path state_path = dir_ / "state.db";
  storage::StateFile state = storage::StateFile::open(state_path.string());
  PerformedRequests performed(state, machine_.machine_id);
  std::vector<MeasurementSet> published;
  Station station(machine_.machine_id, make_instruments(machine_, clock_, "ncqual test"),
                  std::move(performed), StationOptions{}, [&](const MeasurementSet& set) {
                    published.push_back(set);
                    return true;
                  });
  EXPECT_FALSE(station.on_request(request("s"), "", kStart));
  EXPECT_EQ(station.poll(kStart), 0u);
  testing::answer_programs(machine_, kStart);
  clock_.advance_ns(3 * kSecond);
  EXPECT_EQ(station.poll(clock_.now_ns()), 1u);
  ASSERT_EQ(published.size(), 1u);
  EXPECT_EQ(published[0].time_ns, kStart + 3 * kSecond);
  EXPECT_EQ(published[0].error, "");
  EXPECT_TRUE(station.on_request(request("s"), "", clock_.now_ns()));
}

}  // namespace
}  // namespace ncqual::acquisition
