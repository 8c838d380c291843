// SPDX-License-Identifier: Apache-2.0
// A real controller: LinuxCNC 2.9 (Debian's linuxcnc-uspace) runs ncqual's probing program for
// the daily check 3 through the control-files driver, end to end across processes.
//
// The LinuxCNC side (tests/linuxcnc/): a three-axis mill with its motion looped back in HAL, no
// GUI (the DISPLAY program is a stand-in operator, lcnc_operator.py, that switches the machine
// on, homes it, runs each program that appears in the outbox in AUTO and moves LinuxCNC's probe
// log into the inbox), and a touch probe made of LinuxCNC's own real-time comparators (probe.hal)
// that trips motion.probe-input where the true stylus ball meets the true monument: the machine
// shift and the probe come from the machine config's simulator section, as the simulator uses
// them. G38.2 stops and latches the position; (PROBEOPEN) .. (PROBECLOSE) writes the log.
//
// The ncqual side: historian, solver, acquisition (instrument: control-files, dialect linuxcnc)
// and scheduler, as a plant runs them. The stored result must find the injected shift.
//
// Where LinuxCNC is not installed, or its real-time layer cannot start on this machine, the test
// is skipped with LinuxCNC's own messages; the recorded LinuxCNC logs in tests/data/linuxcnc
// (ProbingProgram.RecordedLinuxCncLogsGiveTheInjectedShift) keep the log path covered.
#include "harness.hpp"

#include "ncqual/common/config.hpp"
#include "ncqual/sim/machine_simulator.hpp"
#include "ncqual/common/text.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace ncqual::testing {
namespace {

const std::string kLinuxCncDir = NCQUAL_SOURCE_DIR "/tests/linuxcnc";

// The test machine: pm1's probe and a small bore (12 mm: short probing moves at a slow feed, so
// that the 1 ms servo period moves the latched position by at most 1 um), shifted by a known
// error; measured by LinuxCNC through folders.
std::string machine_text(const fs::path& dir) {
  return "machine_id: lc1\n"
         "probe: {tool_length_mm: 350.0, ball_radius_mm: 3.0}\n"
         "monument: {hole_center_mm: [1200.0, 800.0], hole_diameter_mm: 12.0, face_z_mm: 150.0,\n"
         "           probe_depth_mm: 5.0, gauge_width_mm: 200.0}\n"
         "tolerances: {center_dx_mm: 0.025, center_dy_mm: 0.025, face_dz_mm: 0.025}\n"
         "probing: {clearance_mm: 2, overtravel_mm: 2, probe_feed_mm_per_min: 60,\n"
         "          approach_feed_mm_per_min: 3000}\n"
         "instrument: {driver: control-files, dialect: linuxcnc, outbox: " +
         (dir / "programs").string() + ", inbox: " + (dir / "results").string() +
         ", timeout_s: 300}\n"
         "simulator:\n  seed: 5\n  errors:\n    machine_shift_mm: [0.041, -0.029, 0.033]\n"
         "    monument_shift_mm: [0.004, 0.002, -0.003]\n";
}

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (auto at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

std::string number(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.9f", v);
  return buffer;
}

std::string read_or_empty(const fs::path& path) {
  std::string why;
  return read_text_file(path.string(), &why).value_or("");
}

// probe.hal from the simulator's truth: with the head at home the true ball centre is the axis
// readouts plus a constant, which is also where the simulator puts it.
std::string probe_hal(const MachineConfig& machine) {
  const sim::MachineSimulator simulator(machine, machine.simulator);
  const Eigen::Vector3d k = simulator.true_ball_centre(AxisPosition{});
  const sim::RingGaugePlate& monument = simulator.true_monument();
  const double r = simulator.true_probe().ball_radius_mm;
  const double big_r = monument.hole_radius_mm;
  std::string text = read_or_empty(kLinuxCncDir + "/probe.hal.in");
  text = replace_all(text, "@DX_OFFSET@", number(k.x() - monument.hole_centre_mm.x()));
  text = replace_all(text, "@DY_OFFSET@", number(k.y() - monument.hole_centre_mm.y()));
  text = replace_all(text, "@BZ_OFFSET@", number(k.z()));
  text = replace_all(text, "@R_MINUS_r@", number(big_r - r));
  text = replace_all(text, "@R_PLUS_r@", number(big_r + r));
  text = replace_all(text, "@FACE_Z_PLUS_r@", number(monument.face_z_mm + r));
  text = replace_all(text, "@FACE_Z@", number(monument.face_z_mm));
  return text;
}

// The environment LinuxCNC's real-time layer needs when run as root (the build machines and CI
// run as root): rtapi_app refuses root without a fallback user and puts its socket where that
// user can write.
Launch with_rtapi_environment(Launch launch, const fs::path& dir) {
  const fs::path fifo = dir / "rtapi";
  fs::create_directories(fifo);
  ::chmod(fifo.c_str(), 0777);
  fs::create_directories(dir / "home");
  return launch.with_env("RTAPI_UID", "65534")
      .with_env("RTAPI_FIFO_PATH", (fifo / "rtapi_fifo").string())
      .with_env("HOME", (dir / "home").string());  // where LinuxCNC copies its logs on failure
}

// Why LinuxCNC cannot run here ("" when it can): not installed, or its real-time layer does
// not start (halrun with one real-time module and thread), in LinuxCNC's own words.
std::string linuxcnc_unavailable(const fs::path& dir) {
  if (std::system("command -v linuxcnc >/dev/null 2>&1 && command -v halrun >/dev/null 2>&1") !=
      0) {
    return "LinuxCNC is not installed (Debian's linuxcnc-uspace; deploy/install-deps.sh --test "
           "installs it)";
  }
  fs::create_directories(dir);
  const fs::path hal = dir / "preflight.hal";
  std::ofstream(hal) << "loadrt threads name1=preflight period1=1000000\nstart\nstop\n";
  Process preflight(
      with_rtapi_environment(Launch({"halrun", "-f", hal.string()}, Output::Merged), dir));
  if (!preflight.wait_for(std::chrono::seconds(60))) {
    preflight.kill();
    preflight.wait();
    return "LinuxCNC's real-time layer did not start within 60 s (halrun -f preflight.hal)";
  }
  if (preflight.wait() != 0) {
    return "LinuxCNC's real-time layer does not start on this machine (halrun -f "
           "preflight.hal):\n" +
           preflight.out();
  }
  return "";
}

TEST(LinuxCnc, ADailyCheckRunsOnLinuxCncThroughTheControlFilesDriver) {
  Plant plant("linuxcnc", TestDomain::LinuxCnc);
  const fs::path cell = plant.dir() / "cell";
  if (const std::string why = linuxcnc_unavailable(cell); !why.empty()) {
    GTEST_SKIP() << why;
  }
  for (const char* folder : {"programs", "results", "linuxcnc"}) {
    fs::create_directories(cell / folder);
  }
  const std::string machine_file = plant.add_machine("lc1", machine_text(cell));
  const MachineConfig machine = load_machine_config(machine_file);

  // The LinuxCNC configuration: the INI with the operator's path, the HAL files, a tool table.
  const fs::path config = cell / "linuxcnc";
  std::ofstream(config / "ncqual-sim.ini")
      << replace_all(read_or_empty(kLinuxCncDir + "/ncqual-sim.ini.in"), "@OPERATOR@",
                     kLinuxCncDir + "/lcnc_operator.py");
  fs::copy_file(kLinuxCncDir + "/core.hal", config / "core.hal");
  std::ofstream(config / "probe.hal") << probe_hal(machine);
  std::ofstream(config / "ncqual.tbl") << "";

  plant.write_plant();
  plant.start("historian");
  plant.start("solver");
  plant.start("acquisition", {"--all"});
  plant.start("scheduler");

  const fs::path operator_log = cell / "operator.log";
  Process linuxcnc(
      with_rtapi_environment(Launch({"linuxcnc", (config / "ncqual-sim.ini").string()})
                                 .in(config.string())
                                 .with_env("NCQUAL_OUTBOX", (cell / "programs").string())
                                 .with_env("NCQUAL_INBOX", (cell / "results").string())
                                 .with_env("NCQUAL_PROGRAMS", "1")
                                 .with_env("NCQUAL_DEADLINE_S", "240")
                                 .with_env("NCQUAL_OPERATOR_LOG", operator_log.string())
                                 .log_to((cell / "linuxcnc.log").string()),
                             cell));
  const auto linuxcnc_said = [&] {
    return "operator:\n" + read_or_empty(operator_log) + "linuxcnc:\n" +
           read_or_empty(cell / "linuxcnc.log") + "LinuxCNC's debug file:\n" +
           read_or_empty(cell / "home" / "linuxcnc_debug.txt") + "acquisition:\n" +
           plant.log("acquisition");
  };
  ASSERT_TRUE(linuxcnc.wait_for(std::chrono::seconds(300))) << linuxcnc_said();
  ASSERT_EQ(linuxcnc.wait(), 0) << linuxcnc_said();
  const std::string said = read_or_empty(operator_log);
  EXPECT_NE(said.find("machine on and homed"), std::string::npos) << said;
  EXPECT_NE(said.find("1 program(s) run"), std::string::npos) << said;

  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) {
    storage::HistoryQuery q;
    q.machine_id = "lc1";
    const auto records = db.history(q);
    return !records.empty() && records.front().result.has_value();
  })) << linuxcnc_said();
  auto db = storage::Database::open_readonly(plant.db_path());
  storage::HistoryQuery q;
  q.machine_id = "lc1";
  const auto record = db.history(q).front();
  const CheckResult& result = *record.result;
  EXPECT_EQ(result.verdict, Verdict::Fail) << result.reason;
  const auto set = db.load_measurement_set(record.request_id);
  ASSERT_TRUE(set);
  EXPECT_EQ(set->error, "");
  EXPECT_EQ(set->touches.size(), 5u);
  // Check 3 sees the monument relative to the machine. The probe trips at most one servo period
  // (1 ms at 1 mm/s: 1 um) past the contact; opposite bore touches cancel that in the centre.
  const auto& truth = machine.simulator.errors;
  const Eigen::Vector3d expected = truth.monument_shift_mm - truth.machine_shift_mm;
  EXPECT_NEAR(find_metric(result, "center_dx_mm")->value, expected.x(), 0.0006);
  EXPECT_NEAR(find_metric(result, "center_dy_mm")->value, expected.y(), 0.0006);
  EXPECT_NEAR(find_metric(result, "face_dz_mm")->value, expected.z(), 0.0015);
  std::cerr << "LinuxCNC measured center_dx " << find_metric(result, "center_dx_mm")->value
            << ", center_dy " << find_metric(result, "center_dy_mm")->value << ", face_dz "
            << find_metric(result, "face_dz_mm")->value << " mm (injected " << expected.x() << ", "
            << expected.y() << ", " << expected.z() << ")\n";
  // The program and LinuxCNC's own log, as it wrote it, are in the archive.
  const fs::path archive = cell / "results" / "archive";
  EXPECT_TRUE(fs::exists(archive / ("ncqual-" + record.request_id + ".ngc")));
  EXPECT_TRUE(fs::exists(archive / ("ncqual-" + record.request_id + ".txt")));
}

}  // namespace
}  // namespace ncqual::testing
