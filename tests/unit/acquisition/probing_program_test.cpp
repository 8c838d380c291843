// SPDX-License-Identifier: Apache-2.0
// Probing programs for real controls and their touch logs (ncqual/probing/program.hpp):
//  - the programs of pm1 in the three dialects are golden files (tests/data/programs/, reviewed
//    by eye; NCQUAL_UPDATE_GOLDEN=1 rewrites them);
//  - every program is parsed back here with a G-code reader of this test's own: each probing
//    move runs from its start to start + travel * direction of the touch plan;
//  - touch logs written as each control writes them (tests/support/control_emulator.hpp formats
//    them from the simulator's touches) give the same MeasurementSet, and so the same figures, as
//    the simulator's own set, and those figures find the injected truth;
//  - logs that do not belong to their program are refused saying why.
#include "control_emulator.hpp"

#include "ncqual/probing/plan.hpp"
#include "ncqual/probing/program.hpp"
#include "ncqual/probing/tracker_nominals.hpp"

#include "ncqual/sim/machine_simulator.hpp"
#include "ncqual/solver/instrument_files.hpp"
#include "ncqual/solver/solve.hpp"
#include "ncqual/common/csv.hpp"
#include "ncqual/common/global_check.hpp"
#include "ncqual/common/units.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>

namespace ncqual::probing {
namespace {

MachineConfig pm1() { return load_machine_config(NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml"); }

CheckRequest request(const MachineConfig& m, CheckKind kind, const std::string& id,
                     std::vector<NamedValue> parameters = {}) {
  CheckRequest r;
  r.machine_id = m.machine_id;
  r.request_id = id;
  r.kind = kind;
  r.requested_by = "test";
  r.parameters = std::move(parameters);
  return r;
}

const Dialect kDialects[] = {Dialect::LinuxCnc, Dialect::Fanuc, Dialect::GenericCsv};

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(ProbingProgram, GoldenProgramsOfTheDailyPositioningCheck) {
  const MachineConfig m = pm1();
  const CheckRequest r = request(m, CheckKind::MonumentPositioning, "pm1-golden-1");
  for (Dialect d : kDialects) {
    const std::string text = write_program(r, m, d, "ncqual test");
    const std::string path = std::string(NCQUAL_SOURCE_DIR "/tests/data/programs/pm1-") +
                             std::string(to_string(d)) + ".nc";
    if (std::getenv("NCQUAL_UPDATE_GOLDEN")) std::ofstream(path) << text;
    EXPECT_EQ(text, read_text(path)) << path << " (NCQUAL_UPDATE_GOLDEN=1 rewrites it)";
  }
}

// A G-code reader of this test's own: the X, Y, Z of every G38.2/G31 line and of the line's
// position before it (the modal position after the previous motion lines).
struct ProbingLine {
  Eigen::Vector3d from, to;
  std::string touch_comment;
};

std::vector<ProbingLine> probing_lines(const std::string& program) {
  std::vector<ProbingLine> out;
  Eigen::Vector3d at = Eigen::Vector3d::Constant(NAN);
  std::string last_comment;
  std::istringstream in(program);
  std::string line;
  const std::regex word(R"(([XYZ])(-?[0-9]*\.?[0-9]+))");
  while (std::getline(in, line)) {
    if (line.rfind("(NCQUAL TOUCH", 0) == 0 || line.rfind("(NCQUAL GUARD", 0) == 0) {
      last_comment = line;
    }
    // Comments, macro lines, LinuxCNC's O-words and the head's moves in machine coordinates (G53:
    // W, A, C and the first Z up) leave the program's X, Y, Z as they are.
    if (line.empty() || line[0] == '(' || line[0] == ' ' || line[0] == 'o' ||
        line.rfind("IF", 0) == 0 || line.rfind("DPRNT", 0) == 0 || line.rfind("G53", 0) == 0) {
      continue;
    }
    Eigen::Vector3d next = at;
    for (auto it = std::sregex_iterator(line.begin(), line.end(), word);
         it != std::sregex_iterator(); ++it) {
      next[(*it)[1].str()[0] - 'X'] = std::stod((*it)[2].str());
    }
    const bool guard = last_comment.rfind("(NCQUAL GUARD", 0) == 0;
    if (line.rfind("G38.2", 0) == 0 || (line.rfind("G31", 0) == 0 && !guard)) {
      out.push_back({at, next, last_comment});
    }
    if (line.rfind("G38.3", 0) == 0 || line.rfind("G31", 0) == 0) last_comment.clear();
    at = next;
  }
  return out;
}

// A request of every probe check of `m` (the four daily checks, the part set points and a
// fixture pre-calibration of configuration 3), their ids starting with `prefix`.
std::vector<CheckRequest> every_probe_check(const MachineConfig& m, const std::string& prefix) {
  std::vector<CheckRequest> requests;
  for (CheckKind k :
       {CheckKind::MonumentCAlignment, CheckKind::MonumentToolLength,
        CheckKind::MonumentPositioning, CheckKind::MonumentCRotation, CheckKind::PartSetPoints}) {
    requests.push_back(request(m, k, prefix + std::string(to_string(k))));
  }
  requests.push_back(request(m, CheckKind::FixturePreCalibration, prefix + "pre",
                             {{"fixture_configuration", 3, ""}}));
  return requests;
}

TEST(ProbingProgram, EveryProgramRunsThePlanAndDescribesItself) {
  MachineConfig m = pm1();
  ASSERT_TRUE(m.fixture);
  const std::vector<CheckRequest> requests = every_probe_check(m, "r-");
  for (bool inch : {false, true}) {
    m.probing.inch = inch;
    m.probing.work_offset_mm = inch ? Eigen::Vector3d(100, -200, 50) : Eigen::Vector3d::Zero();
    const double unit = inch ? 25.4 : 1;
    const double resolution = inch ? 0.5e-5 * 25.4 : 0.5e-4;
    for (const CheckRequest& r : requests) {
      const TouchPlan plan = touch_plan(r, m);
      ASSERT_EQ(plan.error, "");
      for (Dialect d : kDialects) {
        const std::string text = write_program(r, m, d, "ncqual test");
        SCOPED_TRACE(std::string(to_string(r.kind)) + " " + std::string(to_string(d)) +
                     (inch ? " inch" : " mm"));
        EXPECT_EQ(text.find("G10"), std::string::npos);
        EXPECT_EQ(text.find("G92"), std::string::npos);
        EXPECT_NE(text.find(inch ? "G20 " : "G21 "), std::string::npos);
        const ProgramDescription desc = read_program(text, "p.nc");
        EXPECT_EQ(desc.request_id, r.request_id);
        EXPECT_EQ(desc.kind, r.kind);
        EXPECT_EQ(desc.dialect, d);
        EXPECT_EQ(desc.parameters.size(), r.parameters.size());
        const auto lines = probing_lines(text);
        ASSERT_EQ(desc.touches.size(), plan.moves.size());
        ASSERT_EQ(lines.size(), plan.moves.size());
        for (std::size_t i = 0; i < plan.moves.size(); ++i) {
          const ProbingMove& p = plan.moves[i];
          EXPECT_EQ(desc.touches[i].feature, p.feature);
          EXPECT_LT((desc.touches[i].approach - p.direction).norm(), 1e-8);
          EXPECT_NEAR(desc.touches[i].a_rad, p.start.a_rad, 1e-6);
          EXPECT_NEAR(desc.touches[i].c_rad, p.start.c_rad, 1e-6);
          const Eigen::Vector3d start(p.start.x_mm, p.start.y_mm, p.start.z_mm);
          const Eigen::Vector3d from = lines[i].from * unit + m.probing.work_offset_mm;
          const Eigen::Vector3d to = lines[i].to * unit + m.probing.work_offset_mm;
          EXPECT_LT((from - start).cwiseAbs().maxCoeff(), resolution) << i;
          EXPECT_LT((to - (start + p.travel_mm * p.direction)).cwiseAbs().maxCoeff(), resolution)
              << i;
          EXPECT_NE(lines[i].touch_comment.find("TOUCH " + std::to_string(i + 1) + " "),
                    std::string::npos)
              << "the comment before the probing move names its touch";
        }
      }
    }
  }
}

// The head a program has commanded at each of its lines: the last G53 W, A and C words (NaN where
// none came yet).
struct HeadState {
  double w = NAN, a = NAN, c = NAN;
};

double word_value(const std::string& line, char letter) {
  const std::regex word(std::string(1, letter) + R"((-?[0-9]*\.?[0-9]+))");
  std::smatch m;
  return std::regex_search(line, m, word) ? std::stod(m[1].str()) : NAN;
}

// From any state the machine is in, every program first goes up to the retract Z in machine
// coordinates, then commands every head axis the control has (W, A, C) before it moves X or Y, and
// each touch is taken with the head its comment declares; every way down to a touch's start and
// up from it is a guarded move that stops the program on a contact (LinuxCNC: G38.3 and #5070
// with ABORT; Fanuc: G31 and its skip position with #3000), announced by (NCQUAL GUARD).
TEST(ProbingProgram, EveryProgramCommandsTheHeadFirstAndGuardsItsWaysDownAndUp) {
  MachineConfig m = pm1();
  const std::vector<CheckRequest> requests = every_probe_check(m, "h-");
  for (const CheckRequest& r : requests) {
    for (Dialect d : {Dialect::LinuxCnc, Dialect::Fanuc}) {
      SCOPED_TRACE(std::string(to_string(r.kind)) + " " + std::string(to_string(d)));
      const std::string text = write_program(r, m, d, "t");
      const ProgramDescription desc = read_program(text, "p.nc");
      std::istringstream in(text);
      std::string line, previous;
      HeadState head;
      bool moved_xy = false, first_motion = true;
      std::size_t touches = 0, guards = 0;
      while (std::getline(in, line)) {
        const bool motion = line.rfind("G0 ", 0) == 0 || line.rfind("G1 ", 0) == 0 ||
                            line.rfind("G53 ", 0) == 0 || line.rfind("G38", 0) == 0 ||
                            line.rfind("G31 ", 0) == 0;
        if (motion && first_motion) {
          EXPECT_EQ(line.rfind("G53 G0 Z", 0), 0u) << "the first move is up, in machine "
                                                      "coordinates: "
                                                   << line;
          first_motion = false;
        }
        if (line.rfind("G53", 0) == 0) {
          for (auto [letter, value] :
               {std::pair{'W', &head.w}, std::pair{'A', &head.a}, std::pair{'C', &head.c}}) {
            if (const double v = word_value(line, letter); !std::isnan(v)) *value = v;
          }
        }
        if (motion && line.rfind("G53", 0) != 0 &&
            (!std::isnan(word_value(line, 'X')) || !std::isnan(word_value(line, 'Y')))) {
          EXPECT_FALSE(std::isnan(head.w) || std::isnan(head.a) || std::isnan(head.c))
              << "X or Y moved before W, A and C were commanded: " << line;
          moved_xy = true;
        }
        if (line.rfind("(NCQUAL TOUCH", 0) == 0) {
          const ProgramTouch& t = desc.touches.at(touches++);
          EXPECT_NEAR(head.a, units::rad_to_deg(t.a_rad), 1e-4) << line;
          EXPECT_NEAR(head.c, units::rad_to_deg(t.c_rad), 1e-4) << line;
          EXPECT_NEAR(head.w, t.w_mm, 1e-4) << line;
        }
        if (line.rfind("(NCQUAL GUARD", 0) == 0) {
          ++guards;
          std::string move, check;
          ASSERT_TRUE(std::getline(in, move));
          ASSERT_TRUE(std::getline(in, check));
          if (d == Dialect::LinuxCnc) {
            EXPECT_EQ(move.rfind("G38.3 ", 0), 0u) << move;
            EXPECT_NE(check.find("if [#5070 NE 0]"), std::string::npos) << check;
            std::string abort;
            ASSERT_TRUE(std::getline(in, abort));
            EXPECT_NE(abort.find("(ABORT, NCQUAL contact"), std::string::npos) << abort;
          } else {
            EXPECT_EQ(move.rfind("G31 ", 0), 0u) << move;
            EXPECT_NE(check.find("]GE"), std::string::npos) << check;
            EXPECT_NE(check.find("#3000=2"), std::string::npos) << check;
          }
        }
        // No straight move goes down to a start: only the retrace after a touch is a G1.
        if (line.rfind("G1 ", 0) == 0) {
          EXPECT_TRUE(previous.rfind("G38.2", 0) == 0 || previous.rfind("G31", 0) == 0)
              << "unguarded: " << line << " after " << previous;
        }
        if (line.rfind("IF", 0) != 0 && line.rfind("DPRNT", 0) != 0) previous = line;
      }
      EXPECT_TRUE(moved_xy);
      EXPECT_EQ(touches, desc.touches.size());
      EXPECT_EQ(guards + desc.touches.size(), desc.probe_moves.size());
      EXPECT_GE(guards, 2u);
    }
  }
}

// A control without some head axes gets no word for them, and a check that needs one is refused
// naming it; the config refuses an axes list that is not one.
TEST(ProbingProgram, AControlWithoutAnAxisGetsNoWordForItAndNoCheckThatNeedsIt) {
  MachineConfig m = pm1();
  m.probing.axes = "XYZAC";
  const std::string text =
      write_program(request(m, CheckKind::MonumentPositioning, "ax-1"), m, Dialect::LinuxCnc, "t");
  EXPECT_EQ(text.find("G53 G0 W"), std::string::npos);
  EXPECT_NE(text.find("G53 G0 A0.0000 C0.0000"), std::string::npos);
  m.probing.axes = "XYZ";
  EXPECT_EQ(
      write_program(request(m, CheckKind::MonumentPositioning, "ax-2"), m, Dialect::Fanuc, "t")
          .find("G53 G0 A"),
      std::string::npos);
  try {
    write_program(request(m, CheckKind::MonumentToolLength, "ax-3"), m, Dialect::LinuxCnc, "t");
    ADD_FAILURE() << "a check that turns the head was programmed for a control without A";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("monument_tool_length needs the A axis (pm1's "
                                         "probing.axes: XYZ)"),
              std::string::npos)
        << e.what();
  }
  for (const char* bad : {"XYA", "XYZAA", "XYZB"}) {
    const std::string yaml = "machine_id: ax\nprobing:\n  axes: " + std::string(bad) + "\n";
    try {
      parse_machine_config(yaml, "ax.yaml");
      ADD_FAILURE() << bad << " was taken";
    } catch (const ConfigError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("ax.yaml: probing.axes = '" + std::string(bad) +
                          "': expected X, Y and Z and any of W, A and C, each once"),
                std::string::npos)
          << what;
    }
  }
}

// The log a control writes for the simulator's touches, formatted as the control does.
std::string control_log(Dialect d, const ProgramDescription& program, const MeasurementSet& set,
                        const MachineConfig& m) {
  return testing::control_log(d, program.request_id, set.touches, m, program.probe_moves);
}

TEST(ProbingProgram, LogsOfEachDialectGiveTheSimulatorsFiguresAndTheInjectedTruth) {
  MachineConfig m = pm1();
  m.simulator.errors.machine_shift_mm = Eigen::Vector3d(0.030, -0.020, 0.015);
  m.simulator.errors.tool_length_error_mm = 0.012;
  for (bool inch : {false, true}) {
    m.probing.inch = inch;
    m.probing.work_offset_mm = inch ? Eigen::Vector3d(100, -200, 50) : Eigen::Vector3d::Zero();
    const sim::MachineSimulator simulator(m, m.simulator);
    for (CheckKind k :
         {CheckKind::MonumentCAlignment, CheckKind::MonumentToolLength,
          CheckKind::MonumentPositioning, CheckKind::MonumentCRotation, CheckKind::PartSetPoints}) {
      const CheckRequest r = request(m, k, "log-" + std::string(to_string(k)));
      const MeasurementSet truth_set = simulator.perform(r, 1'000'000'000);
      ASSERT_EQ(truth_set.error, "");
      const CheckResult expected = solver::solve(truth_set, m, 2);
      for (Dialect d : kDialects) {
        SCOPED_TRACE(std::string(to_string(k)) + " " + std::string(to_string(d)) +
                     (inch ? " inch" : " mm"));
        const ProgramDescription program =
            read_program(write_program(r, m, d, "ncqual test"), "p.nc");
        const std::string file = "/inbox/" + results_file_name(r.request_id, d);
        const TouchLog log = read_touch_log(control_log(d, program, truth_set, m), file, d);
        const MeasurementSet set =
            measurement_set_from_log(program, log, file, m, truth_set.time_ns);
        const CheckResult got = solver::solve(set, m, 2);
        EXPECT_EQ(got.verdict, expected.verdict) << got.reason;
        ASSERT_EQ(got.metrics.size(), expected.metrics.size());
        // The log's resolution (6 decimals, or Fanuc's 4 of mm and 5 of inch) moves no figure
        // by more than a 25th of its tolerance band (Fanuc in inch: 0.25 um steps).
        for (std::size_t i = 0; i < got.metrics.size(); ++i) {
          const Metric& e = expected.metrics[i];
          ASSERT_TRUE(std::isfinite(e.upper - e.lower)) << e.name;
          EXPECT_NEAR(got.metrics[i].value, e.value, (e.upper - e.lower) / 25) << e.name;
        }
        if (k == CheckKind::MonumentPositioning) {
          // The monument positioning check sees the machine shift (the sign: the ball is truly
          // at readout + shift, the hole where taught, so the readouts centre at -shift).
          const Metric* dx = find_metric(got, "center_dx_mm");
          ASSERT_NE(dx, nullptr);
          EXPECT_NEAR(dx->value, -0.030, 0.003);
        }
      }
    }
  }
}

// A program and the probe log LinuxCNC 2.9 wrote running it (tests/data/linuxcnc, recorded by
// LinuxCnc.ADailyCheckRunsOnLinuxCncThroughTheControlFilesDriver; its README says how): the
// machine config writes the same program again, and the log gives the injected shift. This keeps
// LinuxCNC's own log format covered where LinuxCNC cannot run.
TEST(ProbingProgram, RecordedLinuxCncLogsGiveTheInjectedShift) {
  const std::string dir = NCQUAL_SOURCE_DIR "/tests/data/linuxcnc/";
  const std::string id = "lc1-monument_positioning-20261128T114441Z-1";
  const MachineConfig m = load_machine_config(dir + "lc1.yaml");
  const std::string program_file = dir + "ncqual-" + id + ".ngc";
  const std::string log_file = dir + "ncqual-" + id + ".txt";
  const ProgramDescription recorded = read_program(read_text(program_file), program_file);
  EXPECT_EQ(recorded.request_id, id);
  // The program of that request from the committed machine: the same moves (only the version
  // line may differ).
  CheckRequest r = request(m, CheckKind::MonumentPositioning, id);
  const std::string again = write_program(r, m, Dialect::LinuxCnc, "ncqual test");
  const auto without_version = [](const std::string& text) {
    return std::regex_replace(text, std::regex(R"(\(NCQUAL VERSION [^)]*\)\n)"), "");
  };
  EXPECT_EQ(without_version(again), without_version(read_text(program_file)));

  const TouchLog log = read_touch_log(read_text(log_file), log_file, Dialect::LinuxCnc);
  // A line per G38 move: the 5 touches and the 4 guarded moves down and up.
  ASSERT_EQ(log.touches.size(), 9u);
  const MeasurementSet set = measurement_set_from_log(recorded, log, log_file, m, 1);
  ASSERT_EQ(set.touches.size(), 5u);
  const CheckResult result = solver::solve(set, m, 2);
  EXPECT_EQ(result.verdict, Verdict::Fail) << result.reason;
  // Check 3 sees the monument relative to the machine; LinuxCNC's probe tripped at most one
  // servo period (1 um at this feed) past each contact.
  const auto& truth = m.simulator.errors;
  const Eigen::Vector3d expected = truth.monument_shift_mm - truth.machine_shift_mm;
  EXPECT_NEAR(find_metric(result, "center_dx_mm")->value, expected.x(), 0.0006);
  EXPECT_NEAR(find_metric(result, "center_dy_mm")->value, expected.y(), 0.0006);
  EXPECT_NEAR(find_metric(result, "face_dz_mm")->value, expected.z(), 0.0015);
}

TEST(ProbingProgram, ALogThatIsNotItsProgramsIsRefusedSayingWhy) {
  const MachineConfig m = pm1();
  const CheckRequest r = request(m, CheckKind::MonumentPositioning, "pm1-r7");
  const sim::MachineSimulator simulator(m, m.simulator);
  const MeasurementSet truth = simulator.perform(r, 1);
  ASSERT_EQ(truth.touches.size(), 5u);
  auto refusal = [&](Dialect d, const std::string& text, const std::string& file) {
    const ProgramDescription program = read_program(write_program(r, m, d, "t"), "p.nc");
    try {
      measurement_set_from_log(program, read_touch_log(text, file, d), file, m, 1);
    } catch (const ProgramError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const ProgramDescription generic =
      read_program(write_program(r, m, Dialect::GenericCsv, "t"), "p.nc");
  const std::string good = control_log(Dialect::GenericCsv, generic, truth, m);
  const std::string file = "in/ncqual-pm1-r7.csv";
  EXPECT_EQ(refusal(Dialect::GenericCsv, good, file), "accepted");

  // Touch 3 missing.
  std::string missing = good;
  const auto third = missing.find("\n3,");
  missing.erase(third + 1, missing.find('\n', third + 1) - third);
  std::string why = refusal(Dialect::GenericCsv, missing, file);
  EXPECT_NE(why.find("expected 5 touches, found 4; touch 3 is missing"), std::string::npos) << why;
  // Touch 2 twice.
  std::string twice = good;
  const auto second = twice.find("\n2,");
  twice.insert(second + 1, twice.substr(second + 1, twice.find('\n', second + 1) - second));
  why = refusal(Dialect::GenericCsv, twice, file);
  EXPECT_NE(why.find("touch 2 again, out of order (expected touch 3)"), std::string::npos) << why;
  // The log of another request, by its comment and by its file name.
  std::string other = good;
  other.replace(other.find("pm1-r7"), 6, "pm1-r8");
  why = refusal(Dialect::GenericCsv, other, file);
  EXPECT_NE(why.find("names request 'pm1-r8'"), std::string::npos) << why;
  why = refusal(Dialect::GenericCsv, good, "in/ncqual-pm1-r8.csv");
  EXPECT_NE(why.find("named for request 'pm1-r8'"), std::string::npos) << why;
  // LinuxCNC logs carry no numbers: the counts and what LinuxCNC leaves out.
  const ProgramDescription lcnc = read_program(write_program(r, m, Dialect::LinuxCnc, "t"), "p.nc");
  // (Cut at touch 5's line: the lines before it include the guarded moves'.)
  std::string short_log = control_log(Dialect::LinuxCnc, lcnc, truth, m);
  std::size_t cut = 0;
  for (const ProbeMove& mv : lcnc.probe_moves) {
    if (mv.touch == 5) break;
    cut = short_log.find('\n', cut) + 1;
  }
  short_log.erase(cut);
  why = refusal(Dialect::LinuxCnc, short_log, "in/ncqual-pm1-r7.txt");
  EXPECT_NE(why.find("expected 5 touches, found 4"), std::string::npos) << why;
  EXPECT_NE(why.find("line equal to the one before"), std::string::npos) << why;
  // A LinuxCNC log whose touch was taken with another head than the program declares (a program
  // that did not command it): refused naming the touch, the logged and the declared head.
  std::string turned = control_log(Dialect::LinuxCnc, lcnc, truth, m);
  const std::size_t first_touch_line = [&] {
    std::size_t at = 0;
    for (const ProbeMove& mv : lcnc.probe_moves) {
      if (mv.touch == 1) break;
      at = turned.find('\n', at) + 1;
    }
    return at;
  }();
  // Its fourth field is A.
  std::size_t field = first_touch_line;
  for (int k = 0; k < 3; ++k) field = turned.find(' ', field) + 1;
  turned.replace(field, turned.find(' ', field) - field, "-90.000000");
  why = refusal(Dialect::LinuxCnc, turned, "in/ncqual-pm1-r7.txt");
  EXPECT_NE(why.find("touch 1 was taken at A -90.0000, C 0.0000, W 0.0000; the program declares "
                     "a 0.0000, c 0.0000, w 0.0000"),
            std::string::npos)
      << why;
  // A malformed line names file, line and field.
  why = refusal(Dialect::GenericCsv, "# request pm1-r7\n1,2,x3,4\n", file);
  EXPECT_NE(why.find(file + ":2: y = 'x3' is not a number"), std::string::npos) << why;
  // Fanuc: the first line names the request.
  why = refusal(Dialect::Fanuc, "T1 X1 Y2 Z3\n", "in/fanuc.txt");
  EXPECT_NE(why.find("in/fanuc.txt:1:"), std::string::npos) << why;
  EXPECT_NE(why.find("first line of a Fanuc touch log is NCQUAL <request id>"), std::string::npos)
      << why;
}

TEST(ProbingProgram, ARequestWithoutATouchPlanIsRefused) {
  const MachineConfig m = pm1();
  try {
    write_program(request(m, CheckKind::GlobalGrid, "g"), m, Dialect::LinuxCnc, "t");
    FAIL() << "a tracker check has no probing program";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("laser tracker"), std::string::npos) << e.what();
  }
}

// The tracker checks' nominal lists: one row per measurement of the program; at home head angles
// the reflector of tool length L and offset (ox, oy) sits at pivot + (ox, oy, -L) (worked by
// hand from the kinematics' definition, ncqual/common/kinematics.hpp), and the list reads back as a
// tracker point export that pairs with the program point for point, at zero deviation.
TEST(TrackerNominals, OneRowPerMeasurementThatReadsBackAsAnExportOfTheProgram) {
  const MachineConfig m = pm1();
  const GlobalCheckConfig& gc = *m.global_check;
  const std::string text =
      write_tracker_nominals(request(m, CheckKind::GlobalGrid, "pm1-nominals-1"), m, "ncqual test");
  std::size_t measured = 0;
  for (const TrackerMove& mv : global_check_program(CheckKind::GlobalGrid, gc)) {
    if (!mv.label.empty()) ++measured;
  }
  EXPECT_NE(text.find("# NCQUAL TRACKER NOMINALS machine=pm1 check=global_grid "
                      "request=pm1-nominals-1 points=" +
                      std::to_string(measured) + " version=ncqual test\n"),
            std::string::npos);
  const CsvTable table = read_csv(text, "nominals.csv");
  ASSERT_EQ(table.rows.size(), measured);
  int home_rows = 0;
  for (const CsvRow& row : table.rows) {
    if (table.number(row, 8) != 0 || table.number(row, 9) != 0) continue;  // A, C in degrees
    const ProbeGeometry& t = gc.targets.at(static_cast<std::size_t>(table.number(row, 4)));
    EXPECT_NEAR(table.number(row, 1), table.number(row, 5) + t.stylus_offset_mm.x(), 1e-9);
    EXPECT_NEAR(table.number(row, 2), table.number(row, 6) + t.stylus_offset_mm.y(), 1e-9);
    EXPECT_NEAR(table.number(row, 3), table.number(row, 7) - t.tool_length_mm, 1e-9);
    ++home_rows;
  }
  EXPECT_GT(home_rows, 200);
  EXPECT_TRUE(solver::is_tracker_point_export(table));
  for (const char* prefix : {"x_run", "y_run", "grid"}) {
    SCOPED_TRACE(prefix);
    const solver::GridFromExport part = solver::grid_points_from_export(table, prefix, gc);
    ASSERT_FALSE(part.points.empty());
    for (const auto& p : part.points) {
      EXPECT_LT((p.measured_mm - p.commanded_mm).norm(), 1e-4) << p.point;
    }
  }
  // A rotary check's list carries its head angles: rotary_a steps A from -90 to 90 degrees.
  const CsvTable rotary = read_csv(
      write_tracker_nominals(request(m, CheckKind::RotaryA, "pm1-nominals-2"), m, "ncqual test"),
      "rotary.csv");
  double lowest = 0, highest = 0;
  for (const CsvRow& row : rotary.rows) {
    lowest = std::min(lowest, rotary.number(row, 8));
    highest = std::max(highest, rotary.number(row, 8));
  }
  EXPECT_EQ(lowest, -90);
  EXPECT_EQ(highest, 90);
  // A probe check has a probing program, not nominals.
  try {
    write_tracker_nominals(request(m, CheckKind::MonumentPositioning, "x"), m, "ncqual test");
    ADD_FAILURE() << "a probe check's nominals were written";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("monument_positioning is not measured by the laser "
                                         "tracker"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace ncqual::probing
