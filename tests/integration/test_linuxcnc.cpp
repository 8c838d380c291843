// SPDX-License-Identifier: Apache-2.0
// A real controller: LinuxCNC 2.9 (Debian's linuxcnc-uspace) runs ncqual's probing programs.
//
// The LinuxCNC side (tests/linuxcnc/): a post mill with ncqual's axes X, Y, Z, A, C and W, its
// motion looped back in HAL, no GUI (the DISPLAY program is a stand-in operator,
// lcnc_operator.py, that switches the machine on, homes it, runs each program that appears in the
// outbox in AUTO and moves LinuxCNC's probe log into the inbox), and a touch probe made of
// LinuxCNC's own real-time comparators (probe.hal) that trips motion.probe-input where the true
// stylus ball overlaps the true monument; the ball is placed by the wrist (ncqual_wrist.py, a
// userspace HAL component with the kinematics written again in Python) from A, C and W. The
// machine's and the probe's errors come from the machine config's simulator section, as the
// simulator uses them. G38.2 stops and latches the position; (PROBEOPEN) .. (PROBECLOSE) writes
// the log.
//
//  - ADailyCheckRunsOnLinuxCncThroughTheControlFilesDriver: historian, solver, acquisition
//    (instrument: control-files, dialect linuxcnc) and scheduler, as a plant runs them; the stored
//    result must find the injected shift.
//  - EveryDailyProgramLandsOnItsFeaturesFromAnyStartState: the four daily probe checks' programs,
//    run one after the other (each from the state the one before left) and again each after a
//    program that turns A, C and W to random positions: every touch must land where the
//    simulator's true machine puts it, in both runs.
//
// Where LinuxCNC is not installed, or its real-time layer cannot start on this machine, the tests
// are skipped with LinuxCNC's own messages; the recorded LinuxCNC logs in tests/data/linuxcnc
// (ProbingProgram.RecordedLinuxCncLogsGiveTheInjectedShift) keep the log path covered.
#include "harness.hpp"

#include "ncqual/common/config.hpp"
#include "ncqual/common/text.hpp"
#include "ncqual/common/units.hpp"
#include "ncqual/probing/plan.hpp"
#include "ncqual/probing/program.hpp"
#include "ncqual/sim/machine_simulator.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <random>
#include <map>
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

// probe.hal from the simulator's truth: the wrist's true probe and angle errors, the machine's
// shift and the true monument.
std::string probe_hal(const MachineConfig& machine) {
  const sim::MachineSimulator simulator(machine, machine.simulator);
  const ProbeGeometry& probe = simulator.true_probe();
  const sim::RingGaugePlate& monument = simulator.true_monument();
  const auto& errors = machine.simulator.errors;
  const double r = probe.ball_radius_mm;
  const double half = std::isfinite(monument.half_width_mm()) ? monument.half_width_mm() : 1e6;
  std::string text = read_or_empty(kLinuxCncDir + "/probe.hal.in");
  text = replace_all(text, "@WRIST@", kLinuxCncDir + "/ncqual_wrist.py");
  text = replace_all(text, "@OX@", number(probe.stylus_offset_mm.x()));
  text = replace_all(text, "@OY@", number(probe.stylus_offset_mm.y()));
  text = replace_all(text, "@LENGTH@", number(probe.tool_length_mm));
  text = replace_all(text, "@DA@", number(errors.a_home_error_rad));
  text = replace_all(text, "@DC@", number(errors.c_angle_error_rad));
  text = replace_all(text, "@DX_OFFSET@",
                     number(errors.machine_shift_mm.x() - monument.hole_centre_mm.x()));
  text = replace_all(text, "@DY_OFFSET@",
                     number(errors.machine_shift_mm.y() - monument.hole_centre_mm.y()));
  text = replace_all(text, "@BZ_OFFSET@", number(errors.machine_shift_mm.z()));
  text = replace_all(text, "@FACE_Z_PLUS_r@", number(monument.face_z_mm + r));
  text = replace_all(text, "@UNDERSIDE_Z_MINUS_r@", number(monument.underside_z_mm() - r));
  text = replace_all(text, "@HALF_PLUS_r@", number(half + r));
  text = replace_all(text, "@R_MINUS_r@", number(monument.hole_radius_mm - r));
  return text;
}

// The LinuxCNC configuration in `config`: the INI with the operator's path, the HAL files, a tool
// table.
void write_linuxcnc_config(const fs::path& config, const MachineConfig& machine) {
  fs::create_directories(config);
  std::ofstream(config / "ncqual-sim.ini")
      << replace_all(read_or_empty(kLinuxCncDir + "/ncqual-sim.ini.in"), "@OPERATOR@",
                     kLinuxCncDir + "/lcnc_operator.py");
  fs::copy_file(kLinuxCncDir + "/core.hal", config / "core.hal");
  std::ofstream(config / "probe.hal") << probe_hal(machine);
  std::ofstream(config / "ncqual.tbl") << "";
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

// LinuxCNC with the configuration in `cell`/linuxcnc and its stand-in operator, which runs the
// first `programs` programs of `cell`/programs, moves their logs to `cell`/results and ends
// within `deadline_s`; its operator log is `cell`/operator.log, its output `cell`/linuxcnc.log.
Launch linuxcnc_launch(const fs::path& cell, int programs, int deadline_s) {
  const fs::path config = cell / "linuxcnc";
  return with_rtapi_environment(
      Launch({"linuxcnc", (config / "ncqual-sim.ini").string()})
          .in(config.string())
          .with_env("NCQUAL_OUTBOX", (cell / "programs").string())
          .with_env("NCQUAL_INBOX", (cell / "results").string())
          .with_env("NCQUAL_PROGRAMS", std::to_string(programs))
          .with_env("NCQUAL_DEADLINE_S", std::to_string(deadline_s))
          .with_env("NCQUAL_OPERATOR_LOG", (cell / "operator.log").string())
          .log_to((cell / "linuxcnc.log").string()),
      cell);
}

TEST(LinuxCnc, ADailyCheckRunsOnLinuxCncThroughTheControlFilesDriver) {
  Plant plant("linuxcnc", TestDomain::LinuxCnc);
  const fs::path cell = plant.dir() / "cell";
  if (const std::string why = linuxcnc_unavailable(cell); !why.empty()) {
    GTEST_SKIP() << why;
  }
  for (const char* folder : {"programs", "results"}) {
    fs::create_directories(cell / folder);
  }
  const std::string machine_file = plant.add_machine("lc1", machine_text(cell));
  const MachineConfig machine = load_machine_config(machine_file);

  write_linuxcnc_config(cell / "linuxcnc", machine);

  plant.write_plant();
  plant.start("historian");
  plant.start("solver");
  plant.start("acquisition", {"--all"});
  plant.start("scheduler");

  const fs::path operator_log = cell / "operator.log";
  Process linuxcnc(linuxcnc_launch(cell, 1, 240));
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

// The four daily probe checks' machine: lc1's monument with its outer edges in reach (the tool
// length and C-rotation checks touch them with the probe horizontal), a probe with a stylus
// offset, and every error the wrist can have, so that a touch taken with a head the program did not
// command lands somewhere else.
std::string daily_machine_text() {
  return "machine_id: lc2\n"
         "probe: {tool_length_mm: 350.0, ball_radius_mm: 3.0}\n"
         "monument: {hole_center_mm: [1200.0, 800.0], hole_diameter_mm: 12.0, face_z_mm: 150.0,\n"
         "           probe_depth_mm: 5.0, gauge_width_mm: 200.0, hole_touches: 4}\n"
         "tolerances: {center_dx_mm: 0.025, center_dy_mm: 0.025, face_dz_mm: 0.025}\n"
         "probing: {clearance_mm: 2, overtravel_mm: 2, probe_feed_mm_per_min: 60,\n"
         "          approach_feed_mm_per_min: 3000, retract_z_mm: 1000}\n"
         "simulator:\n  seed: 7\n  errors:\n    machine_shift_mm: [0.041, -0.029, 0.033]\n"
         "    monument_shift_mm: [0.004, 0.002, -0.003]\n"
         "    stylus_offset_mm: [0.012, -0.008]\n    tool_length_error_mm: 0.021\n"
         "    c_angle_error_rad: 0.00015\n    a_home_error_rad: -0.0001\n";
}

// A program that leaves A, C and W where a previous job might have: random, seeded.
std::string disturbing_program(std::mt19937& random) {
  std::uniform_real_distribution<double> a(-90, 90), c(-180, 180), w(-20, 20);
  char text[160];
  std::snprintf(text, sizeof text,
                "(a previous job's head)\nG21 G90\nG53 G0 A%.3f C%.3f W%.3f\nM2\n", a(random),
                c(random), w(random));
  return text;
}

TEST(LinuxCnc, EveryDailyProgramLandsOnItsFeaturesFromAnyStartState) {
  Plant plant("linuxcnc-daily", TestDomain::LinuxCnc);
  const fs::path cell = plant.dir() / "cell";
  if (const std::string why = linuxcnc_unavailable(cell); !why.empty()) {
    GTEST_SKIP() << why;
  }
  for (const char* folder : {"programs", "results"}) fs::create_directories(cell / folder);
  const MachineConfig machine = load_machine_config(plant.add_machine("lc2", daily_machine_text()));
  write_linuxcnc_config(cell / "linuxcnc", machine);

  // The daily checks in the calendar's order, each run twice: first one after the other, then each
  // after a program that turns the head at random (the seed is printed on failure).
  const CheckKind daily[] = {CheckKind::MonumentCAlignment, CheckKind::MonumentToolLength,
                             CheckKind::MonumentCRotation, CheckKind::MonumentPositioning};
  const unsigned seed = std::random_device{}();
  std::mt19937 random(seed);
  std::vector<std::pair<CheckRequest, fs::path>> programs;  // each check's request and program
  int file = 0;
  const auto next_file = [&] {
    char name[32];
    std::snprintf(name, sizeof name, "ncqual-%02d.ngc", ++file);
    return cell / "programs" / name;
  };
  for (const char* run : {"after", "random"}) {
    for (CheckKind kind : daily) {
      if (std::string(run) == "random") std::ofstream(next_file()) << disturbing_program(random);
      CheckRequest r;
      r.machine_id = machine.machine_id;
      r.request_id = std::string(run) + "-" + std::string(to_string(kind));
      r.kind = kind;
      const fs::path path = next_file();
      std::ofstream(path) << probing::write_program(r, machine, probing::Dialect::LinuxCnc,
                                                    "ncqual test");
      programs.emplace_back(r, path);
    }
  }

  const fs::path operator_log = cell / "operator.log";
  Process linuxcnc(linuxcnc_launch(cell, file, 330));
  const auto linuxcnc_said = [&] {
    return "seed " + std::to_string(seed) + "\noperator:\n" + read_or_empty(operator_log) +
           "linuxcnc:\n" + read_or_empty(cell / "linuxcnc.log");
  };
  ASSERT_TRUE(linuxcnc.wait_for(std::chrono::seconds(360))) << linuxcnc_said();
  ASSERT_EQ(linuxcnc.wait(), 0) << linuxcnc_said();

  // Each touch against the simulator's true machine (noise-free) and against the same touch of
  // the other run: LinuxCNC latches at most one servo period (1 ms at 1 mm/s) past the contact.
  const sim::MachineSimulator simulator(machine, machine.simulator);
  std::map<std::string, std::vector<Touch>> measured;
  double worst_against_truth = 0, worst_between_runs = 0;
  for (const auto& [r, path] : programs) {
    SCOPED_TRACE(r.request_id + ", seed " + std::to_string(seed));
    const probing::ProgramDescription program =
        probing::read_program(read_or_empty(path), path.string());
    const fs::path log_file = cell / "results" / program.results_file;
    ASSERT_TRUE(fs::exists(log_file)) << linuxcnc_said();
    MeasurementSet set;
    try {
      set = probing::measurement_set_from_log(
          program,
          probing::read_touch_log(read_or_empty(log_file), log_file.string(),
                                  probing::Dialect::LinuxCnc),
          log_file.string(), machine, 1);
    } catch (const probing::ProgramError& e) {
      FAIL() << e.what() << "\n" << linuxcnc_said();
    }
    const probing::TouchPlan plan = probing::touch_plan(r, machine);
    ASSERT_EQ(set.touches.size(), plan.moves.size());
    for (std::size_t i = 0; i < plan.moves.size(); ++i) {
      std::string why;
      const auto truth = simulator.execute(plan.moves[i], 0.0, &why);
      ASSERT_TRUE(truth) << why;
      const Touch& got = set.touches[i];
      const Eigen::Vector3d at(got.axes.x_mm, got.axes.y_mm, got.axes.z_mm);
      const Eigen::Vector3d expected(truth->axes.x_mm, truth->axes.y_mm, truth->axes.z_mm);
      worst_against_truth = std::max(worst_against_truth, (at - expected).norm());
      EXPECT_LT((at - expected).norm(), 0.0015)
          << "touch " << i + 1 << " (" << plan.moves[i].feature << ") at " << at.transpose()
          << ", the true machine's contact " << expected.transpose();
    }
    measured[r.request_id] = set.touches;
  }
  for (CheckKind kind : daily) {
    const auto& after = measured["after-" + std::string(to_string(kind))];
    const auto& turned = measured["random-" + std::string(to_string(kind))];
    ASSERT_EQ(after.size(), turned.size());
    for (std::size_t i = 0; i < after.size(); ++i) {
      const Eigen::Vector3d a(after[i].axes.x_mm, after[i].axes.y_mm, after[i].axes.z_mm);
      const Eigen::Vector3d b(turned[i].axes.x_mm, turned[i].axes.y_mm, turned[i].axes.z_mm);
      worst_between_runs = std::max(worst_between_runs, (a - b).norm());
      EXPECT_LT((a - b).norm(), 0.002)
          << to_string(kind) << " touch " << i + 1 << ", seed " << seed;
    }
  }
  std::cerr << "LinuxCNC's touches of the four daily checks, twice (seed " << seed << "): at most "
            << worst_against_truth * 1000 << " um from the true machine's contact, "
            << worst_between_runs * 1000 << " um between the two start states\n";
  const std::string said = read_or_empty(operator_log);
  EXPECT_NE(said.find(std::to_string(file) + " program(s) run\n"), std::string::npos) << said;
}

}  // namespace
}  // namespace ncqual::testing
