// SPDX-License-Identifier: Apache-2.0
#include "ncqual/charts/vector_plot.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "frame.hpp"

namespace ncqual::charts {
namespace {

constexpr MarkerStyle kNominal{Shape::Circle, 5, palette::kInk, "#ffffff", 0.5};
constexpr MarkerStyle kNominalFail{Shape::Circle, 6, palette::kRed, "#ffffff", 0.5};
constexpr LineStyle kArrow{palette::kAccent, 1.8, ""};
constexpr LineStyle kArrowFail{palette::kRed, 2.4, ""};
constexpr LineStyle kCircle{palette::kGrey, 1, "3 2"};
constexpr LineStyle kCircleFail{palette::kRed, 1.2, ""};
// The automatic magnification (vector_magnification): the largest arrow at most this fraction of
// the closest spacing of the points, and at least this many pixels long.
constexpr double kLargestArrowOfSpacing = 0.8;
constexpr double kMinLargestArrowPx = 8;
// Tolerance circles wider than this fraction of the closest spacing (in radius) would cover
// their neighbours: they are not drawn, the out-of-tolerance points are red all the same.
constexpr double kLargestCircleOfSpacing = 0.5;

bool usable(const PlaneDeviation& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.dx) && std::isfinite(p.dy);
}

// The largest step of the 1-2-5 series that is <= v (v > 0).
double nice_floor(double v) {
  const TickStep s = nice_step(v);
  if (s.value() <= v * (1 + 1e-9)) return s.value();
  const int m = s.mantissa == 1 ? 5 : s.mantissa == 2 ? 1 : 2;
  const int e = s.mantissa == 1 ? s.exponent - 1 : s.exponent;
  return TickStep{m, e}.value();
}

bool has_tolerance(const DeviationVectorPlot& c) {
  return std::isfinite(c.tolerance) && c.tolerance > 0;
}

// The closest spacing of two distinct points; without two, a fifth of the first's distance from
// the origin (at least 100 position units).
double closest_spacing(const std::vector<const PlaneDeviation*>& pts) {
  double spacing = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    for (std::size_t j = i + 1; j < pts.size(); ++j) {
      const double d = std::hypot(pts[i]->x - pts[j]->x, pts[i]->y - pts[j]->y);
      if (d > 0) spacing = std::min(spacing, d);
    }
  }
  if (!std::isfinite(spacing) && !pts.empty()) {
    spacing = std::max({std::abs(pts[0]->x), std::abs(pts[0]->y), 100.0}) * 0.2;
  }
  return spacing;
}

// Pixels per position unit the plot of `size` will about have (a little less than it will: the
// margins taken generously), with the arrows of the magnification the deviations alone give.
double estimated_px_per_unit(const DeviationVectorPlot& c,
                             const std::vector<const PlaneDeviation*>& pts, const Size& size) {
  if (pts.empty()) return 0;
  double xmin = pts[0]->x, xmax = xmin, ymin = pts[0]->y, ymax = ymin, largest = 0;
  for (const PlaneDeviation* p : pts) {
    xmin = std::min(xmin, p->x);
    xmax = std::max(xmax, p->x);
    ymin = std::min(ymin, p->y);
    ymax = std::max(ymax, p->y);
    largest = std::max(largest, std::hypot(p->dx, p->dy));
  }
  DeviationVectorPlot spacing_only = c;
  spacing_only.magnification.reset();
  const double reach = largest * vector_magnification(spacing_only, 0) * 2;
  const double extent = std::max(xmax - xmin, ymax - ymin);
  const double xr = std::max(xmax - xmin + reach, extent * 0.1) * 1.1;
  const double yr = std::max(ymax - ymin + reach, extent * 0.1) * 1.1;
  if (!(xr > 0) || !(yr > 0)) return 0;
  return std::min((size.width - 100) / xr, (size.height - 170) / yr);
}

}  // namespace

double vector_magnification(const DeviationVectorPlot& c, double px_per_unit) {
  if (c.magnification && std::isfinite(*c.magnification) && *c.magnification > 0) {
    return *c.magnification;
  }
  std::vector<const PlaneDeviation*> pts;
  for (const PlaneDeviation& p : c.points) {
    if (usable(p)) pts.push_back(&p);
  }
  double largest = 0;
  for (const PlaneDeviation* p : pts) largest = std::max(largest, std::hypot(p->dx, p->dy));
  // No deviation to draw: the tolerance circle sets it, as the arrows would.
  if (!(largest > 0) && has_tolerance(c)) largest = c.tolerance;
  if (pts.empty() || !(largest > 0)) return 1;
  const double spacing = closest_spacing(pts);
  // The largest arrow at most kLargestArrowOfSpacing of the closest spacing (it does not reach
  // its neighbour), as near it as the 1-2-5 series allows (at least 0.32 of it).
  double mag = nice_floor(kLargestArrowOfSpacing * spacing / largest);
  // ... and at least kMinLargestArrowPx long when the scale is known (points so dense that this
  // reaches past the neighbours: the arrow's length matters more than the overlap).
  if (px_per_unit > 0) {
    while (largest * mag * px_per_unit < kMinLargestArrowPx) mag = nice_step(mag * 1.01).value();
  }
  return mag;
}

std::string deviation_vector_plot(const DeviationVectorPlot& c) {
  const Size size = detail::resolve_size(c.size, kVectorPlotSize);
  const double scale = detail::display_scale(c.unit);
  const bool tol = has_tolerance(c);
  std::size_t skipped = 0;
  std::vector<const PlaneDeviation*> pts = detail::usable_items(c.points, usable, skipped);
  const double spacing = closest_spacing(pts);
  const double mag = vector_magnification(c, estimated_px_per_unit(c, pts, size));
  // Circles that would cover their neighbours are left out (the legend says so).
  const bool circles = tol && c.tolerance * mag <= kLargestCircleOfSpacing * spacing;
  auto fails = [&](const PlaneDeviation& p) {
    if (p.out_of_tolerance) return *p.out_of_tolerance;
    return tol && std::hypot(p.dx, p.dy) > c.tolerance;
  };
  const auto failed = static_cast<std::size_t>(
      std::count_if(pts.begin(), pts.end(), [&](const PlaneDeviation* p) { return fails(*p); }));
  const PlaneDeviation* worst = nullptr;
  for (const PlaneDeviation* p : pts) {
    if (!worst || std::hypot(p->dx, p->dy) > std::hypot(worst->dx, worst->dy)) worst = p;
  }
  const double largest = worst ? std::hypot(worst->dx, worst->dy) : 0;
  const int value_decimals =
      largest * scale > 0 ? std::max(1, nice_step(largest * scale / 100).decimals()) : 1;
  auto dv = [&](double v) { return detail::display_value(v * scale, value_decimals, c.unit.unit); };

  std::string desc = "Deviation vectors in the " + c.x_name + c.y_name +
                     " plane: " + detail::count_phrase(pts.size(), "point", "points");
  if (tol) desc += ", " + std::to_string(failed) + " out of the tolerance of " + dv(c.tolerance);
  if (worst) {
    desc += "; largest deviation " + dv(largest) + " at " +
            (worst->label.empty() ? std::string("the point") : worst->label) + " (" + c.x_name +
            " " + svg::exact(worst->x) + ", " + c.y_name + " " + svg::exact(worst->y) + " " +
            c.position_unit + ")";
  }
  desc += "; vectors drawn ×" + svg::exact(mag) + ".";
  if (tol && !circles) {
    desc += " Tolerance circles not drawn: at ×" + svg::exact(mag) +
            " they would be wider than half the points' spacing.";
  }

  std::vector<LegendItem> legend;
  if (!pts.empty()) {
    legend.push_back(detail::marker_item("nominal point", kNominal));
    legend.push_back(detail::line_item("deviation ×" + svg::exact(mag), kArrow));
    if (circles) {
      legend.push_back(detail::marker_item("tolerance " + dv(c.tolerance),
                                           {Shape::Circle, 12, "none", palette::kGrey, 1}));
    } else if (tol) {
      legend.push_back(detail::marker_item("tolerance " + dv(c.tolerance) + ": circles ×" +
                                               svg::exact(mag) +
                                               " would cover the neighbours, not drawn",
                                           {Shape::Circle, 12, "none", palette::kLightGrey, 1}));
    }
    if (failed > 0) legend.push_back(detail::line_item("out of tolerance", kArrowFail));
  }
  const detail::Tally tally{pts.size(), skipped, failed, "point with non-finite values",
                            "points with non-finite values"};
  svg::Writer w;
  // The plot: what remains above the x axis and the scale bar row.
  constexpr double kScaleRowPx = 22;
  Box box;
  box.top = detail::open_chart(w,
                               {kind::kDeviationVectors,
                                c.title,
                                desc,
                                c.description,
                                size,
                                tally,
                                {{"data-magnification", svg::exact(mag)}}},
                               legend);
  box.bottom = detail::plot_bottom(size.height, true, kScaleRowPx);
  box.right = size.width - 16;

  // The data extent: the points and how far their arrows and circles reach.
  double reach = circles ? c.tolerance * mag : 0;
  for (const PlaneDeviation* p : pts) reach = std::max(reach, std::hypot(p->dx, p->dy) * mag);
  double xmin = 0, xmax = 0, ymin = 0, ymax = 0;
  if (!pts.empty()) {
    xmin = xmax = pts[0]->x;
    ymin = ymax = pts[0]->y;
    for (const PlaneDeviation* p : pts) {
      xmin = std::min(xmin, p->x);
      xmax = std::max(xmax, p->x);
      ymin = std::min(ymin, p->y);
      ymax = std::max(ymax, p->y);
    }
  }
  xmin -= reach;
  xmax += reach;
  ymin -= reach;
  ymax += reach;
  double extent = std::max(xmax - xmin, ymax - ymin);
  if (!(extent > 0)) extent = std::max({std::abs(xmin), std::abs(ymin), 10.0});
  const double pad = extent * 0.05;
  xmin -= pad, xmax += pad, ymin -= pad, ymax += pad;
  const double xc = (xmin + xmax) / 2;
  const double yc = (ymin + ymax) / 2;
  const double xr = std::max(xmax - xmin, extent * 0.1);
  const double yr = std::max(ymax - ymin, extent * 0.1);

  // Two passes: the tick labels decide the left margin, which decides the scale.
  LinearScale x, y;
  TickStep step;
  std::vector<double> x_ticks, y_ticks;
  std::vector<std::string> y_labels;
  detail::LeftEdge left{60, 19};
  for (int pass = 0; pass < 2; ++pass) {
    box.left = left.plot_left;
    const double ppu = std::min(box.width() / xr, box.height() / yr);  // px per position unit
    const double hx = box.width() / ppu / 2;
    const double hy = box.height() / ppu / 2;
    x = LinearScale(xc - hx, xc + hx, box.left, box.right);
    y = LinearScale(yc - hy, yc + hy, box.bottom, box.top);
    const double wide = std::max(2 * hx, 2 * hy);
    const double longest = std::max(box.width(), box.height());
    step = nice_step(wide / std::clamp(std::round(longest / 70), 2.0, 10.0));
    x_ticks = ticks_within(xc - hx, xc + hx, step);
    y_ticks = ticks_within(yc - hy, yc + hy, step);
    // Labels that do not fit under the plot thin out to every second one.
    auto x_labels = detail::tick_labels(x_ticks, step);
    if (x_ticks.size() > 1 && detail::widest(x_labels) + 14 > step.value() * ppu) {
      step = TickStep{step.mantissa == 1   ? 2
                      : step.mantissa == 2 ? 5
                                           : 1,
                      step.mantissa == 5 ? step.exponent + 1 : step.exponent};
      x_ticks = ticks_within(xc - hx, xc + hx, step);
      y_ticks = ticks_within(yc - hy, yc + hy, step);
    }
    y_labels = detail::tick_labels(y_ticks, step);
    left = detail::left_edge(y_labels, true);
  }
  const double ppu = x.pixels_per_unit();

  if (pts.empty()) return detail::close_empty_chart(w, box);

  detail::y_axis(w, box, y, y_ticks, y_labels, detail::axis_title(c.y_name, c.position_unit),
                 left.title_x);
  const double below = detail::x_axis(w, box, x, x_ticks, detail::tick_labels(x_ticks, step),
                                      detail::axis_title(c.x_name, c.position_unit));

  w.open("g", {{"class", "vectors"}});
  for (const PlaneDeviation* p : pts) {
    const bool fail = fails(*p);
    const double len = std::hypot(p->dx, p->dy);
    std::string tip = (p->label.empty() ? std::string() : p->label + ": ") + c.x_name + " " +
                      svg::exact(p->x) + ", " + c.y_name + " " + svg::exact(p->y) + " " +
                      c.position_unit + "; d" + c.x_name + " " + dv(p->dx) + ", d" + c.y_name +
                      " " + dv(p->dy) + ", |d| " + dv(len);
    if (fail) tip += " (out of tolerance)";
    w.open("g", {{"class", fail ? "vector fail" : "vector pass"},
                 {"data-label", p->label},
                 {"data-x", svg::exact(p->x)},
                 {"data-y", svg::exact(p->y)},
                 {"data-dx", svg::exact(p->dx)},
                 {"data-dy", svg::exact(p->dy)},
                 {"data-value", svg::exact(len)}});
    w.text("title", {}, tip);
    const double px = x(p->x);
    const double py = y(p->y);
    if (circles) {
      auto attrs = detail::line_attrs(fail ? kCircleFail : kCircle);
      attrs.insert(attrs.begin(), {{"class", "tolerance"},
                                   {"cx", svg::coord(px)},
                                   {"cy", svg::coord(py)},
                                   {"r", svg::coord(c.tolerance * mag * ppu)}});
      w.leaf("circle", attrs);
    }
    // The arrow: a shaft and a filled head, the head at most 45 % of the arrow.
    const double ex = x(p->x + p->dx * mag);
    const double ey = y(p->y + p->dy * mag);
    const double lpx = std::hypot(ex - px, ey - py);
    if (lpx >= 0.5) {
      const LineStyle& style = fail ? kArrowFail : kArrow;
      const double ux = (ex - px) / lpx;
      const double uy = (ey - py) / lpx;
      const double head = std::min(9.0, 0.45 * lpx);
      const double half = head * 0.42;
      const double bx = ex - ux * head;
      const double by = ey - uy * head;
      svg::Path shaft;
      shaft.move_to(px, py).line_to(bx + ux * 0.5, by + uy * 0.5);
      auto attrs = detail::line_attrs(style);
      attrs.insert(attrs.begin(), {{"class", "arrow"}, {"d", shaft.str()}});
      attrs.emplace_back("stroke-linecap", "butt");
      w.leaf("path", attrs);
      svg::Path tip_path;
      tip_path.move_to(ex, ey)
          .line_to(bx - uy * half, by + ux * half)
          .line_to(bx + uy * half, by - ux * half)
          .close();
      w.leaf("path", {{"class", "arrow-head"},
                      {"d", tip_path.str()},
                      {"fill", std::string(style.stroke)},
                      {"stroke", "none"}});
    }
    detail::marker(w, fail ? kNominalFail : kNominal, px, py, {{"class", "nominal"}}, "");
    w.close("g");
  }
  w.close("g");
  detail::plot_frame(w, box,
                     {{"data-x-min", svg::exact(x.domain_lo())},
                      {"data-x-max", svg::exact(x.domain_hi())},
                      {"data-y-min", svg::exact(y.domain_lo())},
                      {"data-y-max", svg::exact(y.domain_hi())}});

  // The scale bar: a nice length of deviation, 30 to 90 px long, and what it stands for.
  const double bar_display = nice_floor(90 / (mag * ppu) * std::abs(scale));
  const double bar_px = bar_display / std::abs(scale) * mag * ppu;
  const int bar_decimals = nice_step(bar_display).decimals();
  const double sy = below + 8;
  const double sx = box.left;
  w.open("g", {{"class", "scale-bar"},
               {"data-value", svg::exact(bar_display / scale)},
               {"data-length", svg::coord(bar_px)}});
  svg::Path bar;
  bar.move_to(sx, sy - 4)
      .line_to(sx, sy + 4)
      .move_to(sx, sy)
      .line_to(sx + bar_px, sy)
      .move_to(sx + bar_px, sy - 4)
      .line_to(sx + bar_px, sy + 4);
  w.leaf("path", {{"d", bar.str()},
                  {"fill", "none"},
                  {"stroke", std::string(palette::kInk)},
                  {"stroke-width", "2"}});
  const std::string scale_text = detail::display_value(bar_display, bar_decimals, c.unit.unit) +
                                 " of deviation (arrows ×" + svg::exact(mag) + ")";
  w.text("text",
         {{"x", svg::coord(sx + bar_px + 8)},
          {"y", svg::coord(sy + 4)},
          {"fill", std::string(palette::kInk)}},
         detail::fit_text(scale_text, size.width - (sx + bar_px + 16), detail::kFontPx));
  w.close("g");
  return detail::close_chart(w);
}

}  // namespace ncqual::charts
