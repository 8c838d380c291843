// SPDX-License-Identifier: Apache-2.0
// Plausibility against the machine: the envelope of its monthly programs, and the refusal of an
// ISO 230-2, circle or grid file that no instrument on it can have measured.
#include "ncqual/solver/instrument_files.hpp"

#include "instrument_columns.hpp"
#include "ncqual/common/check_kinds.hpp"
#include "result_building.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::solver {

using namespace detail;  // instrument_columns.hpp

double Envelope::span_mm() const { return std::max(100.0, (hi_mm - lo_mm).maxCoeff()); }

Envelope machine_envelope(const GlobalCheckConfig& config) {
  Envelope e;
  e.lo_mm = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  e.hi_mm = -e.lo_mm;
  for (const auto& info : check_kinds()) {
    if (!is_tracker_check(info.kind)) continue;
    for (const TrackerMove& m : global_check_program(info.kind, config)) {
      const Eigen::Vector3d p(m.commanded.x_mm, m.commanded.y_mm, m.commanded.z_mm);
      e.lo_mm = e.lo_mm.cwiseMin(p);
      e.hi_mm = e.hi_mm.cwiseMax(p);
    }
  }
  if (!e.lo_mm.allFinite()) e.lo_mm = e.hi_mm = Eigen::Vector3d::Zero();
  return e;
}

namespace {

using detail::format_number;

constexpr double kSpansBeyond = 10;      // how far beyond the envelope a position may lie
constexpr double kDeviationShare = 0.1;  // how large a deviation may be, as a share of the span

std::string mm(double v) { return format_number(v) + " mm"; }

std::string envelope_text(const Envelope& e) {
  std::string out = "the machine's envelope";
  const char* const axes = "XYZ";
  for (int k = 0; k < 3; ++k) {
    out += std::string(k ? "," : "") + " " + axes[k] + " " + format_number(e.lo_mm[k]) + ".." +
           format_number(e.hi_mm[k]);
  }
  return out + " mm (span " + mm(e.span_mm()) + ", from its monthly programs)";
}

// A position in column `c` of `row` on machine axis `axis` (-1: an offset about the centre,
// compared with ten spans either way).
void check_position(const CsvTable& t, const CsvRow& row, std::size_t c, int axis,
                    const Envelope& e, double to_mm = 1) {
  const double v = t.number(row, c) * to_mm;
  const double reach = kSpansBeyond * e.span_mm();
  const double lo = axis < 0 ? -reach : e.lo_mm[axis] - reach;
  const double hi = axis < 0 ? reach : e.hi_mm[axis] + reach;
  if (v >= lo && v <= hi) return;
  t.fail(row.line, c,
         "column '" + t.header[c] + "' = '" + t.cell(row, c) + "': beyond " + format_number(lo) +
             ".." + format_number(hi) + " mm, ten spans round " + envelope_text(e) +
             "; a file in another unit?");
}

}  // namespace

void check_iso230_2_envelope(const CsvTable& t, int axis, const Envelope& e) {
  const Iso230_2Columns c = iso230_2_columns(t, false);
  const double most = kDeviationShare * e.span_mm();
  for (const ReadingCells& r : reading_cells(t, c, false)) {
    const CsvRow& row = *r.row;
    check_position(t, row, c.target.index, axis, e, c.target.to_mm);
    const double deviation = measured_mm(t, r) - target_mm(t, r);
    if (std::abs(deviation) > most) {
      t.fail(row.line, r.value->index,
             "column '" + t.header[r.value->index] + "' = '" + t.cell(row, r.value->index) +
                 "': " + mm(deviation) + " from " + t.header[c.target.index] + " " +
                 t.cell(row, c.target.index) + ", more than " + mm(most) +
                 ", a tenth of the span of " + envelope_text(e));
    }
  }
}

void check_circle_envelope(const CsvTable& t, const Envelope& e, std::optional<Plane> plane,
                           std::optional<double> nominal_radius_mm) {
  const CircleColumns c = circle_columns(t, plane, nominal_radius_mm, false);
  const double most = kDeviationShare * e.span_mm();
  for (const CsvRow& row : t.rows) {
    if (!c.polar) {
      check_position(t, row, c.u.index, -1, e, c.u.to_mm);
      check_position(t, row, c.v.index, -1, e, c.v.to_mm);
    } else if (c.radius) {
      check_position(t, row, c.radius->index, -1, e, c.radius->to_mm);
    } else {
      const double deviation = length_mm(t, row, *c.deviation);
      if (std::abs(deviation) > most) {
        t.fail(row.line, c.deviation->index,
               "column '" + t.header[c.deviation->index] + "' = '" +
                   t.cell(row, c.deviation->index) + "': a radial deviation of " + mm(deviation) +
                   ", more than " + mm(most) + ", a tenth of the span of " + envelope_text(e) +
                   "; a file in another unit?");
      }
    }
  }
}

void check_grid_envelope(const CsvTable& t, const std::vector<GridFilePoint>& points,
                         const Envelope& e) {
  if (points.empty()) return;
  // The cells of the measured x: a grid file's x_meas, an export's x.
  const bool exported = is_tracker_point_export(t);
  std::size_t x_column = 0;
  if (exported) {  // an export's commanded positions are the program's
    x_column = find_coordinate_column(t, {"x"})->index;
  } else {  // a grid file's are its own
    const GridColumns c = grid_columns(t);
    x_column = c.measured[0];
    for (const CsvRow& row : t.rows) {
      for (int k = 0; k < 3; ++k) check_position(t, row, c.commanded[k], k, e);
    }
  }
  const double most = kDeviationShare * e.span_mm();
  const GridFilePoint& first = points.front();
  for (const GridFilePoint& p : points) {
    const double commanded = (p.commanded_mm - first.commanded_mm).norm();
    const double measured = (p.measured_mm - first.measured_mm).norm();
    if (std::abs(measured - commanded) > most) {
      t.fail(p.line, x_column,
             "measured " + mm(measured) + " from the first point (" + first.point + ", line " +
                 std::to_string(first.line) + ") where " +
                 (exported ? "the program commands " : "commanded ") + mm(commanded) +
                 ": more than " + mm(most) + " apart, a tenth of the span of " + envelope_text(e) +
                 "; a file in another unit?");
    }
  }
}

}  // namespace ncqual::solver
