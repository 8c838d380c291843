// SPDX-License-Identifier: Apache-2.0
// The report's HTML (machine_report.hpp, docs/report.md): the gathered data as sections with
// inline SVG charts of ncqual_charts. Text in, text out; every text escaped.
#include "ncqual/report/machine_report.hpp"

#include "ncqual/charts/charts.hpp"
#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace ncqual::report {
namespace {

namespace svg = charts::svg;

charts::DisplayUnit micrometres() { return {1000, "µm"}; }

std::string esc(std::string_view text) { return svg::escape(text); }

// "2026-03-02 07:00 +01:00 CET": in the plant's zone with the offset, as `ncqual status` has it.
std::string when(const MachineReport& r, std::int64_t ns) { return r.calendar.local_text(ns); }
// The date alone ("2026-03-02") at a local midnight, else when().
std::string day_or_time(const MachineReport& r, std::int64_t ns) {
  const std::string day = r.calendar.local_text(ns).substr(0, 10);
  return r.calendar.parse_time(day) == ns ? day : when(r, ns);
}
// A chart's time axis in the plant's zone: ticks on local days, labels of its wall clock.
charts::TimeZone chart_zone(const MachineReport& r) {
  const Calendar* cal = &r.calendar;
  return {[cal](std::int64_t t) { return cal->wall_ns(t); },
          [cal](std::int64_t wall) { return cal->from_wall_ns(wall); },
          [cal](std::int64_t t) { return cal->local_text(t); }};
}

// The local date of a time.
std::string local_day(const MachineReport& r, std::int64_t ns) {
  return r.calendar.local_text(ns).substr(0, 10);
}

// Where the report looks: "since 2026-01-05", "in check daily-1", "in the historian".
std::string range_phrase(const MachineReport& r) {
  if (r.check_id) return "in check " + *r.check_id;
  if (r.since_ns) return "since " + day_or_time(r, *r.since_ns);
  return "in the historian";
}

// One sentence for a section without data.
std::string none_sentence(const std::string& what, const MachineReport& r) {
  return "<p class=\"none\">No " + esc(what) + " " + esc(range_phrase(r)) + ".</p>\n";
}

std::string verdict_cell(const std::optional<Verdict>& v) {
  if (!v) return "<span class=\"verdict none\">no result</span>";
  const std::string name(to_string(*v));
  std::string lower = name;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return "<span class=\"verdict " + lower + "\">" + esc(name) + "</span>";
}

// A length for people: mm shown in µm, never "-0.0".
std::string um(double mm, int decimals = 1) { return svg::fixed(mm * 1000, decimals) + " µm"; }

std::string check_title(const MachineReport& r, const ReportedCheck& c) {
  return std::string(check_kind_info(c.kind).title) + " — " + c.request_id + ", " +
         when(r, c.time_ns);
}

// The marker of a check whose numbers ncqual's simulator produced; nothing for measured data.
std::string origin_badge(DataOrigin origin) {
  return origin == DataOrigin::Simulated ? " <span class=\"origin-badge simulated\" "
                                           "title=\"produced by ncqual's simulator: says "
                                           "nothing about the machine\">SIMULATED</span>"
                                         : "";
}

// The origin cell of the checks table.
std::string origin_cell(DataOrigin origin) {
  switch (origin) {
    case DataOrigin::Simulated: return origin_badge(origin);
    case DataOrigin::Measured: return "measured";
    case DataOrigin::Unknown: break;
  }
  return "<span class=\"origin unknown\">not recorded</span>";
}

std::string check_line(const MachineReport& r, const ReportedCheck& c) {
  return "<p class=\"check\">" + esc(check_title(r, c)) + ": " + verdict_cell(c.verdict) +
         origin_badge(c.origin) + "</p>\n";
}

// ---- 0. Simulated data -----------------------------------------------------------------------

// A banner above everything when any check of the report is the simulator's: its verdicts and
// charts say nothing about a machine. A report of measured data has none; checks stored before the
// historian recorded their origin get a quiet note.
std::string origin_banner(const MachineReport& r) {
  std::size_t simulated = 0, unknown = 0;
  for (const auto& c : r.checks) {
    const DataOrigin origin = storage::origin_of(c);
    simulated += origin == DataOrigin::Simulated ? 1 : 0;
    unknown += origin == DataOrigin::Unknown ? 1 : 0;
  }
  std::string h;
  if (simulated > 0) {
    const std::string which =
        simulated == r.checks.size()
            ? (r.checks.size() == 1
                   ? std::string("this check was")
                   : "all " + std::to_string(simulated) + " checks " + range_phrase(r) + " were")
            : std::to_string(simulated) + " of the " + std::to_string(r.checks.size()) +
                  " checks " + range_phrase(r) + " (marked SIMULATED) were";
    h += "<div class=\"ncqual-simulated-banner\" role=\"alert\"><strong>SIMULATED DATA</strong>: " +
         esc(which) +
         " produced by ncqual's simulator, not measured on a machine: the verdicts, charts and "
         "figures of such checks say nothing about " +
         esc(r.machine_id) + "'s accuracy.</div>\n";
  }
  if (unknown > 0) {
    h += "<p class=\"origin-note\">" + esc(std::to_string(unknown)) + " of the " +
         esc(std::to_string(r.checks.size())) +
         " checks do not say whether they were measured or simulated (stored before the "
         "historian recorded it).</p>\n";
  }
  return h;
}

std::string figure(const std::string& svg_text) {
  return "<figure class=\"chart\">" + svg_text + "</figure>\n";
}

// ---- 1. State ------------------------------------------------------------------------------

std::string state_section(const MachineReport& r) {
  // The simulated-data banner first: above everything the report says.
  std::string h = "<section class=\"ncqual-report-state\">\n" + origin_banner(r) + "<h2>State of " +
                  esc(r.machine_id) + "</h2>\n";
  h += "<p class=\"asof\">As of " + esc(when(r, r.now_ns)) + "; checks " + esc(range_phrase(r)) +
       (r.configured ? "" : "; no machine configuration given") + ".</p>\n";
  if (!r.status) {
    h += "<p class=\"none\">No status of " + esc(r.machine_id) + " is stored.</p>\n";
  } else {
    const MachineStatus& s = *r.status;
    const std::string state(to_string(s.state));
    h += "<table class=\"status\"><tbody>\n";
    h += "<tr><th>state</th><td><span class=\"state " + esc(state) + "\">" + esc(state) +
         "</span></td></tr>\n";
    h += "<tr><th>since</th><td>" + esc(when(r, s.time_ns)) + "</td></tr>\n";
    if (!s.detail.empty()) h += "<tr><th>detail</th><td>" + esc(s.detail) + "</td></tr>\n";
    if (s.last_kind) {
      h += "<tr><th>last check</th><td>" + esc(to_string(*s.last_kind)) +
           (s.request_id.empty() ? "" : " (" + esc(s.request_id) + ")") + " " +
           verdict_cell(s.last_verdict) + "</td></tr>\n";
    }
    h += "</tbody></table>\n";
  }
  h += "<h3>Trend warnings</h3>\n";
  if (r.warnings.empty()) {
    h += "<p class=\"none\">No trend warning was ever raised for " + esc(r.machine_id) + ".</p>\n";
  } else {
    h += "<ul class=\"warnings\">\n";
    for (const auto& w : r.warnings) {
      h += std::string("<li class=\"warning ") + (w.active() ? "active" : "ended") + "\">";
      h += std::string("<strong>") + (w.active() ? "active" : "ended") + "</strong> " +
           esc(w.metric) + " (" + esc(w.kind) + ", " + esc(w.side) + "), raised " +
           esc(when(r, w.raised_ns)) + " by " + esc(w.raised_by);
      if (w.ended_ns) {
        h += ", ended " + esc(when(r, *w.ended_ns)) + (w.ended_by ? " by " + esc(*w.ended_by) : "");
      }
      h += ": " + esc(w.text) + "</li>\n";
    }
    h += "</ul>\n";
    if (r.ended_warnings_not_listed > 0) {
      h += "<p class=\"more\">" + std::to_string(r.ended_warnings_not_listed) +
           " older ended warnings are not listed: <code>ncqual trend --machine " +
           esc(r.machine_id) + " --metric NAME</code> lists those of a metric.</p>\n";
    }
  }
  return h + "</section>\n";
}

// ---- 2. Monthly grid -----------------------------------------------------------------------

// The number of a grid point: i of "grid:<i>:t<k>"; else its position + 1.
int point_number(const std::string& label, std::size_t position) {
  const auto colon = label.find(':');
  if (colon != std::string::npos) {
    const auto end = label.find(':', colon + 1);
    const std::string digits = label.substr(colon + 1, end - colon - 1);
    if (!digits.empty() && digits.size() < 7 &&
        digits.find_first_not_of("0123456789") == std::string::npos) {
      return std::stoi(digits);
    }
  }
  return static_cast<int>(position) + 1;
}

std::string grid_section(const MachineReport& r) {
  std::string h = "<section class=\"ncqual-report-grid\">\n<h2>Monthly grid</h2>\n";
  if (!r.grid) return h + none_sentence("monthly grid", r) + "</section>\n";
  const GridSection& g = *r.grid;
  h += check_line(r, g.check);
  if (!g.check.error.empty()) {
    return h + "<p class=\"none\">The grid's charts cannot be drawn: " + esc(g.check.error) +
           ".</p>\n</section>\n";
  }
  const double tol = g.tolerance_mm.value_or(0);
  h += "<p class=\"how\">Per constant-Z plane: each nominal point's X/Y deviation (measured in "
       "the master frame minus commanded) as an arrow, magnified so that the largest is at most "
       "0.8 of the points' spacing and at least 8 px long (the chart says by how much, with a "
       "scale bar), against its tolerance circle" +
       std::string(g.tolerance_mm ? " (radius " + esc(um(tol)) +
                                        ", the grid's maximum deviation; left out when at that "
                                        "magnification it would cover the neighbouring points: "
                                        "the points out of tolerance are red)"
                                  : " (the result has no tolerance)") +
       ", and the Z deviation by point number with the tolerance limits dashed.</p>\n";
  for (const GridPlane& plane : g.planes) {
    const std::string z = fmt::format("{:.1f}", plane.z_mm);
    h += "<div class=\"plane\"><h3>Plane Z = " + esc(z) + " mm</h3>\n";
    charts::DeviationVectorPlot v;
    v.title = r.machine_id + ": grid plane Z = " + z + " mm, X/Y deviation";
    v.description = "Check " + g.check.request_id + ".";
    v.unit = micrometres();
    v.tolerance = tol;
    charts::PointDeviationChart zc;
    zc.title = r.machine_id + ": grid plane Z = " + z + " mm, Z deviation";
    zc.description = v.description;
    zc.quantity = "Z deviation";
    zc.unit = micrometres();
    if (g.tolerance_mm) zc.tolerance = {-tol, tol};
    for (std::size_t i = 0; i < plane.points.size(); ++i) {
      const solver::GridPointResult& p = plane.points[i];
      charts::PlaneDeviation d;
      d.x = p.commanded_mm.x();
      d.y = p.commanded_mm.y();
      d.dx = p.deviation_mm.x();
      d.dy = p.deviation_mm.y();
      d.label = p.label;
      if (g.tolerance_mm) d.out_of_tolerance = p.deviation_norm_mm > tol;
      v.points.push_back(d);
      zc.points.push_back({point_number(p.label, i), p.deviation_mm.z(), p.label});
    }
    // Both axes at one scale: a plot as wide as the trend charts, as high as the plane's shape
    // asks (within 320..720 px), so a long, narrow envelope does not leave half the plot empty.
    double x_lo = 0, x_hi = 0, y_lo = 0, y_hi = 0;
    for (std::size_t i = 0; i < v.points.size(); ++i) {
      const auto& p = v.points[i];
      x_lo = i ? std::min(x_lo, p.x) : p.x;
      x_hi = i ? std::max(x_hi, p.x) : p.x;
      y_lo = i ? std::min(y_lo, p.y) : p.y;
      y_hi = i ? std::max(y_hi, p.y) : p.y;
    }
    if (x_hi > x_lo && y_hi > y_lo) {
      v.size = {720, std::clamp(560 * (y_hi - y_lo) / (x_hi - x_lo) + 200, 320.0, 720.0)};
    }
    h += figure(charts::deviation_vector_plot(v)) + figure(charts::point_deviation_chart(zc)) +
         "</div>\n";
  }
  return h + "</section>\n";
}

// ---- 3. ISO 230-2 run and circular tests ---------------------------------------------------

const char* axis_name(int axis) { return axis == 0 ? "X" : axis == 1 ? "Y" : "Z"; }

std::string figure_row(const std::string& name, const std::optional<double>& mm) {
  return mm ? "<tr><th>" + esc(name) + "</th><td>" + esc(um(*mm)) + "</td></tr>" : "";
}

std::string linear_section(const MachineReport& r) {
  std::string h =
      "<section class=\"ncqual-report-linear\">\n<h2>Linear axis positioning (ISO 230-2)</h2>\n";
  if (!r.linear_run) return h + none_sentence("ISO 230-2 linear axis run", r) + "</section>\n";
  const LinearRunSection& s = *r.linear_run;
  h += check_line(r, s.check);
  if (!s.evaluation) {
    return h + "<p class=\"none\">The run's chart cannot be drawn: " + esc(s.check.error) +
           ".</p>\n</section>\n";
  }
  const solver::Iso230_2Result& iso = s.evaluation->result;
  charts::PositioningChart c;
  c.axis_name = axis_name(s.evaluation->axis);
  c.title = r.machine_id + ": " + c.axis_name + " axis, bidirectional positioning";
  c.description = "Check " + s.check.request_id + ".";
  c.unit = micrometres();
  for (const auto& t : iso.targets) {
    charts::PositioningTarget p;
    p.position = t.target_mm;
    if (t.up) p.up = charts::DirectionStats{t.up->mean_mm, t.up->s_mm};
    if (t.down) p.down = charts::DirectionStats{t.down->mean_mm, t.down->s_mm};
    c.targets.push_back(p);
  }
  h += figure(charts::positioning_chart(c));
  h += "<table class=\"figures\"><tbody>" + figure_row("accuracy A", iso.A_mm) +
       figure_row("systematic deviation E", iso.E_mm) + figure_row("repeatability R", iso.R_mm) +
       figure_row("reversal B", iso.B_mm) + figure_row("range of mean deviation M", iso.M_mm) +
       figure_row("tolerance of A", s.tolerance_mm) + "</tbody></table>\n";
  return h + "</section>\n";
}

std::string circles_section(const MachineReport& r) {
  std::string h =
      "<section class=\"ncqual-report-circles\">\n<h2>Circular tests "
      "(ISO 230-4)</h2>\n";
  if (r.circles.empty()) return h + none_sentence("circular test", r) + "</section>\n";
  h += "<p class=\"how\">The radial deviation from the nominal circle against the angle, both "
       "directions, magnified around the reference circle.</p>\n";
  for (const CircleSection& s : r.circles) {
    h += "<div class=\"circle\">" + check_line(r, s.check);
    if (!s.evaluation) {
      h += "<p class=\"none\">The test's chart cannot be drawn: " + esc(s.check.error) +
           ".</p></div>\n";
      continue;
    }
    const solver::CircularTestResult& res = s.evaluation->result;
    const std::string plane(solver::to_string(res.plane));
    charts::PolarChart c;
    c.title = r.machine_id + ": circle in " + plane;
    c.description = "Check " + s.check.request_id + ".";
    c.u_name = plane.substr(0, 1);
    c.v_name = plane.substr(1, 1);
    c.unit = micrometres();
    charts::PolarTrace ccw{"CCW", {}}, cw{"CW", {}};
    for (const auto& p : s.evaluation->input.points) {
      const solver::RadialDeviation d = solver::radial_deviation_about(p.uv_mm, res.F_reference);
      (p.direction == solver::PathDirection::Ccw ? ccw : cw)
          .samples.push_back({d.angle_rad, d.deviation_mm});
    }
    // Deviations below the instrument's resolution are not magnified into a shape: rings at
    // least 1 µm apart.
    double largest_um = 0;
    for (const auto* t : {&ccw, &cw}) {
      for (const auto& sample : t->samples) {
        largest_um = std::max(largest_um, std::abs(sample.deviation) * 1000);
      }
    }
    if (largest_um < 3) c.ring_step = 1.0;
    if (!ccw.samples.empty()) c.traces.push_back(ccw);
    if (!cw.samples.empty()) c.traces.push_back(cw);
    h += figure(charts::polar_chart(c));
    h += "<table class=\"figures\"><tbody>" + figure_row("circular deviation G", res.G_mm) +
         figure_row("bidirectional G(b)", res.G_b_mm) + figure_row("hysteresis H", res.H_mm) +
         figure_row("radial deviation F max", res.F_max_mm) +
         figure_row("radial deviation F min", res.F_min_mm) +
         figure_row("tolerance of G", s.tolerance_mm) + "</tbody></table></div>\n";
  }
  return h + "</section>\n";
}

// ---- 4. Trends -----------------------------------------------------------------------------

charts::DisplayUnit display_unit(const std::string& unit) {
  if (unit == "mm") return micrometres();
  if (unit == "rad") return {1e6, "µrad"};  // angular errors are µrad-sized: µrad, not 0.000767°
  if (unit == "urad") return {1, "µrad"};
  if (unit == "um") return {1, "µm"};
  if (unit == "um/m") return {1, "µm/m"};
  return {1, unit};
}

std::string trend_figures(const MachineReport& r, const MetricTrend& t) {
  std::vector<std::string> parts;
  parts.push_back(std::to_string(t.checks) + (t.checks == 1 ? " check" : " checks"));
  if (t.pass_rate.rate) parts.push_back(fmt::format("pass rate {:.0f} %", 100 * *t.pass_rate.rate));
  if (t.capability.cpk) parts.push_back(fmt::format("Cpk {:.2f}", *t.capability.cpk));
  const TrendForecast& f = t.least_squares;
  if (f.error.empty() && f.points > 0) {
    const charts::DisplayUnit u = display_unit(t.unit);
    parts.push_back(fmt::format("slope {:.3g} {}/day", f.slope_per_day * u.scale, u.unit));
    if (f.expected.status == "date" && f.expected.time_ns) {
      parts.push_back("expected to cross its limit " + local_day(r, *f.expected.time_ns));
    }
  }
  if (!t.error.empty()) parts.push_back(t.error);
  std::string out;
  for (const auto& p : parts) out += (out.empty() ? "" : "; ") + p;
  return out;
}

std::string trends_section(const MachineReport& r) {
  std::string h = "<section class=\"ncqual-report-trends\">\n<h2>Trends</h2>\n";
  if (r.trends.empty()) return h + none_sentence("metric trend", r) + "</section>\n";
  h += "<p class=\"how\">The metrics to look at (those with a trend warning, then those out "
       "of tolerance, then the nearest their tolerance; " +
       std::to_string(kMaxTrendCharts) +
       " at most) over time: the tolerance band (grey), control limits (dashed), the "
       "least-squares forecast with its 95 % prediction band, and the interventions and "
       "compensations that restart a series.</p>\n";
  std::string singles;
  for (const MetricTrend& t : r.trends) {
    if (t.checks < 2) {
      // One value is no trend: a row of the table below.
      for (const auto& p : t.points) {
        const charts::DisplayUnit u = display_unit(t.unit);
        auto shown = [&](const std::optional<double>& v) {
          return v ? svg::fixed(*v * u.scale, u.scale >= 1000 ? 1 : 2) : std::string("—");
        };
        const bool outside =
            p.value && ((p.lower && *p.value < *p.lower) || (p.upper && *p.value > *p.upper));
        singles += std::string(outside ? "<tr class=\"over\">" : "<tr>") + "<td>" + esc(t.metric) +
                   "</td><td>" + esc(shown(p.value)) + "</td><td>" +
                   esc("[" + shown(p.lower) + ", " + shown(p.upper) + "]") + "</td><td>" +
                   esc(u.unit) + "</td><td>" + esc(p.request_id) + "</td><td>" +
                   esc(when(r, p.time_ns)) + "</td></tr>\n";
      }
      continue;
    }
    charts::TrendChart c;
    c.title = r.machine_id + ": " + t.metric;
    c.quantity = t.metric;
    c.unit = display_unit(t.unit);
    c.zone = chart_zone(r);
    c.time_title = "date (" + r.calendar.zone_name() + ")";
    std::int64_t lo = std::numeric_limits<std::int64_t>::max(), hi = r.now_ns;
    for (const auto& p : t.points) {
      lo = std::min(lo, p.time_ns);
      hi = std::max(hi, p.time_ns);
      if (!p.value) continue;
      // Failed: this metric outside its own band (the check's verdict may concern another).
      const bool outside = (p.lower && *p.value < *p.lower) || (p.upper && *p.value > *p.upper);
      c.points.push_back({p.time_ns, *p.value, outside, p.request_id});
    }
    c.tolerance = {t.lower.value_or(-charts::kNoLimit), t.upper.value_or(charts::kNoLimit)};
    if (t.error.empty() && t.baseline.error.empty() && t.baseline.points > 0) {
      // A one-sided metric has the control limit of its watched side only.
      const double nan = std::numeric_limits<double>::quiet_NaN();
      c.control = charts::ControlLimits{
          t.baseline.mean, t.baseline.watched == "above" ? nan : t.baseline.lower_control_limit,
          t.baseline.watched == "below" ? nan : t.baseline.upper_control_limit};
    }
    if (!t.prediction.empty()) {
      charts::Forecast f;
      for (const auto& s : t.prediction)
        f.samples.push_back({s.time_ns, s.fitted, s.lower, s.upper});
      if (t.least_squares.expected.status == "date") {
        f.crossing_ns = t.least_squares.expected.time_ns;
      }
      hi = std::max(hi, f.samples.back().time_ns);
      c.forecast = std::move(f);
    }
    // Only what restarts this series (docs/trends.md, "What restarts a series"): the kind of
    // its newest check, as its statistics.
    const CheckKind series =
        t.points.empty() ? CheckKind::MonumentPositioning : t.points.back().kind;
    for (const auto& m : r.markers) {
      if (m.time_ns < lo || m.time_ns > hi) continue;
      if (!restarts_series(m.compensation, series, t.metric)) continue;
      c.markers.push_back(
          {m.time_ns, m.label,
           m.compensation ? charts::MarkerKind::Compensation : charts::MarkerKind::Intervention});
    }
    h += "<div class=\"trend\">" + figure(charts::trend_chart(c)) + "<p class=\"figures\">" +
         esc(trend_figures(r, t)) + "</p></div>\n";
  }
  if (!r.other_metrics.empty()) {
    h += "<h3>The other " + std::to_string(r.other_metrics.size()) + " metrics " +
         esc(range_phrase(r)) +
         ", nearest their tolerance first</h3>\n<p class=\"how\">Each with the value that came "
         "nearest its tolerance and how much of the tolerance it used (100 %: at the limit); "
         "`ncqual trend --machine " +
         esc(r.machine_id) +
         " --metric NAME` gives its trend.</p>\n<table class=\"other-metrics\">\n<thead><tr>"
         "<th>metric</th><th>check</th><th>checks</th><th>nearest value</th><th>tolerance</th>"
         "<th>unit</th><th>used</th><th>time</th></tr></thead>\n<tbody>\n";
    for (const MetricUsage& m : r.other_metrics) {
      const charts::DisplayUnit u = display_unit(m.unit);
      auto shown = [&](double v) {
        return std::isfinite(v) ? svg::fixed(v * u.scale, u.scale >= 1000 ? 1 : 2)
                                : std::string("—");
      };
      h += std::string(m.usage > 1 ? "<tr class=\"over\">" : "<tr>") + "<td>" + esc(m.metric) +
           "</td><td>" + esc(to_string(m.kind)) + "</td><td>" + std::to_string(m.checks) +
           "</td><td>" + esc(m.checks > 0 ? shown(m.value) : std::string("—")) + "</td><td>" +
           esc("[" + shown(m.lower) + ", " + shown(m.upper) + "]") + "</td><td>" + esc(u.unit) +
           "</td><td>" + esc(m.checks > 0 ? fmt::format("{:.0f} %", 100 * m.usage) : "—") +
           "</td><td>" + esc(m.checks > 0 ? when(r, m.time_ns) : std::string("—")) + "</td></tr>\n";
    }
    h += "</tbody></table>\n";
  }
  if (!singles.empty()) {
    h += "<h3>Metrics with one check " + esc(range_phrase(r)) +
         "</h3>\n<table class=\"single-metrics\">\n<thead><tr><th>metric</th><th>value</th>"
         "<th>tolerance</th><th>unit</th><th>request</th><th>time</th></tr></thead>\n<tbody>\n" +
         singles + "</tbody></table>\n";
  }
  return h + "</section>\n";
}

// ---- 5. Checks -----------------------------------------------------------------------------

std::string correction_text(const Correction& c) {
  std::string out = c.target + ":";
  for (const auto& o : c.offsets) {
    if (o.unit == "mm") {
      out += " " + o.name + " = " + um(o.value, 2);
    } else if (o.unit == "rad") {
      out += " " + o.name + " = " + fmt::format("{:.1f} µrad", o.value * 1e6);
    } else {
      out += " " + o.name + " = " + fmt::format("{:.6g} {}", o.value, o.unit);
    }
  }
  return out;
}

std::string checks_section(const MachineReport& r) {
  std::string h = "<section class=\"ncqual-report-checks\">\n<h2>Checks</h2>\n";
  if (r.checks.empty()) return h + none_sentence("check", r) + "</section>\n";
  h += "<table class=\"checks\">\n<thead><tr><th>time (" + esc(r.calendar.zone_name()) +
       ")</th><th>kind</th><th>request</th>"
       "<th>verdict</th><th>data</th><th>causes (most likely first)</th><th>corrections</th>"
       "</tr></thead>\n"
       "<tbody>\n";
  for (const auto& c : r.checks) {
    const std::int64_t t = c.result        ? c.result->time_ns
                           : c.measurement ? c.measurement->time_ns
                           : c.request     ? c.request->time_ns
                                           : 0;
    const DataOrigin origin = storage::origin_of(c);
    h += std::string(origin == DataOrigin::Simulated ? "<tr class=\"simulated\">" : "<tr>") +
         "<td class=\"time\">" + esc(when(r, t)) + "</td><td>" + esc(to_string(c.kind)) +
         "</td><td>" + esc(c.request_id) + "</td><td>" +
         verdict_cell(c.result ? std::optional<Verdict>(c.result->verdict) : std::nullopt);
    if (c.result && !c.result->reason.empty()) {
      h += "<div class=\"reason\">" + esc(c.result->reason) + "</div>";
    }
    h += "</td><td class=\"origin\">" + origin_cell(origin) + "</td><td>";
    if (c.result && !c.result->likely_causes.empty()) {
      h += "<ol class=\"causes\">";
      for (const auto& cause : c.result->likely_causes) h += "<li>" + esc(cause) + "</li>";
      h += "</ol>";
    }
    h += "</td><td>";
    if (c.result && c.result->correction) h += esc(correction_text(*c.result->correction));
    h += "</td></tr>\n";
  }
  return h + "</tbody></table>\n</section>\n";
}

// ---- 6. Error budget -----------------------------------------------------------------------

std::string budget_section(const MachineReport& r) {
  std::string h = "<section class=\"ncqual-report-budget\">\n<h2>Error budget</h2>\n";
  const BudgetSection& b = r.budget;
  if (!b.evaluation) return h + "<p class=\"none\">" + esc(b.error) + "</p>\n</section>\n";
  const solver::ErrorBudgetReport& e = *b.evaluation;
  charts::BudgetChart c;
  c.title = r.machine_id + ": error budget at the tool tip (today)";
  c.description = fmt::format(
      "The newest value of each metric, up to {}; capabilities from the "
      "newest {} values.",
      when(r, b.until_ns), b.last);
  if (b.judgement.verdict == solver::BudgetVerdict::Held) {
    c.description += " The machine is held: not within budget whatever the total.";
  }
  c.unit = micrometres();
  for (const auto& s : e.sources) c.contributions.push_back({s.name, s.today_contribution_mm});
  c.total = charts::BudgetBar{"total (RSS)", e.today.rss_total_mm};
  c.allowance = e.allowable_total_mm;
  h += figure(charts::budget_chart(c));
  const solver::BudgetJudgement& j = b.judgement;
  const char* verdict = j.verdict == solver::BudgetVerdict::WithinBudget ? "within budget"
                        : j.verdict == solver::BudgetVerdict::OverBudget ? "over budget"
                                                                         : "NOT within budget";
  std::string why;
  for (const auto& w : j.why) why += (why.empty() ? " " : "; ") + w;
  if (j.verdict == solver::BudgetVerdict::Held) {
    why += ". A held machine is not released to cut parts, whatever its errors' total";
  }
  h += "<p class=\"figures\">" +
       esc(fmt::format("Total {} against an allowance of {} at θ = {:.1f}° ({:.1f} % of it): "
                       "{}{}.",
                       um(e.today.rss_total_mm), um(e.allowable_total_mm),
                       units::rad_to_deg(e.today.theta_rad),
                       100 * e.today.rss_total_mm / e.allowable_total_mm, verdict,
                       why.empty() ? "" : ":" + why)) +
       (b.values == 0 ? " No value of its metrics is stored yet: the capabilities are the "
                        "configured defaults."
                      : "") +
       "</p>\n";
  return h + "</section>\n";
}

}  // namespace

std::string machine_report_sections(const MachineReport& report) {
  return state_section(report) + grid_section(report) + linear_section(report) +
         circles_section(report) + trends_section(report) + checks_section(report) +
         budget_section(report);
}

std::string report_stylesheet() {
  return R"css(.ncqual-report { font-family: "DejaVu Sans", Arial, Helvetica, sans-serif; color: #000; max-width: 1100px; margin: 0 auto; padding: 0 16px; }
.ncqual-report h1 { font-size: 1.6em; margin: 0.6em 0 0.2em; }
section[class^="ncqual-report-"] { margin: 1.5em 0; }
section[class^="ncqual-report-"] h2 { font-size: 1.3em; border-bottom: 2px solid #1f5fa8; padding-bottom: 0.15em; }
section[class^="ncqual-report-"] h3 { font-size: 1.05em; margin: 1em 0 0.3em; }
section[class^="ncqual-report-"] p.none { font-style: italic; color: #333; }
section[class^="ncqual-report-"] p.how { color: #333; font-size: 0.92em; }
section[class^="ncqual-report-"] figure.chart { margin: 0.5em 0; display: inline-block; vertical-align: top; break-inside: avoid; page-break-inside: avoid; }
section[class^="ncqual-report-"] figure.chart svg { max-width: 100%; height: auto; }
section[class^="ncqual-report-"] table { border-collapse: collapse; font-size: 0.9em; margin: 0.4em 0; }
section[class^="ncqual-report-"] th, section[class^="ncqual-report-"] td { border: 1px solid #b4b4b4; padding: 3px 6px; text-align: left; vertical-align: top; }
section[class^="ncqual-report-"] thead th { background: #eeeeee; }
table.checks { width: 100%; }
table.checks tr { break-inside: avoid; page-break-inside: avoid; }
table.checks td.time { white-space: nowrap; }
table.single-metrics tr.over td { color: #c8102e; font-weight: bold; }
table.other-metrics tr.over td { color: #c8102e; font-weight: bold; }
table.checks ol.causes { margin: 0; padding-left: 1.3em; }
table.checks div.reason { font-size: 0.85em; color: #333; }
.ncqual-simulated-banner { margin: 0.8em 0; padding: 0.7em 1em; border: 3px solid #6a1b9a; background: #f6edfa; color: #3b0a57; font-size: 1.05em; break-inside: avoid; page-break-inside: avoid; }
.ncqual-simulated-banner strong { color: #6a1b9a; letter-spacing: 0.04em; }
.origin-badge.simulated { display: inline-block; margin-left: 0.4em; padding: 0 0.45em; border-radius: 3px; background: #6a1b9a; color: #fff; font-size: 0.8em; font-weight: bold; letter-spacing: 0.03em; }
table.checks tr.simulated td { background: #faf4fd; }
.origin.unknown, p.origin-note { color: #555; font-style: italic; }
.verdict { font-weight: bold; }
.verdict.fail, .verdict.invalid { color: #c8102e; }
.verdict.pass { color: #1f5fa8; }
.state { font-weight: bold; }
.state.NEEDS_INTERVENTION, .state.OVERDUE, .state.needs_intervention, .state.overdue { color: #c8102e; }
ul.warnings li.active { color: #c8102e; }
ul.warnings li.ended { color: #333; }
div.plane, div.trend, div.circle { break-inside: avoid; page-break-inside: avoid; }
@media print {
  .ncqual-report { max-width: none; padding: 0; }
  section[class^="ncqual-report-"] { break-before: page; page-break-before: always; margin: 0; }
  section.ncqual-report-state { break-before: auto; page-break-before: auto; }
  section[class^="ncqual-report-"] h2 { break-after: avoid; page-break-after: avoid; }
  figure.chart svg { max-height: 24cm; }
  a { color: inherit; text-decoration: none; }
}
@page { size: A4; margin: 12mm; }
)css";
}

std::string machine_report_document(const MachineReport& report) {
  std::string h = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n";
  h += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"/>\n";
  h += "<title>" +
       esc("Qualification report of " + report.machine_id + ", " +
           local_day(report, report.now_ns)) +
       "</title>\n<style>\n" + report_stylesheet() + "</style>\n</head>\n<body>\n";
  h += "<main class=\"ncqual-report\">\n<h1>" + esc("Qualification report: " + report.machine_id) +
       "</h1>\n";
  h += machine_report_sections(report);
  const std::string by = report.produced_by.empty() ? "ncqual report" : report.produced_by;
  h += "<footer><p class=\"how\">Written by " + esc(by) + " as of " +
       esc(when(report, report.now_ns)) +
       ". Lengths in µm; angular errors in µrad; the budget's table angle θ in "
       "degrees.</p></footer>\n</main>\n</body>\n</html>\n";
  return h;
}

}  // namespace ncqual::report
