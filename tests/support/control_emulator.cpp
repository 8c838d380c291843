// SPDX-License-Identifier: Apache-2.0
#include "control_emulator.hpp"

#include "ncqual/acquisition/instruments.hpp"
#include "ncqual/probing/program.hpp"
#include "ncqual/common/text.hpp"
#include "ncqual/common/units.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace ncqual::testing {
namespace fs = std::filesystem;

std::string control_log(ControlDialect dialect, const std::string& request_id,
                        const std::vector<Touch>& touches, const MachineConfig& m) {
  std::string out;
  char line[256];
  const double unit = m.probing.inch ? 25.4 : 1;
  if (dialect == ControlDialect::Fanuc) out = "NCQUAL " + request_id + "\r\n";
  if (dialect == ControlDialect::GenericCsv) out = "# request " + request_id + "\ntouch,x,y,z\n";
  int n = 0;
  for (const Touch& t : touches) {
    const Eigen::Vector3d q =
        (Eigen::Vector3d(t.axes.x_mm, t.axes.y_mm, t.axes.z_mm) - m.probing.work_offset_mm) / unit;
    ++n;
    if (dialect == ControlDialect::LinuxCnc) {
      std::snprintf(line, sizeof line, "%f %f %f %f %f %f %f %f %f\n", q.x(), q.y(), q.z(),
                    units::rad_to_deg(t.axes.a_rad), 0.0, units::rad_to_deg(t.axes.c_rad), 0.0, 0.0,
                    t.axes.w_mm / unit);
    } else if (dialect == ControlDialect::Fanuc) {
      // DPRNT with [54] (mm) or [45] (inch): sign or blank, leading blanks.
      const int decimals = m.probing.inch ? 5 : 4;
      std::snprintf(line, sizeof line, "T%d X% 10.*f Y% 10.*f Z% 10.*f\r\n", n, decimals, q.x(),
                    decimals, q.y(), decimals, q.z());
    } else {
      std::snprintf(line, sizeof line, "%d,%.6f,%.6f,%.6f\n", n, q.x(), q.y(), q.z());
    }
    out += line;
  }
  return out;
}

std::vector<std::string> answer_programs(const MachineConfig& m, std::int64_t time_ns) {
  std::vector<std::string> answered;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(m.instrument.outbox, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("ncqual-", 0) != 0 || entry.path().extension() == ".part") continue;
    std::string why;
    const auto text = read_text_file(entry.path().string(), &why);
    if (!text) continue;
    const probing::ProgramDescription program = probing::read_program(*text, entry.path().string());
    const fs::path results = fs::path(m.instrument.inbox) / program.results_file;
    if (fs::exists(results)) continue;
    CheckRequest request;
    request.machine_id = program.machine_id;
    request.request_id = program.request_id;
    request.kind = program.kind;
    request.parameters = program.parameters;
    acquisition::SimulatedInstruments machine(m);
    const auto set = machine.measure(request, time_ns);
    const std::string log = control_log(program.dialect, program.request_id, set->touches, m);
    // A control appends as it probes: the first half, then the rest.
    std::size_t half = log.find('\n', log.size() / 2);
    half = half == std::string::npos ? log.size() : half + 1;
    std::ofstream(results, std::ios::binary) << log.substr(0, half) << std::flush;
    std::ofstream(results, std::ios::binary | std::ios::app) << log.substr(half);
    answered.push_back(program.request_id);
  }
  return answered;
}

}  // namespace ncqual::testing
