// SPDX-License-Identifier: Apache-2.0
#include "ncqual/probing/tracker_nominals.hpp"

#include "comment_fields.hpp"
#include "ncqual/probing/program.hpp"

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/global_check.hpp"
#include "ncqual/common/kinematics.hpp"
#include "ncqual/common/text.hpp"
#include "ncqual/common/units.hpp"

#include <stdexcept>
#include <vector>

namespace ncqual::probing {
namespace {

// Micrometre resolution in mm, 1e-5 deg: finer than any tracker's uncertainty.
std::string mm(double v) { return format_fixed(v, 4); }
std::string deg(double rad) { return format_fixed(rad * 180.0 / units::kPi, 5); }

}  // namespace

std::string tracker_nominals_file_name(const std::string& request_id) {
  return "ncqual-" + request_id + "-nominals.csv";
}

std::string write_tracker_nominals(const CheckRequest& request, const MachineConfig& machine,
                                   const std::string& version) {
  if (!is_tracker_check(request.kind)) {
    throw std::invalid_argument(std::string(to_string(request.kind)) +
                                " is not measured by the laser tracker: it has no tracker "
                                "nominals (a probe check has a probing program: --dialect "
                                "linuxcnc, fanuc or generic-csv)");
  }
  if (!machine.global_check) {
    throw std::invalid_argument("machine " + machine.machine_id +
                                " has no global_check section: no tracker program");
  }
  const GlobalCheckConfig& gc = *machine.global_check;
  std::vector<TrackerMove> measured;
  for (TrackerMove& m : global_check_program(request.kind, gc)) {
    if (!m.label.empty()) measured.push_back(std::move(m));
  }
  std::string out;
  out += "# NCQUAL TRACKER NOMINALS machine=" + machine.machine_id +
         " check=" + std::string(to_string(request.kind)) + " request=" + request.request_id +
         " points=" + std::to_string(measured.size()) + " version=" + version + "\n";
  for (const NamedValue& p : request.parameters) {
    out += "# NCQUAL PARAMETER " + p.name + "=" + mm(p.value) + "\n";
  }
  out +=
      "# The reflector's nominal position in the machine frame at each measurement, in the order\n"
      "# the machine runs them. Measure each point with the machine at its Machine X..W, keep\n"
      "# the point's name in the export (Point, X, Y, Z in a declared unit): ncqual import pairs\n"
      "# the measured points with the program by name. Reflector: global_check.targets index.\n";
  for (std::size_t k = 0; k < gc.targets.size(); ++k) {
    const ProbeGeometry& t = gc.targets[k];
    out += "# Reflector " + std::to_string(k) + ": tool length " + mm(t.tool_length_mm) + " mm";
    if (!t.stylus_offset_mm.isZero()) {
      out += ", offset " + mm(t.stylus_offset_mm.x()) + ", " + mm(t.stylus_offset_mm.y()) + " mm";
    }
    out += "\n";
  }
  out +=
      "Point,X (mm),Y (mm),Z (mm),Reflector,Machine X (mm),Machine Y (mm),Machine Z (mm),"
      "A (deg),C (deg),W (mm)\n";
  for (const TrackerMove& m : measured) {
    const Eigen::Vector3d p = stylus_ball_centre(m.commanded, gc.targets.at(m.target));
    out += m.label + "," + mm(p.x()) + "," + mm(p.y()) + "," + mm(p.z()) + "," +
           std::to_string(m.target) + "," + mm(m.commanded.x_mm) + "," + mm(m.commanded.y_mm) +
           "," + mm(m.commanded.z_mm) + "," + deg(m.commanded.a_rad) + "," +
           deg(m.commanded.c_rad) + "," + mm(m.commanded.w_mm) + "\n";
  }
  return out;
}

TrackerNominalsDescription read_tracker_nominals(const std::string& text, const std::string& file) {
  const std::string header = "# NCQUAL TRACKER NOMINALS ";
  const std::string parameter = "# NCQUAL PARAMETER ";
  TrackerNominalsDescription d;
  bool found = false;
  const std::vector<std::string> lines = detail::lines_of(text);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const int ln = static_cast<int>(i) + 1;
    const std::string& line = lines[i];
    if (line.rfind(header, 0) == 0) {
      const std::string c = "NCQUAL TRACKER NOMINALS";
      // The version is last and may hold spaces ("ncqual 0.9.0 (abc1234)").
      std::string rest = line.substr(header.size());
      const auto v = rest.find(" version=");
      if (v != std::string::npos) {
        d.version = rest.substr(v + 9);
        rest.resize(v);
      }
      const detail::Fields f = detail::fields_of(rest, file, ln);
      d.machine_id = detail::field(f, "machine", c, file, ln);
      d.request_id = detail::field(f, "request", c, file, ln);
      const std::string& check = detail::field(f, "check", c, file, ln);
      const auto kind = parse_check_kind(check);
      if (!kind) throw ProgramError(file, ln, c + ": check = '" + check + "' is no check kind");
      if (!is_tracker_check(*kind)) {
        throw ProgramError(file, ln,
                           c + ": check = '" + check +
                               "' is not measured by the laser tracker (a probe check's "
                               "program is read by analyze|import touches)");
      }
      d.kind = *kind;
      const std::string& points = detail::field(f, "points", c, file, ln);
      const auto count = detail::parse_integer(points);
      if (!count || *count <= 0) {
        throw ProgramError(file, ln, c + ": points = '" + points + "' is no count");
      }
      d.points = static_cast<std::size_t>(*count);
      found = true;
    } else if (line.rfind(parameter, 0) == 0) {
      const detail::Fields f = detail::fields_of(line.substr(parameter.size()), file, ln);
      if (f.size() != 1) throw ProgramError(file, ln, "NCQUAL PARAMETER: expected one name=value");
      NamedValue p;
      p.name = f.begin()->first;
      p.value = detail::number_field(f, p.name, "NCQUAL PARAMETER", file, ln);
      d.parameters.push_back(p);
    }
  }
  if (!found) {
    throw ProgramError(file, 0,
                       "no '# NCQUAL TRACKER NOMINALS' line: not a nominal list written by ncqual "
                       "program --check <tracker check>");
  }
  return d;
}

}  // namespace ncqual::probing
