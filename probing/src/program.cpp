// SPDX-License-Identifier: Apache-2.0
#include "ncqual/probing/program.hpp"

#include "comment_fields.hpp"

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/probing/plan.hpp"
#include "ncqual/common/text.hpp"
#include "ncqual/common/units.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <stdexcept>

namespace ncqual::probing {

using detail::field;
using detail::fields_of;
using detail::lines_of;
using detail::number_field;
using detail::parse_integer;

namespace {

constexpr double kMmPerInch = 25.4;
constexpr double kSafeZAboveHighestStartMm = 50.0;
// A skip position this close to the probing move's end: the probe did not trip (Fanuc).
constexpr double kNoTripMm = 0.001;

std::string general(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.9g", std::abs(v) < 1e-12 ? 0.0 : v);
  return buffer;
}

// Program comments may not hold parentheses.
std::string comment_safe(std::string s) {
  std::replace(s.begin(), s.end(), '(', '[');
  std::replace(s.begin(), s.end(), ')', ']');
  return s;
}

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string_view::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return std::string(s.substr(b, e - b + 1));
}

// The program text, as the control reads it.
class Writer {
 public:
  explicit Writer(const MachineConfig& machine) : p_(machine.probing) {}

  void line(const std::string& s) { out_ << s << "\n"; }
  void comment(const std::string& s) { line("(" + comment_safe(s) + ")"); }

  std::string length(double mm) const {
    return p_.inch ? format_fixed(mm / kMmPerInch, 5) : format_fixed(mm, 4);
  }
  std::string feed(double mm_per_min) const {
    return p_.inch ? format_fixed(mm_per_min / kMmPerInch, 2) : format_fixed(mm_per_min, 1);
  }
  // A pivot position (machine coordinates, mm) in the work offset's coordinates (mm).
  Eigen::Vector3d program(const Eigen::Vector3d& pivot) const { return pivot - p_.work_offset_mm; }
  // X, Y, Z words of a pivot position in program coordinates and units.
  std::string xyz(const Eigen::Vector3d& pivot) const {
    const Eigen::Vector3d q = program(pivot);
    return "X" + length(q.x()) + " Y" + length(q.y()) + " Z" + length(q.z());
  }
  std::string z(double pivot_z) const { return length(pivot_z - p_.work_offset_mm.z()); }

  std::string text() const { return out_.str(); }

 private:
  const ProbingConfig& p_;
  std::ostringstream out_;
};

Eigen::Vector3d xyz_of(const AxisPosition& a) { return {a.x_mm, a.y_mm, a.z_mm}; }

std::string degrees(double rad) { return format_fixed(units::rad_to_deg(rad), 4); }

}  // namespace

ProgramError::ProgramError(const std::string& file, int line, const std::string& message)
    : Error(file + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + message) {}

std::string program_file_name(const std::string& request_id, Dialect dialect) {
  return "ncqual-" + request_id + (dialect == Dialect::LinuxCnc ? ".ngc" : ".nc");
}

std::string results_file_name(const std::string& request_id, Dialect dialect) {
  return "ncqual-" + request_id + (dialect == Dialect::GenericCsv ? ".csv" : ".txt");
}

std::string write_program(const CheckRequest& request, const MachineConfig& machine,
                          Dialect dialect, const std::string& version) {
  if (request.machine_id != machine.machine_id) {
    throw std::invalid_argument("the request is for machine '" + request.machine_id + "', not '" +
                                machine.machine_id + "'");
  }
  const TouchPlan plan = touch_plan(request, machine);
  if (!plan.error.empty()) throw std::invalid_argument(plan.error);
  const std::vector<ProbingMove>& moves = plan.moves;
  const ProbingConfig& p = machine.probing;
  double highest = -INFINITY;
  bool head = false;
  for (const ProbingMove& m : moves) {
    highest = std::max(highest, m.start.z_mm);
    head |= m.start.a_rad != 0 || m.start.c_rad != 0 || m.start.w_mm != 0;
  }
  const double safe_z = p.safe_z_mm.value_or(highest + kSafeZAboveHighestStartMm);
  const std::string results = results_file_name(request.request_id, dialect);

  Writer w(machine);
  if (dialect == Dialect::Fanuc) {
    w.line("%");
    w.line("O8000 (NCQUAL PROBING)");
  }
  w.comment("NCQUAL PROGRAM machine=" + machine.machine_id +
            " check=" + std::string(to_string(request.kind)) + " request=" + request.request_id +
            " dialect=" + std::string(to_string(dialect)) + " units=" + (p.inch ? "inch" : "mm") +
            " work_offset=" + p.work_offset + " touches=" + std::to_string(moves.size()) +
            " results=" + results);
  w.comment("NCQUAL VERSION " + version);
  for (const NamedValue& v : request.parameters) {
    w.comment("NCQUAL PARAMETER " + v.name + "=" + general(v.value));
  }
  w.comment("probing program of " + std::string(check_kind_info(request.kind).title));
  w.comment("X Y Z: the wrist pivot in " + p.work_offset + " = machine coordinates - [" +
            general(p.work_offset_mm.x()) + ", " + general(p.work_offset_mm.y()) + ", " +
            general(p.work_offset_mm.z()) + "] mm; angles in degrees");
  w.comment("tool length compensation off; no offset is changed; probe feed " +
            w.feed(p.probe_feed_mm_per_min) + ", approach " + w.feed(p.approach_feed_mm_per_min) +
            ", safe Z " + w.z(safe_z));
  w.line(std::string(p.inch ? "G20" : "G21") + " G90 G94 G17 G40 G49" +
         (dialect == Dialect::Fanuc ? " G80" : ""));
  w.line(p.work_offset);
  switch (dialect) {
    case Dialect::LinuxCnc: w.line("(PROBEOPEN " + results + ")"); break;
    case Dialect::Fanuc:
      w.line("POPEN");
      w.line("DPRNT[NCQUAL*" + request.request_id + "]");
      break;
    case Dialect::GenericCsv:
      w.comment("after each G31 the control writes n,x,y,z (pivot, program units) to " + results);
      break;
  }

  const std::string fanuc_xyz = p.inch ? "[45]" : "[54]";
  std::optional<ProbingMove> previous;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const ProbingMove& m = moves[i];
    const int n = static_cast<int>(i) + 1;
    const Eigen::Vector3d start = xyz_of(m.start);
    const bool same_head = previous && previous->start.a_rad == m.start.a_rad &&
                           previous->start.c_rad == m.start.c_rad &&
                           previous->start.w_mm == m.start.w_mm;
    if (!(same_head && (xyz_of(previous->start) - start).norm() < 1e-9)) {
      w.line("G0 Z" + w.z(safe_z));
      if (head && !same_head) {
        w.line("G0 A" + degrees(m.start.a_rad) + " C" + degrees(m.start.c_rad) +
               (m.start.w_mm != 0 || previous ? " W" + w.length(m.start.w_mm) : ""));
      }
      const Eigen::Vector3d q = w.program(start);
      w.line("G0 X" + w.length(q.x()) + " Y" + w.length(q.y()));
      w.line("G1 Z" + w.z(start.z()) + " F" + w.feed(p.approach_feed_mm_per_min));
    }
    w.comment("NCQUAL TOUCH " + std::to_string(n) + " feature=" + m.feature +
              " approach=" + general(m.direction.x()) + "," + general(m.direction.y()) + "," +
              general(m.direction.z()) + " w=" + w.length(m.start.w_mm) +
              " a=" + degrees(m.start.a_rad) + " c=" + degrees(m.start.c_rad));
    const Eigen::Vector3d target = start + m.travel_mm * m.direction;
    const std::string probe = dialect == Dialect::LinuxCnc ? "G38.2 " : "G31 ";
    w.line(probe + w.xyz(target) + " F" + w.feed(p.probe_feed_mm_per_min));
    if (dialect == Dialect::Fanuc) {
      const Eigen::Vector3d t = w.program(target);
      w.line("IF[[ABS[#5061-" + w.length(t.x()) + "]+ABS[#5062-" + w.length(t.y()) +
             "]+ABS[#5063-" + w.length(t.z()) + "]]LT" + w.length(kNoTripMm) +
             "]THEN#3000=1(NCQUAL NO TOUCH " + std::to_string(n) + ")");
      w.line("DPRNT[T" + std::to_string(n) + "*X#5061" + fanuc_xyz + "*Y#5062" + fanuc_xyz +
             "*Z#5063" + fanuc_xyz + "]");
    } else if (dialect == Dialect::GenericCsv) {
      w.comment("NCQUAL LOG " + std::to_string(n));
    }
    w.line("G1 " + w.xyz(start) + " F" + w.feed(p.approach_feed_mm_per_min));
    previous = m;
  }
  w.line("G0 Z" + w.z(safe_z));
  switch (dialect) {
    case Dialect::LinuxCnc:
      w.line("(PROBECLOSE)");
      w.line("M2");
      break;
    case Dialect::Fanuc:
      w.line("PCLOS");
      w.line("M30");
      w.line("%");
      break;
    case Dialect::GenericCsv: w.line("M2"); break;
  }
  return w.text();
}

ProgramDescription read_program(const std::string& text, const std::string& file) {
  ProgramDescription d;
  bool header = false;
  std::size_t declared = 0;
  const std::vector<std::string> lines = lines_of(text);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const int ln = static_cast<int>(i) + 1;
    const auto open = lines[i].find("(NCQUAL ");
    if (open == std::string::npos) continue;
    const auto close = lines[i].find(')', open);
    if (close == std::string::npos) throw ProgramError(file, ln, "NCQUAL comment without ')'");
    const std::string body = lines[i].substr(open + 8, close - open - 8);
    const auto space = body.find(' ');
    const std::string keyword = body.substr(0, space);
    const std::string rest = space == std::string::npos ? "" : body.substr(space + 1);
    if (keyword == "PROGRAM") {
      const auto f = fields_of(rest, file, ln);
      const std::string c = "NCQUAL PROGRAM";
      d.machine_id = field(f, "machine", c, file, ln);
      d.request_id = field(f, "request", c, file, ln);
      d.results_file = field(f, "results", c, file, ln);
      d.work_offset = field(f, "work_offset", c, file, ln);
      const std::string& check = field(f, "check", c, file, ln);
      const auto kind = parse_check_kind(check);
      if (!kind) throw ProgramError(file, ln, c + ": check = '" + check + "' is no check kind");
      d.kind = *kind;
      const std::string& dialect = field(f, "dialect", c, file, ln);
      const auto parsed = dialect_from(dialect);
      if (!parsed) {
        throw ProgramError(file, ln,
                           c + ": dialect = '" + dialect + "': expected one of " + dialect_names());
      }
      d.dialect = *parsed;
      const std::string& units = field(f, "units", c, file, ln);
      if (units != "mm" && units != "inch") {
        throw ProgramError(file, ln, c + ": units = '" + units + "': expected mm or inch");
      }
      d.inch = units == "inch";
      const std::string& touches = field(f, "touches", c, file, ln);
      const auto count = parse_integer(touches);
      if (!count) throw ProgramError(file, ln, c + ": touches = '" + touches + "' is no count");
      declared = static_cast<std::size_t>(*count);
      header = true;
    } else if (keyword == "VERSION") {
      d.version = rest;
    } else if (keyword == "PARAMETER") {
      const auto f = fields_of(rest, file, ln);
      if (f.size() != 1) throw ProgramError(file, ln, "NCQUAL PARAMETER: expected one name=value");
      NamedValue v;
      v.name = f.begin()->first;
      v.value = number_field(f, v.name, "NCQUAL PARAMETER", file, ln);
      d.parameters.push_back(v);
    } else if (keyword == "TOUCH") {
      const auto space2 = rest.find(' ');
      const std::string number = rest.substr(0, space2);
      const auto n = parse_integer(number);
      const std::string c = "NCQUAL TOUCH " + number;
      if (!n) throw ProgramError(file, ln, "NCQUAL TOUCH: '" + number + "' is no touch number");
      if (*n != static_cast<int>(d.touches.size()) + 1) {
        throw ProgramError(file, ln,
                           c + ": expected touch " + std::to_string(d.touches.size() + 1) +
                               " (touches are numbered from 1 in program order)");
      }
      const auto f =
          fields_of(space2 == std::string::npos ? "" : rest.substr(space2 + 1), file, ln);
      ProgramTouch t;
      t.number = *n;
      t.feature = field(f, "feature", c, file, ln);
      std::string approach = field(f, "approach", c, file, ln);
      std::replace(approach.begin(), approach.end(), ',', ' ');
      std::istringstream in(approach);
      std::string part;
      for (int k = 0; k < 3; ++k) {
        const auto v = in >> part ? parse_finite_number(part) : std::nullopt;
        if (!v) throw ProgramError(file, ln, c + ": approach is not dx,dy,dz");
        t.approach[k] = *v;
      }
      if (std::abs(t.approach.norm() - 1) > 1e-6) {
        throw ProgramError(file, ln, c + ": approach is not a unit vector");
      }
      const double to_mm = d.inch ? kMmPerInch : 1;
      t.w_mm = number_field(f, "w", c, file, ln) * to_mm;
      t.a_rad = units::deg_to_rad(number_field(f, "a", c, file, ln));
      t.c_rad = units::deg_to_rad(number_field(f, "c", c, file, ln));
      d.touches.push_back(t);
    }
  }
  if (!header) {
    throw ProgramError(file, 0,
                       "no (NCQUAL PROGRAM ...) comment: not a probing program written by "
                       "`ncqual program`");
  }
  if (declared != d.touches.size()) {
    throw ProgramError(file, 0,
                       "the header declares " + std::to_string(declared) +
                           " touches, the program has " + std::to_string(d.touches.size()) +
                           " (NCQUAL TOUCH ...) comments");
  }
  return d;
}

namespace {

// "T12X1200.1234Y-3.5Z.25" (spaces removed) -> the touch number and X, Y, Z.
LoggedTouch fanuc_touch(const std::string& raw, const std::string& file, int ln) {
  std::string s;
  for (char ch : raw) {
    if (!std::isspace(static_cast<unsigned char>(ch))) s += ch;
  }
  const auto x = s.find('X'), y = s.find('Y'), z = s.find('Z');
  if (s.empty() || s[0] != 'T' || x == std::string::npos || y == std::string::npos ||
      z == std::string::npos || !(x < y && y < z)) {
    throw ProgramError(file, ln, "'" + raw + "': expected T<touch> X<x> Y<y> Z<z>");
  }
  LoggedTouch t;
  t.line = ln;
  const auto n = parse_integer(s.substr(1, x - 1));
  if (!n) throw ProgramError(file, ln, "T = '" + s.substr(1, x - 1) + "' is no touch number");
  t.number = *n;
  const std::string parts[3] = {s.substr(x + 1, y - x - 1), s.substr(y + 1, z - y - 1),
                                s.substr(z + 1)};
  for (int k = 0; k < 3; ++k) {
    const auto v = parse_finite_number(parts[k]);
    if (!v) {
      throw ProgramError(file, ln,
                         std::string(1, "XYZ"[k]) + " = '" + parts[k] + "' is not a number");
    }
    t.position[k] = *v;
  }
  return t;
}

}  // namespace

TouchLog read_touch_log(const std::string& text, const std::string& file, Dialect dialect) {
  TouchLog log;
  const std::vector<std::string> lines = lines_of(text);
  bool first = true;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const int ln = static_cast<int>(i) + 1;
    const std::string line = trim(lines[i]);
    if (line.empty()) continue;
    if (dialect == Dialect::LinuxCnc) {
      std::istringstream words(line);
      std::string word;
      std::vector<double> values;
      while (words >> word) {
        const auto v = parse_finite_number(word);
        if (!v) {
          throw ProgramError(file, ln,
                             "field " + std::to_string(values.size() + 1) + " = '" + word +
                                 "' is not a number (LinuxCNC's probe log: X Y Z A B C U V W)");
        }
        values.push_back(*v);
      }
      if (values.size() < 3) {
        throw ProgramError(file, ln,
                           std::to_string(values.size()) +
                               " number(s): expected X Y Z A B C U V W (LinuxCNC's probe log)");
      }
      LoggedTouch t;
      t.line = ln;
      t.position = Eigen::Vector3d(values[0], values[1], values[2]);
      log.touches.push_back(t);
    } else if (dialect == Dialect::Fanuc) {
      if (line == "%") continue;
      if (first) {
        first = false;
        if (line.rfind("NCQUAL", 0) != 0) {
          throw ProgramError(file, ln,
                             "'" + line +
                                 "': the first line of a Fanuc touch log is NCQUAL "
                                 "<request id>");
        }
        log.request_id = trim(line.substr(6));
        continue;
      }
      log.touches.push_back(fanuc_touch(line, file, ln));
    } else {
      if (line[0] == '#') {
        const std::string c = trim(line.substr(1));
        if (c.rfind("request ", 0) == 0) log.request_id = trim(c.substr(8));
        continue;
      }
      std::string fields = line;
      for (char& ch : fields) {
        if (ch == ';' || ch == '\t') ch = ',';
      }
      std::vector<std::string> parts;
      std::istringstream in(fields);
      std::string part;
      while (std::getline(in, part, ',')) parts.push_back(trim(part));
      if (first && !parts.empty() && !parse_finite_number(parts[0])) {
        first = false;  // a header line: touch,x,y,z
        continue;
      }
      first = false;
      if (parts.size() != 4) {
        throw ProgramError(file, ln,
                           std::to_string(parts.size()) + " field(s): expected touch,x,y,z");
      }
      LoggedTouch t;
      t.line = ln;
      const auto n = parse_integer(parts[0]);
      if (!n) throw ProgramError(file, ln, "touch = '" + parts[0] + "' is no touch number");
      t.number = *n;
      for (int k = 0; k < 3; ++k) {
        const auto v = parse_finite_number(parts[static_cast<std::size_t>(k) + 1]);
        if (!v) {
          throw ProgramError(file, ln,
                             std::string(1, "xyz"[k]) + " = '" +
                                 parts[static_cast<std::size_t>(k) + 1] + "' is not a number");
        }
        t.position[k] = *v;
      }
      log.touches.push_back(t);
    }
  }
  return log;
}

MeasurementSet measurement_set_from_log(const ProgramDescription& program, const TouchLog& log,
                                        const std::string& log_file, const MachineConfig& machine,
                                        std::int64_t time_ns) {
  const std::string of_program = " (program of request " + program.request_id + ")";
  if (program.machine_id != machine.machine_id) {
    throw ProgramError(log_file, 0,
                       "the program was written for machine '" + program.machine_id + "', not '" +
                           machine.machine_id + "'");
  }
  if (program.work_offset != machine.probing.work_offset) {
    throw ProgramError(log_file, 0,
                       "the program uses " + program.work_offset + ", the machine config " +
                           machine.probing.work_offset + ": its coordinates cannot be converted");
  }
  if (log.request_id && *log.request_id != program.request_id) {
    throw ProgramError(log_file, 1,
                       "the log names request '" + *log.request_id + "': it is not the log of " +
                           "the program of request " + program.request_id);
  }
  const std::string base = log_file.substr(log_file.find_last_of('/') + 1);
  if (base.rfind("ncqual-", 0) == 0) {
    const auto dot = base.find_last_of('.');
    const std::string named = base.substr(7, dot == std::string::npos ? dot : dot - 7);
    if (named != program.request_id) {
      throw ProgramError(log_file, 0,
                         "the file is named for request '" + named + "': it is not the log of " +
                             "the program of request " + program.request_id);
    }
  }
  const std::size_t expected = program.touches.size();
  const std::size_t found = log.touches.size();
  const std::string counts =
      "expected " + std::to_string(expected) + " touches, found " + std::to_string(found);
  for (std::size_t i = 0; i < found; ++i) {
    const LoggedTouch& t = log.touches[i];
    if (!t.number) continue;
    const int want = static_cast<int>(i) + 1;
    if (*t.number > want) {
      throw ProgramError(log_file, t.line,
                         counts + "; touch " + std::to_string(want) +
                             " is missing (this line has " + "touch " + std::to_string(*t.number) +
                             ")" + of_program);
    }
    if (*t.number < want) {
      throw ProgramError(log_file, t.line,
                         counts + "; touch " + std::to_string(*t.number) +
                             " again, out of order (expected touch " + std::to_string(want) + ")" +
                             of_program);
    }
    if (*t.number > static_cast<int>(expected)) {
      throw ProgramError(
          log_file, t.line,
          counts + "; touch " + std::to_string(*t.number) + " is not in the program" + of_program);
    }
  }
  if (found != expected) {
    std::string why = counts;
    if (found < expected && !log.touches.empty() && log.touches.front().number) {
      why += "; the first missing is touch " + std::to_string(found + 1);
    }
    if (program.dialect == Dialect::LinuxCnc) {
      why +=
          " (LinuxCNC's probe log has no touch numbers; it leaves out a line equal to the one "
          "before, and a probing move that does not trip stops the program)";
    }
    throw ProgramError(log_file, 0, why + of_program);
  }
  MeasurementSet set;
  set.machine_id = program.machine_id;
  set.request_id = program.request_id;
  set.kind = program.kind;
  set.instrument = "touch_probe";
  set.frame = "machine";
  set.time_ns = time_ns;
  set.parameters = program.parameters;
  const double to_mm = program.inch ? kMmPerInch : 1;
  for (std::size_t i = 0; i < expected; ++i) {
    const ProgramTouch& p = program.touches[i];
    const Eigen::Vector3d pivot = log.touches[i].position * to_mm + machine.probing.work_offset_mm;
    Touch t;
    t.feature = p.feature;
    t.axes.x_mm = pivot.x();
    t.axes.y_mm = pivot.y();
    t.axes.z_mm = pivot.z();
    t.axes.w_mm = p.w_mm;
    t.axes.a_rad = p.a_rad;
    t.axes.c_rad = p.c_rad;
    t.approach = p.approach;
    set.touches.push_back(t);
  }
  return set;
}

}  // namespace ncqual::probing
