// SPDX-License-Identifier: Apache-2.0
// The control-files driver across processes: one acquisition serves three machines, each with
// the instrument its config names:
//   pm-sim   the simulator;
//   pm-ctl   its control, through program and results folders: a stand-in control in a process
//            of its own (ncqual-test-control, tests/support/control_emulator.hpp) runs each
//            program on the simulator and writes a Fanuc log in inches with a work offset;
//   pm-bad   its control, whose log this test writes with a line that cannot be read.
// pm-sim's check is stored while pm-ctl's program still waits for its control (the acquisition
// does not block on it); once the control answers, pm-ctl's stored result finds the injected
// machine shift; pm-bad's check is stored INVALID with the log's file, line and value.
#include "harness.hpp"

#include "ncqual/common/config.hpp"
#include "ncqual/probing/program.hpp"
#include "ncqual/common/text.hpp"

#include <gtest/gtest.h>

namespace ncqual::testing {
namespace {

bool has_result(storage::Database& db, const std::string& machine) {
  storage::HistoryQuery q;
  q.machine_id = machine;
  const auto records = db.history(q);
  return !records.empty() && records.front().result.has_value();
}

std::string control_section(const Plant& plant, const std::string& id, const std::string& dialect) {
  for (const char* folder : {"programs", "results"}) {
    fs::create_directories(plant.dir() / id / folder);
  }
  return "instrument:\n  driver: control-files\n  dialect: " + dialect + "\n  outbox: " + id +
         "/programs\n  inbox: " + id + "/results\n  timeout_s: 600\n";
}

TEST(ControlFiles, AControlAnswersItsProgramsWhileOtherMachinesGoOn) {
  Plant plant("control-files", TestDomain::ControlFiles);
  plant.add_machine("pm-sim", machine_yaml("pm-sim", "    machine_shift_mm: [0, 0, 0]\n", 21));
  const std::string ctl =
      plant.add_machine("pm-ctl", machine_yaml("pm-ctl",
                                               "    machine_shift_mm: [0.041, -0.029, 0.033]\n"
                                               "    monument_shift_mm: [0.002, 0.001, 0.0]\n",
                                               22) +
                                      control_section(plant, "pm-ctl", "fanuc") +
                                      "probing:\n  units: inch\n  work_offset: G55\n"
                                      "  work_offset_mm: [1000.0, 500.0, 100.0]\n");
  plant.add_machine("pm-bad", machine_yaml("pm-bad", "    machine_shift_mm: [0, 0, 0]\n", 23) +
                                  control_section(plant, "pm-bad", "generic-csv"));
  plant.write_plant();
  plant.start("historian");
  plant.start("solver");
  plant.start("acquisition", {"--all"});
  plant.start("scheduler");

  // pm-ctl's program waits in its outbox for a control that is not there yet; pm-sim's check goes
  // through meanwhile.
  const fs::path ctl_programs = plant.dir() / "pm-ctl" / "programs";
  const auto program_of = [](const fs::path& folder) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(folder, ec)) {
      if (e.path().extension() == ".nc") return e.path();
    }
    return fs::path();
  };
  ASSERT_TRUE(plant.wait_for([&] { return !program_of(ctl_programs).empty(); }))
      << plant.log("acquisition");
  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) { return has_result(db, "pm-sim"); }))
      << plant.log("acquisition");
  {
    auto db = storage::Database::open_readonly(plant.db_path());
    EXPECT_FALSE(has_result(db, "pm-ctl")) << "no control has answered yet";
  }
  const fs::path program = program_of(ctl_programs);
  std::string why;
  const auto program_text = read_text_file(program.string(), &why);
  ASSERT_TRUE(program_text) << why;
  const probing::ProgramDescription description =
      probing::read_program(*program_text, program.string());
  EXPECT_TRUE(description.inch);
  EXPECT_EQ(description.work_offset, "G55");

  // pm-bad's control writes a log with a line that cannot be read.
  const fs::path bad_programs = plant.dir() / "pm-bad" / "programs";
  ASSERT_TRUE(plant.wait_for([&] { return !program_of(bad_programs).empty(); }));
  const auto bad_text = read_text_file(program_of(bad_programs).string(), &why);
  ASSERT_TRUE(bad_text) << why;
  const auto bad = probing::read_program(*bad_text, "pm-bad program");
  const fs::path bad_log = plant.dir() / "pm-bad" / "results" / bad.results_file;
  std::ofstream(bad_log) << "# request " << bad.request_id
                         << "\n1,1227.0,800.0,145.0\n2,12oo.0,0,0\n";

  // The control comes up and answers.
  Process control(Launch({NCQUAL_TEST_CONTROL_EXE, "--machine-config", ctl})
                      .log_to((plant.dir() / "control.log").string()));
  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) {
    return has_result(db, "pm-ctl") && has_result(db, "pm-bad");
  })) << plant.log("acquisition");

  auto db = storage::Database::open_readonly(plant.db_path());
  const MachineConfig machine = load_machine_config(ctl);
  const auto truth = machine.simulator.errors;
  const auto record = db.find_check(description.request_id);
  ASSERT_TRUE(record && record->result);
  EXPECT_EQ(record->result->verdict, Verdict::Fail) << record->result->reason;
  // Check 3 sees the monument relative to the machine; 3 sigma of the 1 um trigger noise and the
  // Fanuc log's 5 decimals of an inch (0.13 um).
  const Eigen::Vector3d expected = truth.monument_shift_mm - truth.machine_shift_mm;
  const double bound = 3 * 0.001 + 0.000127;
  EXPECT_NEAR(find_metric(*record->result, "center_dx_mm")->value, expected.x(), bound);
  EXPECT_NEAR(find_metric(*record->result, "center_dy_mm")->value, expected.y(), bound);
  EXPECT_NEAR(find_metric(*record->result, "face_dz_mm")->value, expected.z(), bound);
  const auto set = db.load_measurement_set(description.request_id);
  ASSERT_TRUE(set);
  EXPECT_EQ(set->touches.size(), description.touches.size());
  EXPECT_EQ(set->error, "");
  // Program and log are archived, the outbox is empty again.
  const fs::path archive = plant.dir() / "pm-ctl" / "results" / "archive";
  EXPECT_TRUE(fs::exists(archive / program.filename()));
  EXPECT_TRUE(fs::exists(archive / description.results_file));
  EXPECT_TRUE(program_of(ctl_programs).empty());

  const auto bad_record = db.find_check(bad.request_id);
  ASSERT_TRUE(bad_record && bad_record->result);
  EXPECT_EQ(bad_record->result->verdict, Verdict::Invalid);
  EXPECT_NE(bad_record->result->reason.find(bad_log.string() + ":3:"), std::string::npos)
      << bad_record->result->reason;
  EXPECT_NE(bad_record->result->reason.find("12oo.0"), std::string::npos)
      << bad_record->result->reason;
}

}  // namespace
}  // namespace ncqual::testing
