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
// A guarded move shorter than this is a straight G1 (LinuxCNC refuses a G38 move shorter than
// 0.254 mm).
constexpr double kShortestGuardedMoveMm = 0.5;
// A logged head this far from the program's: the touch was not taken where it declares.
constexpr double kHeadToleranceDeg = 0.001;
constexpr double kHeadToleranceMm = 0.001;

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
  // Fanuc: the alarm `number` with `message` when the skip position (#5061..#5063) is `LT` (the
  // move did not trip) or `GE` (it tripped) kNoTripMm from the move's end, a pivot position.
  std::string skip_alarm(const Eigen::Vector3d& end, const char* comparison, int number,
                         const std::string& message) const {
    const Eigen::Vector3d t = program(end);
    return "IF[[ABS[#5061-" + length(t.x()) + "]+ABS[#5062-" + length(t.y()) + "]+ABS[#5063-" +
           length(t.z()) + "]]" + comparison + length(kNoTripMm) +
           "]THEN#3000=" + std::to_string(number) + "(" + message + ")";
  }

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
  for (const ProbingMove& m : moves) {
    highest = std::max(highest, m.start.z_mm);
    for (const auto& [axis, value] : {std::pair{'W', m.start.w_mm}, std::pair{'A', m.start.a_rad},
                                      std::pair{'C', m.start.c_rad}}) {
      if (value != 0 && !p.has_axis(axis)) {
        throw std::invalid_argument(std::string(to_string(request.kind)) + " needs the " + axis +
                                    " axis (" + machine.machine_id + "'s probing.axes: " + p.axes +
                                    ")");
      }
    }
  }
  const double safe_z = p.safe_z_mm.value_or(highest + kSafeZAboveHighestStartMm);
  // Where the head turns: high enough that the probe clears the plan's features in any
  // orientation (the top of the Z travel where configured).
  const double retract_z = p.retract_z_mm.value_or(
      std::max(safe_z, highest + machine.probe.tool_length_mm + kSafeZAboveHighestStartMm));
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
            ", safe Z " + w.z(safe_z) + ", the head turns at machine Z " + w.length(retract_z));
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
  int guards = 0;
  // A move that stops when the probe trips before its end: the program then stops, naming it
  // (LinuxCNC G38.3 with #5070, Fanuc G31 with its skip position; generic-csv has no such move and
  // moves straight). Announced by (NCQUAL GUARD to=x,y,z) because LinuxCNC's probe log has a line
  // for it too.
  const auto guarded = [&](const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                           const std::string& what) {
    if ((to - from).norm() < kShortestGuardedMoveMm || dialect == Dialect::GenericCsv) {
      w.line("G1 " + w.xyz(to) + " F" + w.feed(p.approach_feed_mm_per_min));
      return;
    }
    const Eigen::Vector3d t = w.program(to);
    w.comment("NCQUAL GUARD to=" + w.length(t.x()) + "," + w.length(t.y()) + "," + w.length(t.z()));
    ++guards;
    if (dialect == Dialect::LinuxCnc) {
      const std::string o = "o" + std::to_string(1000 + guards);
      w.line("G38.3 " + w.xyz(to) + " F" + w.feed(p.approach_feed_mm_per_min));
      w.line(o + " if [#5070 NE 0]");
      w.line("  (ABORT, NCQUAL contact " + what + ": stopped)");
      w.line(o + " endif");
    } else {
      w.line("G31 " + w.xyz(to) + " F" + w.feed(p.approach_feed_mm_per_min));
      w.line(w.skip_alarm(to, "GE", 2, "NCQUAL CONTACT " + std::to_string(guards)));
    }
  };
  // W, A and C in machine coordinates, each axis the control has (the plan's head otherwise is
  // at home: refused above when it is not).
  const auto head = [&](const AxisPosition& a) {
    if (p.has_axis('W')) w.line("G53 G0 W" + w.length(a.w_mm));
    std::string turn;
    if (p.has_axis('A')) turn += " A" + degrees(a.a_rad);
    if (p.has_axis('C')) turn += " C" + degrees(a.c_rad);
    if (!turn.empty()) w.line("G53 G0" + turn);
  };
  const auto at_safe_z = [&](const Eigen::Vector3d& v) {
    return Eigen::Vector3d(v.x(), v.y(), safe_z);
  };
  w.comment("from any state: up to machine Z " + w.length(retract_z) +
            ", then the spindle and the head, in machine coordinates");
  w.line("G53 G0 Z" + w.length(retract_z));
  std::optional<ProbingMove> previous;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const ProbingMove& m = moves[i];
    const int n = static_cast<int>(i) + 1;
    const Eigen::Vector3d start = xyz_of(m.start);
    const bool same_head = previous && previous->start.a_rad == m.start.a_rad &&
                           previous->start.c_rad == m.start.c_rad &&
                           previous->start.w_mm == m.start.w_mm;
    if (!(same_head && (xyz_of(previous->start) - start).norm() < 1e-9)) {
      if (previous) {
        const Eigen::Vector3d from = xyz_of(previous->start);
        guarded(from, at_safe_z(from), "on the way up after touch " + std::to_string(n - 1));
      }
      const Eigen::Vector3d q = w.program(start);
      if (!same_head) {
        // The head turns only up at the retract Z, then comes down over the start.
        if (previous) w.line("G53 G0 Z" + w.length(retract_z));
        head(m.start);
        w.line("G0 X" + w.length(q.x()) + " Y" + w.length(q.y()));
        w.line("G0 Z" + w.z(safe_z));
      } else {
        w.line("G0 X" + w.length(q.x()) + " Y" + w.length(q.y()));
      }
      guarded(at_safe_z(start), start, "on the way down to touch " + std::to_string(n));
    }
    w.comment("NCQUAL TOUCH " + std::to_string(n) + " feature=" + m.feature +
              " approach=" + general(m.direction.x()) + "," + general(m.direction.y()) + "," +
              general(m.direction.z()) + " w=" + w.length(m.start.w_mm) +
              " a=" + degrees(m.start.a_rad) + " c=" + degrees(m.start.c_rad));
    const Eigen::Vector3d target = start + m.travel_mm * m.direction;
    const std::string probe = dialect == Dialect::LinuxCnc ? "G38.2 " : "G31 ";
    w.line(probe + w.xyz(target) + " F" + w.feed(p.probe_feed_mm_per_min));
    if (dialect == Dialect::Fanuc) {
      w.line(w.skip_alarm(target, "LT", 1, "NCQUAL NO TOUCH " + std::to_string(n)));
      w.line("DPRNT[T" + std::to_string(n) + "*X#5061" + fanuc_xyz + "*Y#5062" + fanuc_xyz +
             "*Z#5063" + fanuc_xyz + "]");
    } else if (dialect == Dialect::GenericCsv) {
      w.comment("NCQUAL LOG " + std::to_string(n));
    }
    // Back along the probing move's own path, free by construction.
    w.line("G1 " + w.xyz(start) + " F" + w.feed(p.approach_feed_mm_per_min));
    previous = m;
  }
  if (previous) {
    const Eigen::Vector3d from = xyz_of(previous->start);
    guarded(from, at_safe_z(from), "on the way up after touch " + std::to_string(moves.size()));
  }
  w.line("G53 G0 Z" + w.length(retract_z));
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
      d.probe_moves.push_back({t.number, Eigen::Vector3d::Zero()});
    } else if (keyword == "GUARD") {
      const auto f = fields_of(rest, file, ln);
      std::string to = field(f, "to", "NCQUAL GUARD", file, ln);
      std::replace(to.begin(), to.end(), ',', ' ');
      std::istringstream in(to);
      std::string part;
      ProbeMove g;
      for (int k = 0; k < 3; ++k) {
        const auto v = in >> part ? parse_finite_number(part) : std::nullopt;
        if (!v) throw ProgramError(file, ln, "NCQUAL GUARD: to = '" + to + "' is not x,y,z");
        g.guard_to[k] = *v;
      }
      d.probe_moves.push_back(g);
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
      if (values.size() >= 9) t.head = Eigen::Vector3d(values[3], values[5], values[8]);
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
  // LinuxCNC logs every probing move: the guarded moves' lines are left out here.
  std::vector<LoggedTouch> logged = log.touches;
  if (program.dialect == Dialect::LinuxCnc && program.probe_moves.size() > program.touches.size()) {
    const std::size_t moves = program.probe_moves.size();
    if (logged.size() > moves) {
      throw ProgramError(
          log_file, logged[moves].line,
          std::to_string(logged.size()) + " lines, the program has " + std::to_string(moves) +
              " probing moves (" + std::to_string(program.touches.size()) + " touches and " +
              std::to_string(moves - program.touches.size()) + " guarded moves)" + of_program);
    }
    std::vector<LoggedTouch> kept;
    for (std::size_t i = 0; i < logged.size(); ++i) {
      if (program.probe_moves[i].touch != 0) kept.push_back(logged[i]);
    }
    logged = std::move(kept);
  }
  const std::size_t expected = program.touches.size();
  const std::size_t found = logged.size();
  const std::string counts =
      "expected " + std::to_string(expected) + " touches, found " + std::to_string(found);
  for (std::size_t i = 0; i < found; ++i) {
    const LoggedTouch& t = logged[i];
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
    if (found < expected && !logged.empty() && logged.front().number) {
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
  set.origin = DataOrigin::Measured;  // a control's log: its probe touched the machine
  set.parameters = program.parameters;
  const double to_mm = program.inch ? kMmPerInch : 1;
  for (std::size_t i = 0; i < expected; ++i) {
    const ProgramTouch& p = program.touches[i];
    const LoggedTouch& logged_touch = logged[i];
    if (logged_touch.head) {
      // Where the control's head was when the probe tripped: as the program declares it, or the
      // touch was taken with another probe direction (a head not commanded, a rotary work offset).
      const Eigen::Vector3d& h = *logged_touch.head;
      const double da = std::remainder(h.x() - units::rad_to_deg(p.a_rad), 360.0);
      const double dc = std::remainder(h.y() - units::rad_to_deg(p.c_rad), 360.0);
      const double dw = h.z() * to_mm - p.w_mm;
      if (std::abs(da) > kHeadToleranceDeg || std::abs(dc) > kHeadToleranceDeg ||
          std::abs(dw) > kHeadToleranceMm) {
        throw ProgramError(log_file, logged_touch.line,
                           "touch " + std::to_string(i + 1) + " was taken at A " +
                               format_fixed(h.x(), 4) + ", C " + format_fixed(h.y(), 4) + ", W " +
                               format_fixed(h.z(), 4) + "; the program declares a " +
                               format_fixed(units::rad_to_deg(p.a_rad), 4) + ", c " +
                               format_fixed(units::rad_to_deg(p.c_rad), 4) + ", w " +
                               format_fixed(p.w_mm / to_mm, 4) +
                               " (a head the program did not command, or a work offset on A, C "
                               "or W)" +
                               of_program);
      }
    }
    const Eigen::Vector3d pivot = logged_touch.position * to_mm + machine.probing.work_offset_mm;
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
