// SPDX-License-Identifier: Apache-2.0
// Writes the sample report of the tests (report_historian.hpp, pm1) to OUTDIR/report.html, its
// checks measured, and the same historian's checks as ncqual's simulator's to
// OUTDIR/report-simulated.html, for report.RenderedInChromium (rendered_in_chromium.py), its times
// in Europe/Berlin. Usage: ncqual_report_sample OUTDIR.
#include "ncqual/report/machine_report.hpp"

#include "report_historian.hpp"

#include <filesystem>
#include <fstream>
#include <iostream>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: ncqual_report_sample OUTDIR\n";
    return 2;
  }
  namespace fs = std::filesystem;
  using namespace ncqual;
  const fs::path out(argv[1]);
  fs::create_directories(out);
  for (const auto& [name, origin] : {std::pair{"report", DataOrigin::Measured},
                                     std::pair{"report-simulated", DataOrigin::Simulated}}) {
    const fs::path db = out / (std::string(name) + ".db");
    for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(db.string() + suffix);
    const MachineConfig m = report::testing::report_machine("pm1");
    report::testing::build_report_historian(db.string(), m, origin);
    storage::Database read = storage::Database::open_readonly(db.string());
    report::MachineReportQuery q;
    q.machine_id = "pm1";
    q.since_ns = report::testing::kT0;
    q.now_ns = report::testing::kT0 + 14 * report::testing::kDay;
    q.machine = &m;
    // A plant in Berlin: the report's times and chart axes in CET with the offset.
    CalendarConfig zone = default_calendar_config();
    zone.time_zone = "Europe/Berlin";
    const Calendar calendar(zone);
    q.calendar = &calendar;
    std::ofstream(out / (std::string(name) + ".html"), std::ios::binary)
        << report::machine_report_document(report::gather_machine_report(read, q));
  }
  return 0;
}
