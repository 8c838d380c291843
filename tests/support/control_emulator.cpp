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

namespace {

// LinuxCNC's probe log line: X Y Z A B C U V W, "%f", work coordinates and program units.
std::string linuxcnc_line(const Eigen::Vector3d& q, const AxisPosition& head, double unit) {
  char line[256];
  std::snprintf(line, sizeof line, "%f %f %f %f %f %f %f %f %f\n", q.x(), q.y(), q.z(),
                units::rad_to_deg(head.a_rad), 0.0, units::rad_to_deg(head.c_rad), 0.0, 0.0,
                head.w_mm / unit);
  return line;
}

}  // namespace

std::string control_log(ControlDialect dialect, const std::string& request_id,
                        const std::vector<Touch>& touches, const MachineConfig& m,
                        const std::vector<probing::ProbeMove>& moves) {
  std::string out;
  char line[256];
  const double unit = m.probing.inch ? 25.4 : 1;
  if (dialect == ControlDialect::Fanuc) out = "NCQUAL " + request_id + "\r\n";
  if (dialect == ControlDialect::GenericCsv) out = "# request " + request_id + "\ntouch,x,y,z\n";
  // A touch's X, Y, Z as the control logs them: work coordinates, program units.
  const auto logged = [&](const Touch& t) -> Eigen::Vector3d {
    return (Eigen::Vector3d(t.axes.x_mm, t.axes.y_mm, t.axes.z_mm) - m.probing.work_offset_mm) /
           unit;
  };
  if (dialect == ControlDialect::LinuxCnc && !moves.empty()) {
    for (std::size_t i = 0; i < moves.size(); ++i) {
      const probing::ProbeMove& move = moves[i];
      if (move.touch > 0 && static_cast<std::size_t>(move.touch) > touches.size()) break;
      if (move.touch > 0) {
        const Touch& t = touches[static_cast<std::size_t>(move.touch) - 1];
        out += linuxcnc_line(logged(t), t.axes, unit);
        continue;
      }
      int beside = 0;  // the touch whose head the guarded move has
      if (i > 0 && moves[i - 1].touch > 0) {
        beside = moves[i - 1].touch;
      } else {
        for (std::size_t j = i + 1; j < moves.size() && beside == 0; ++j) beside = moves[j].touch;
      }
      const AxisPosition head = beside > 0 && static_cast<std::size_t>(beside) <= touches.size()
                                    ? touches[static_cast<std::size_t>(beside) - 1].axes
                                    : AxisPosition{};
      out += linuxcnc_line(move.guard_to, head, unit);
    }
    return out;
  }
  int n = 0;
  for (const Touch& t : touches) {
    const Eigen::Vector3d q = logged(t);
    ++n;
    if (dialect == ControlDialect::LinuxCnc) {
      out += linuxcnc_line(q, t.axes, unit);
      continue;
    }
    if (dialect == ControlDialect::Fanuc) {
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
    const std::string log =
        control_log(program.dialect, program.request_id, set->touches, m, program.probe_moves);
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
