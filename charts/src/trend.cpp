// SPDX-License-Identifier: Apache-2.0
#include "ncqual/charts/trend.hpp"

#include <algorithm>
#include <cmath>

#include "frame.hpp"

namespace ncqual::charts {
namespace {

constexpr std::int64_t kNsPerDay = 86'400'000'000'000;

constexpr LineStyle kToleranceLine{palette::kDark, 1.5, ""};
constexpr LineStyle kCentreLine{palette::kGrey, 1, ""};
constexpr LineStyle kControlLine{palette::kGrey, 1.2, "6 4"};
constexpr LineStyle kDataLine{palette::kLightGrey, 1, ""};
constexpr LineStyle kFittedLine{palette::kAccent, 1.8, "8 4"};
constexpr LineStyle kInterventionLine{palette::kDark, 1.2, "4 3"};
constexpr LineStyle kCompensationLine{palette::kAccent, 1.5, "1.5 3"};
constexpr LineStyle kCrossingLine{palette::kRed, 1.5, "6 2 1.5 2"};
constexpr MarkerStyle kPassMarker{Shape::Circle, 7, palette::kAccent, "#ffffff", 1};
constexpr MarkerStyle kFailMarker{Shape::Diamond, 11, palette::kRed, palette::kInk, 0.8};

bool finite(double v) { return std::isfinite(v); }

struct TimeAxis {
  std::int64_t lo = 0, hi = 0;
  TimeTicks ticks;
  std::vector<std::string> labels;
};

// The ticks with the most labels that fit `width` px (labels 14 px apart or more). In a zone:
// ticks on its wall clock's round times, labelled with its wall clock, placed at their instants.
TimeAxis fit_time_axis(std::int64_t lo, std::int64_t hi, double width, const TimeFormatter& fmt,
                       const TimeZone& zone) {
  TimeAxis axis{lo, hi, {}, {}};
  const double span = static_cast<double>(hi - lo);
  const bool zoned = zone.to_wall && zone.from_wall;
  for (int n = std::max(2, static_cast<int>(width / 60)); n >= 2; --n) {
    axis.ticks = zoned ? time_ticks(zone.to_wall(lo), zone.to_wall(hi), n) : time_ticks(lo, hi, n);
    axis.labels.clear();
    for (std::int64_t& t : axis.ticks.ticks) {
      const std::int64_t wall = t;
      if (zoned) t = zone.from_wall(wall);
      axis.labels.push_back(fmt ? fmt(t) : default_time_label(axis.ticks, wall));
    }
    const double spacing = width * static_cast<double>(axis.ticks.step_ns) / span;
    if (axis.ticks.ticks.size() <= 1 || detail::widest(axis.labels) + 14 <= spacing) break;
  }
  return axis;
}

std::string time_text(const TrendChart& c, std::int64_t t) {
  if (c.time_label) return c.time_label(t);
  if (c.zone.text) return c.zone.text(t);
  return utc_date_time(c.zone.to_wall ? c.zone.to_wall(t) : t);
}

// A date of the forecast: a day is as precise as a forecast gets.
std::string date_text(const TrendChart& c, std::int64_t t) {
  return c.time_label ? c.time_label(t) : utc_date(c.zone.to_wall ? c.zone.to_wall(t) : t);
}

// The fitted value at `t` by linear interpolation between the samples around it.
std::optional<double> fitted_at(const std::vector<ForecastSample>& samples, std::int64_t t) {
  for (std::size_t i = 1; i < samples.size(); ++i) {
    const ForecastSample& a = samples[i - 1];
    const ForecastSample& b = samples[i];
    if (t < a.time_ns || t > b.time_ns) continue;
    if (b.time_ns == a.time_ns) return a.fitted;
    const double f =
        static_cast<double>(t - a.time_ns) / static_cast<double>(b.time_ns - a.time_ns);
    return a.fitted + f * (b.fitted - a.fitted);
  }
  if (samples.size() == 1 && samples[0].time_ns == t) return samples[0].fitted;
  return std::nullopt;
}

void vertical_line(svg::Writer& w, const Box& box, double x, const LineStyle& style,
                   std::vector<svg::Attr> extra, std::string_view tooltip) {
  auto attrs = detail::line_attrs(style);
  attrs.insert(attrs.begin(), {{"x1", svg::coord(x)},
                               {"y1", svg::coord(box.top)},
                               {"x2", svg::coord(x)},
                               {"y2", svg::coord(box.bottom)}});
  attrs.insert(attrs.end(), extra.begin(), extra.end());
  w.open("line", attrs);
  w.text("title", {}, tooltip);
  w.close("line");
}

// A label along a vertical line, reading upwards, ending near the plot's top, left of the line
// (clear of the crossing's ring, 5 px in radius).
void vertical_label(svg::Writer& w, const Box& box, double x, std::string_view text) {
  const double ax = x - 7;
  const double ay = box.top + 5;
  auto attrs = detail::halo_text_attrs(ax, ay, "end", detail::kSmallFontPx);
  attrs.emplace_back("transform", "rotate(-90 " + svg::coord(ax) + " " + svg::coord(ay) + ")");
  attrs.emplace_back("class", "marker-label");
  w.text("text", attrs, detail::fit_text(text, box.height() - 10, detail::kSmallFontPx));
}

// Markers closer than this on the time axis are one group at least.
constexpr double kMarkerGroupPx = 6;
// The marker lines and labels may cover at most this fraction of the plot's width.
constexpr double kMaxMarkerInk = 0.1;
// What one marker label covers across the plot (a rotated line of small text with its halo).
constexpr double kMarkerLabelInk = detail::kSmallFontPx + 3;

// Consecutive markers (by time) drawn as one line.
struct MarkerGroup {
  std::vector<const TimeMarker*> markers;  // by time
  std::size_t interventions = 0;
};

// The width of plot one group's line covers.
double marker_ink(const std::vector<MarkerGroup>& groups) {
  double ink = 0;
  for (const MarkerGroup& g : groups) {
    ink += g.interventions > 0 ? kInterventionLine.width : kCompensationLine.width;
  }
  return ink;
}

// The markers in groups, interventions and compensations apart (an intervention keeps its own
// time however many compensations surround it): a marker within `gap` px of the previous one of
// its kind joins its group; the gap widens (x1.5) until the groups' lines cover at most
// kMaxMarkerInk of the plot's width. By the time of their latest marker.
template <typename ToX>
std::vector<MarkerGroup> group_markers(const std::vector<TimeMarker>& markers, const ToX& tx,
                                       double plot_width) {
  std::vector<const TimeMarker*> sorted;
  sorted.reserve(markers.size());
  for (const TimeMarker& m : markers) sorted.push_back(&m);
  std::stable_sort(sorted.begin(), sorted.end(), [](const TimeMarker* a, const TimeMarker* b) {
    return a->time_ns < b->time_ns;
  });
  std::vector<MarkerGroup> groups;
  for (double gap = kMarkerGroupPx;; gap *= 1.5) {
    groups.clear();
    for (const MarkerKind kind : {MarkerKind::Intervention, MarkerKind::Compensation}) {
      const std::size_t first = groups.size();
      double previous = -1e300;
      for (const TimeMarker* m : sorted) {
        if (m->kind != kind) continue;
        const double x = tx(m->time_ns);
        if (groups.size() == first || x - previous > gap) groups.emplace_back();
        groups.back().markers.push_back(m);
        if (kind == MarkerKind::Intervention) ++groups.back().interventions;
        previous = x;
      }
    }
    if (groups.size() <= 2 || marker_ink(groups) <= kMaxMarkerInk * plot_width) break;
  }
  std::stable_sort(groups.begin(), groups.end(), [](const MarkerGroup& a, const MarkerGroup& b) {
    return a.markers.back()->time_ns < b.markers.back()->time_ns;
  });
  return groups;
}

// "7 compensations", "2 interventions", "2 interventions, 5 compensations".
std::string group_label(const MarkerGroup& g) {
  const std::size_t compensations = g.markers.size() - g.interventions;
  std::string out;
  if (g.interventions > 0) {
    out = detail::count_phrase(g.interventions, "intervention", "interventions");
  }
  if (compensations > 0) {
    if (!out.empty()) out += ", ";
    out += detail::count_phrase(compensations, "compensation", "compensations");
  }
  return out;
}

}  // namespace

std::string trend_chart(const TrendChart& c) {
  const Size size = detail::resolve_size(c.size, kTrendSize);
  const double scale = detail::display_scale(c.unit);
  const double lower_tol = c.tolerance.lower;
  const double upper_tol = c.tolerance.upper;
  const bool has_lower = finite(lower_tol);
  const bool has_upper = finite(upper_tol);

  // The points that can be drawn, in time order.
  std::size_t skipped = 0;
  std::vector<const TrendPoint*> points = detail::usable_items(
      c.points, [](const TrendPoint& p) { return finite(p.value); }, skipped);
  std::stable_sort(points.begin(), points.end(), [](const TrendPoint* a, const TrendPoint* b) {
    return a->time_ns < b->time_ns;
  });
  auto is_failed = [&](const TrendPoint& p) {
    return p.failed || (has_lower && p.value < lower_tol) || (has_upper && p.value > upper_tol);
  };
  const std::size_t failed = static_cast<std::size_t>(std::count_if(
      points.begin(), points.end(), [&](const TrendPoint* p) { return is_failed(*p); }));

  std::vector<ForecastSample> forecast;
  if (c.forecast) {
    for (const ForecastSample& s : c.forecast->samples) {
      if (finite(s.fitted) && finite(s.lower) && finite(s.upper)) forecast.push_back(s);
    }
    std::stable_sort(
        forecast.begin(), forecast.end(),
        [](const ForecastSample& a, const ForecastSample& b) { return a.time_ns < b.time_ns; });
  }
  std::optional<std::int64_t> crossing;
  if (c.forecast && !points.empty() && c.forecast->crossing_ns) crossing = *c.forecast->crossing_ns;

  // The <desc>: what a reader without the picture needs.
  std::string desc = "Trend of " + (c.quantity.empty() ? std::string("a metric") : c.quantity) +
                     ": " + detail::count_phrase(points.size(), "check", "checks");
  if (!points.empty()) {
    desc += " from " + time_text(c, points.front()->time_ns) + " to " +
            time_text(c, points.back()->time_ns) + ", " + std::to_string(failed) + " failed";
  }
  desc += ".";
  auto dv = [&](double v) { return detail::exact_display(v * scale, c.unit.unit); };
  desc += detail::tolerance_sentence(lower_tol, upper_tol, scale, c.unit.unit);
  if (c.control) {
    desc += " Control limits: centre " + dv(c.control->centre) + ", LCL " + dv(c.control->lower) +
            ", UCL " + dv(c.control->upper) + ".";
  }
  if (!forecast.empty()) {
    desc += " Forecast to " + date_text(c, forecast.back().time_ns);
    desc += crossing ? ", expected to cross a tolerance limit on " + date_text(c, *crossing)
                     : ", no crossing of a tolerance limit expected";
    desc += ".";
  }
  if (!c.markers.empty()) {
    desc += " " +
            detail::count_phrase(c.markers.size(), "intervention or compensation",
                                 "interventions and compensations") +
            " marked.";
  }

  // The legend: only what the chart shows.
  std::vector<LegendItem> legend;
  if (!points.empty()) {
    legend.push_back(detail::marker_item("check", kPassMarker));
    if (failed > 0) legend.push_back(detail::marker_item("failed check", kFailMarker));
  }
  if (has_lower || has_upper) legend.push_back(detail::line_item("tolerance", kToleranceLine));
  if (c.control) legend.push_back(detail::line_item("control limits", kControlLine));
  if (!forecast.empty()) {
    legend.push_back(detail::line_item("forecast", kFittedLine));
    legend.push_back(detail::area_item(c.forecast->band_label, palette::kAccentLight));
    if (crossing) legend.push_back(detail::line_item("expected crossing", kCrossingLine));
  }
  const bool any_intervention =
      std::any_of(c.markers.begin(), c.markers.end(),
                  [](const TimeMarker& m) { return m.kind == MarkerKind::Intervention; });
  const bool any_compensation =
      std::any_of(c.markers.begin(), c.markers.end(),
                  [](const TimeMarker& m) { return m.kind == MarkerKind::Compensation; });
  if (any_intervention) legend.push_back(detail::line_item("intervention", kInterventionLine));
  if (any_compensation) legend.push_back(detail::line_item("compensation", kCompensationLine));
  svg::Writer w;
  Box box;
  box.top = detail::open_chart(
      w, {kind::kTrend, c.title, desc, c.description, size, {points.size(), skipped, failed}, {}},
      legend);
  box.bottom = detail::plot_bottom(size.height, !c.time_title.empty());

  // The y axis (display units) over everything drawn.
  std::vector<double> ys;
  ys.reserve(points.size() + 5 + 3 * forecast.size());
  for (const TrendPoint* p : points) ys.push_back(p->value * scale);
  if (!points.empty()) {
    if (has_lower) ys.push_back(lower_tol * scale);
    if (has_upper) ys.push_back(upper_tol * scale);
    if (c.control) {
      for (const double v : {c.control->centre, c.control->lower, c.control->upper}) {
        if (finite(v)) ys.push_back(v * scale);
      }
    }
    for (const ForecastSample& s : forecast) {
      ys.push_back(s.fitted * scale);
      ys.push_back(s.lower * scale);
      ys.push_back(s.upper * scale);
    }
  }
  const auto [ymin_it, ymax_it] = std::minmax_element(ys.begin(), ys.end());
  const NiceAxis y_axis =
      ys.empty() ? nice_axis(0, 1, 2)
                 : detail::padded_axis(*ymin_it, *ymax_it, detail::y_intervals(box.height()));
  const auto y_labels = detail::tick_labels(y_axis.ticks, y_axis.step);
  const bool y_title = !c.quantity.empty() || !c.unit.unit.empty();
  const detail::LeftEdge left = detail::left_edge(y_labels, y_title);
  box.left = left.plot_left;

  // Edge labels (right margin) for the horizontal lines.
  const LinearScale y(y_axis.lo, y_axis.hi, box.bottom, box.top);
  std::vector<EdgeLabel> edge;
  if (!points.empty()) {
    if (has_upper) edge.push_back({y(upper_tol * scale), "upper tol.", palette::kDark});
    if (has_lower) edge.push_back({y(lower_tol * scale), "lower tol.", palette::kDark});
    if (c.control) {
      if (finite(c.control->upper))
        edge.push_back({y(c.control->upper * scale), "UCL", palette::kGrey});
      if (finite(c.control->centre))
        edge.push_back({y(c.control->centre * scale), "CL", palette::kGrey});
      if (finite(c.control->lower))
        edge.push_back({y(c.control->lower * scale), "LCL", palette::kGrey});
    }
  }
  box.right = size.width - std::max(14.0, detail::edge_labels_width(edge) + 4);

  if (points.empty()) {
    return detail::close_empty_chart(
        w, box, {{"data-y-min", svg::exact(y_axis.lo)}, {"data-y-max", svg::exact(y_axis.hi)}});
  }

  // The time axis over the points, the forecast and the markers.
  std::int64_t tmin = points.front()->time_ns;
  std::int64_t tmax = points.back()->time_ns;
  for (const ForecastSample& s : forecast) {
    tmin = std::min(tmin, s.time_ns);
    tmax = std::max(tmax, s.time_ns);
  }
  for (const TimeMarker& m : c.markers) {
    tmin = std::min(tmin, m.time_ns);
    tmax = std::max(tmax, m.time_ns);
  }
  if (crossing) tmax = std::max(tmax, *crossing);
  const std::int64_t pad = tmax > tmin ? (tmax - tmin) / 30 : kNsPerDay / 2;
  tmin -= pad;
  tmax += pad;
  const TimeAxis t_axis = fit_time_axis(tmin, tmax, box.width(), c.time_label, c.zone);
  const LinearScale x(0, static_cast<double>(tmax - tmin), box.left, box.right);
  auto tx = [&](std::int64_t t) { return x(static_cast<double>(t - tmin)); };

  // The tolerance band behind everything.
  if (has_lower && has_upper) {
    const double y_hi = y(upper_tol * scale);
    const double y_lo = y(lower_tol * scale);
    w.leaf("rect", {{"class", "tolerance-band"},
                    {"x", svg::coord(box.left)},
                    {"y", svg::coord(y_hi)},
                    {"width", svg::coord(box.width())},
                    {"height", svg::coord(y_lo - y_hi)},
                    {"fill", std::string(palette::kBand)}});
  }
  std::vector<double> t_ticks;
  for (const std::int64_t t : t_axis.ticks.ticks) t_ticks.push_back(static_cast<double>(t - tmin));
  detail::y_axis(w, box, y, y_axis.ticks, y_labels, detail::axis_title(c.quantity, c.unit.unit),
                 left.title_x);
  detail::x_axis(w, box, x, t_ticks, t_axis.labels, c.time_title);

  // The forecast's band under the data.
  if (!forecast.empty()) {
    svg::Path band;
    for (const ForecastSample& s : forecast) band.vertex(tx(s.time_ns), y(s.upper * scale));
    for (std::size_t i = forecast.size(); i-- > 0;) {
      band.line_to(tx(forecast[i].time_ns), y(forecast[i].lower * scale));
    }
    band.close();
    w.leaf("path", {{"class", "prediction-band"},
                    {"d", band.str()},
                    {"fill", std::string(palette::kAccentLight)},
                    {"fill-opacity", "0.8"},
                    {"stroke", "none"}});
  }

  // Horizontal lines: control limits, then the tolerance limits over them.
  auto hline = [&](double v, const LineStyle& style, std::string_view cls) {
    detail::horizontal_line(w, box, y(v * scale), style, cls, v);
  };
  if (c.control) {
    if (finite(c.control->centre)) hline(c.control->centre, kCentreLine, "control centre");
    if (finite(c.control->lower)) hline(c.control->lower, kControlLine, "control lcl");
    if (finite(c.control->upper)) hline(c.control->upper, kControlLine, "control ucl");
  }
  if (has_lower) hline(lower_tol, kToleranceLine, "tolerance lower");
  if (has_upper) hline(upper_tol, kToleranceLine, "tolerance upper");

  // Interventions and compensations, grouped so that their ink stays within a tenth of the
  // plot's width (kMaxMarkerInk): each group one line, at its latest marker (where the segment
  // after it starts), with a pale strip along the plot's top over the time it spans; a label
  // only where it does not crowd the previous one and the ink allows it.
  const std::vector<MarkerGroup> groups = group_markers(c.markers, tx, box.width());
  std::vector<std::pair<double, std::string>> marker_labels;
  double label_ink = 0;
  double last_label_x = -1e9;
  const double line_ink = marker_ink(groups);
  for (const MarkerGroup& g : groups) {
    const TimeMarker& last = *g.markers.back();
    const bool intervention = g.interventions > 0;
    const double mx = tx(last.time_ns);
    std::string tip = time_text(c, last.time_ns) + ": " + last.label;
    if (g.markers.size() > 1) {
      tip = group_label(g) + " from " + time_text(c, g.markers.front()->time_ns) + " to " +
            time_text(c, last.time_ns);
      for (std::size_t k = g.markers.size(); k-- > 0 && g.markers.size() - k <= 5;) {
        tip += "\n" + time_text(c, g.markers[k]->time_ns) + ": " + g.markers[k]->label;
      }
      if (g.markers.size() > 5) tip += "\n...";
      // The time the group spans: a pale strip along the plot's top edge.
      const double x0 = tx(g.markers.front()->time_ns);
      w.leaf("rect", {{"class", "marker-span"},
                      {"x", svg::coord(x0)},
                      {"y", svg::coord(box.top)},
                      {"width", svg::coord(std::max(mx - x0, 1.0))},
                      {"height", "5"},
                      {"fill", std::string(intervention ? palette::kDark : palette::kAccent)},
                      {"fill-opacity", "0.35"}});
    }
    std::vector<svg::Attr> attrs{
        {"class", intervention ? "marker intervention" : "marker compensation"},
        {"data-time", std::to_string(last.time_ns)},
        {"data-count", std::to_string(g.markers.size())},
        {"data-label", g.markers.size() > 1 ? group_label(g) : last.label}};
    if (g.markers.size() > 1) {
      attrs.emplace_back("data-first-time", std::to_string(g.markers.front()->time_ns));
    }
    vertical_line(w, box, mx, intervention ? kInterventionLine : kCompensationLine,
                  std::move(attrs), tip);
    const std::string text = g.markers.size() > 1 ? group_label(g) : last.label;
    if (!text.empty() && mx - last_label_x >= 15 &&
        line_ink + label_ink + kMarkerLabelInk <= kMaxMarkerInk * box.width()) {
      marker_labels.emplace_back(mx, text);
      label_ink += kMarkerLabelInk;
      last_label_x = mx;
    }
  }

  // The data: a thin line in time order, then a marker per check.
  if (points.size() > 1) {
    svg::Path line;
    for (const TrendPoint* p : points) line.vertex(tx(p->time_ns), y(p->value * scale));
    detail::styled_path(w, "data-line", line, kDataLine);
  }

  // The fitted line over the data, dashed.
  if (!forecast.empty()) {
    svg::Path fit;
    for (const ForecastSample& s : forecast) fit.vertex(tx(s.time_ns), y(s.fitted * scale));
    detail::styled_path(w, "forecast", fit, kFittedLine);
  }

  w.open("g", {{"class", "points"}});
  const int decimals = std::max(0, nice_step(y_axis.step.value() / 10).decimals());
  for (const TrendPoint* p : points) {
    const bool fail = is_failed(*p);
    std::string tip = p->label.empty() ? "" : p->label + ": ";
    tip += time_text(c, p->time_ns) + ", " +
           detail::display_value(p->value * scale, decimals, c.unit.unit);
    if (fail) tip += " (failed)";
    detail::marker(w, fail ? kFailMarker : kPassMarker, tx(p->time_ns), y(p->value * scale),
                   {{"class", fail ? "point fail" : "point pass"},
                    {"data-time", std::to_string(p->time_ns)},
                    {"data-value", svg::exact(p->value)}},
                   tip);
  }
  w.close("g");

  // The expected crossing: a red line at its date and a ring where the fitted line crosses.
  if (crossing) {
    const double cx = tx(*crossing);
    vertical_line(w, box, cx, kCrossingLine,
                  {{"class", "crossing"}, {"data-time", std::to_string(*crossing)}},
                  "expected crossing " + date_text(c, *crossing));
    if (const auto v = fitted_at(forecast, *crossing)) {
      w.leaf("circle", {{"class", "crossing-point"},
                        {"cx", svg::coord(cx)},
                        {"cy", svg::coord(y(*v * scale))},
                        {"r", "5"},
                        {"fill", "#ffffff"},
                        {"stroke", std::string(palette::kRed)},
                        {"stroke-width", "2"}});
    }
    marker_labels.emplace_back(cx, "expected crossing " + date_text(c, *crossing));
  }

  detail::plot_frame(w, box,
                     {{"data-y-min", svg::exact(y_axis.lo)},
                      {"data-y-max", svg::exact(y_axis.hi)},
                      {"data-time-min", std::to_string(tmin)},
                      {"data-time-max", std::to_string(tmax)}});
  for (const auto& [mx, text] : marker_labels) vertical_label(w, box, mx, text);
  detail::edge_labels(w, edge, box.right + 5, box.top, box.bottom);
  return detail::close_chart(w);
}

}  // namespace ncqual::charts
