// SPDX-License-Identifier: Apache-2.0
#include "ncqual/charts/point_deviation.hpp"

#include <algorithm>
#include <cmath>

#include "frame.hpp"

namespace ncqual::charts {
namespace {

constexpr LineStyle kToleranceLine{palette::kDark, 1.5, "7 4"};
constexpr LineStyle kDataLine{palette::kLightGrey, 1, ""};
constexpr LineStyle kZeroLine{palette::kGrey, 1, ""};
constexpr MarkerStyle kPassMarker{Shape::Circle, 7, palette::kAccent, "#ffffff", 1};
constexpr MarkerStyle kFailMarker{Shape::Square, 9, palette::kRed, palette::kInk, 0.8};

}  // namespace

std::string point_deviation_chart(const PointDeviationChart& c) {
  const Size size = detail::resolve_size(c.size, kPointDeviationSize);
  const double scale = detail::display_scale(c.unit);
  const bool has_lower = std::isfinite(c.tolerance.lower);
  const bool has_upper = std::isfinite(c.tolerance.upper);

  std::size_t skipped = 0;
  std::vector<const NumberedDeviation*> points = detail::usable_items(
      c.points, [](const NumberedDeviation& p) { return std::isfinite(p.value); }, skipped);
  std::stable_sort(
      points.begin(), points.end(),
      [](const NumberedDeviation* a, const NumberedDeviation* b) { return a->number < b->number; });
  auto out_of_tolerance = [&](double v) {
    return (has_lower && v < c.tolerance.lower) || (has_upper && v > c.tolerance.upper);
  };
  const auto failed = static_cast<std::size_t>(
      std::count_if(points.begin(), points.end(),
                    [&](const NumberedDeviation* p) { return out_of_tolerance(p->value); }));

  std::string desc = (c.quantity.empty() ? std::string("Deviation") : c.quantity) +
                     " by point number: " + detail::count_phrase(points.size(), "point", "points");
  if (!points.empty()) {
    desc += " (numbers " + std::to_string(points.front()->number) + " to " +
            std::to_string(points.back()->number) + "), " + std::to_string(failed) +
            " out of tolerance";
  }
  desc += ".";
  desc += detail::tolerance_sentence(c.tolerance.lower, c.tolerance.upper, scale, c.unit.unit);

  std::vector<LegendItem> legend;
  if (!points.empty()) {
    legend.push_back(detail::marker_item("within tolerance", kPassMarker));
    if (failed > 0) legend.push_back(detail::marker_item("out of tolerance", kFailMarker));
    if (has_lower || has_upper) {
      legend.push_back(detail::line_item("tolerance limit", kToleranceLine));
    }
  }
  svg::Writer w;
  Box box;
  box.top = detail::open_chart(w,
                               {kind::kPointDeviation,
                                c.title,
                                desc,
                                c.description,
                                size,
                                {points.size(), skipped, failed},
                                {}},
                               legend);
  box.bottom = detail::plot_bottom(size.height, !c.number_title.empty());
  std::vector<double> ys = {0};
  for (const NumberedDeviation* p : points) ys.push_back(p->value * scale);
  if (has_lower) ys.push_back(c.tolerance.lower * scale);
  if (has_upper) ys.push_back(c.tolerance.upper * scale);
  const auto [ymin, ymax] = std::minmax_element(ys.begin(), ys.end());
  const NiceAxis y_axis =
      points.empty() ? nice_axis(-1, 1, 2)
                     : detail::padded_axis(*ymin, *ymax, detail::y_intervals(box.height()));
  const auto y_labels = detail::tick_labels(y_axis.ticks, y_axis.step);
  const detail::LeftEdge left =
      detail::left_edge(y_labels, !c.quantity.empty() || !c.unit.unit.empty());
  box.left = left.plot_left;
  const LinearScale y(y_axis.lo, y_axis.hi, box.bottom, box.top);
  std::vector<detail::EdgeLabel> edge;
  if (!points.empty()) {
    if (has_upper) edge.push_back({y(c.tolerance.upper * scale), "upper tol.", palette::kDark});
    if (has_lower) edge.push_back({y(c.tolerance.lower * scale), "lower tol.", palette::kDark});
  }
  box.right = size.width - std::max(14.0, detail::edge_labels_width(edge) + 4);

  if (points.empty()) return detail::close_empty_chart(w, box);

  // Point numbers: whole numbers, half a step of room at each end.
  const double nmin = points.front()->number - 0.5;
  const double nmax = points.back()->number + 0.5;
  NiceAxis n_axis = detail::fitting_x_axis(nmin, nmax, box.width(), 20);
  if (n_axis.step.exponent < 0) n_axis.step = {1, 0};
  const auto n_ticks = ticks_within(nmin, nmax, n_axis.step);
  const LinearScale x(nmin, nmax, box.left, box.right);

  detail::y_axis(w, box, y, y_axis.ticks, y_labels, detail::axis_title(c.quantity, c.unit.unit),
                 left.title_x);
  detail::x_axis(w, box, x, n_ticks, detail::tick_labels(n_ticks, n_axis.step), c.number_title);

  auto hline = [&](double value, const LineStyle& style, std::string_view cls) {
    detail::horizontal_line(w, box, y(value * scale), style, cls, value);
  };
  hline(0, kZeroLine, "zero");
  if (has_lower) hline(c.tolerance.lower, kToleranceLine, "tolerance lower");
  if (has_upper) hline(c.tolerance.upper, kToleranceLine, "tolerance upper");

  if (points.size() > 1) {
    svg::Path line;
    for (const NumberedDeviation* p : points) line.vertex(x(p->number), y(p->value * scale));
    detail::styled_path(w, "data-line", line, kDataLine);
  }
  const int decimals = nice_step(y_axis.step.value() / 10).decimals();
  w.open("g", {{"class", "points"}});
  for (const NumberedDeviation* p : points) {
    const bool fail = out_of_tolerance(p->value);
    std::string tip = p->label.empty() ? "point " + std::to_string(p->number) : p->label;
    tip += ": " + detail::display_value(p->value * scale, decimals, c.unit.unit);
    if (fail) tip += " (out of tolerance)";
    detail::marker(w, fail ? kFailMarker : kPassMarker, x(p->number), y(p->value * scale),
                   {{"class", fail ? "point fail" : "point pass"},
                    {"data-point", std::to_string(p->number)},
                    {"data-value", svg::exact(p->value)}},
                   tip);
  }
  w.close("g");
  detail::plot_frame(
      w, box, {{"data-y-min", svg::exact(y_axis.lo)}, {"data-y-max", svg::exact(y_axis.hi)}});
  detail::edge_labels(w, edge, box.right + 5, box.top, box.bottom);
  return detail::close_chart(w);
}

}  // namespace ncqual::charts
