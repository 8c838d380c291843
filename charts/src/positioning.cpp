// SPDX-License-Identifier: Apache-2.0
#include "ncqual/charts/positioning.hpp"

#include <algorithm>
#include <cmath>

#include "frame.hpp"

namespace ncqual::charts {
namespace {

constexpr LineStyle kUpMean{palette::kAccent, 1.8, ""};
constexpr LineStyle kUpBand{palette::kAccent, 1, "5 3"};
constexpr LineStyle kDownMean{palette::kInk, 1.8, "9 3"};
constexpr LineStyle kDownBand{palette::kInk, 1, "1.5 2.5"};
constexpr LineStyle kBidirectional{palette::kGrey, 1.4, "8 3 2 3"};
constexpr LineStyle kZeroLine{palette::kGrey, 1, ""};
constexpr MarkerStyle kUpMarker{Shape::TriangleUp, 9, palette::kAccent, "#ffffff", 0.8};
constexpr MarkerStyle kDownMarker{Shape::TriangleDown, 9, palette::kInk, "#ffffff", 0.8};

struct Row {
  double position;
  std::optional<DirectionStats> up, down;
};

bool usable(const std::optional<DirectionStats>& d) {
  return d && std::isfinite(d->mean) && std::isfinite(d->s);
}

}  // namespace

std::string positioning_chart(const PositioningChart& c) {
  const Size size = detail::resolve_size(c.size, kPositioningSize);
  const double scale = detail::display_scale(c.unit);

  std::vector<Row> rows;
  std::size_t skipped = 0;
  for (const PositioningTarget& t : c.targets) {
    if (!std::isfinite(t.position)) {
      skipped += (t.up ? 1 : 0) + (t.down ? 1 : 0);
      continue;
    }
    Row r{t.position, std::nullopt, std::nullopt};
    if (usable(t.up)) r.up = t.up;
    if (usable(t.down)) r.down = t.down;
    skipped += (t.up && !r.up ? 1 : 0) + (t.down && !r.down ? 1 : 0);
    if (r.up || r.down) rows.push_back(r);
  }
  std::stable_sort(rows.begin(), rows.end(),
                   [](const Row& a, const Row& b) { return a.position < b.position; });
  const bool any_up =
      std::any_of(rows.begin(), rows.end(), [](const Row& r) { return r.up.has_value(); });
  const bool any_down =
      std::any_of(rows.begin(), rows.end(), [](const Row& r) { return r.down.has_value(); });
  const bool any_both =
      std::any_of(rows.begin(), rows.end(), [](const Row& r) { return r.up && r.down; });
  const bool bidirectional = c.show_bidirectional_mean && any_both;

  std::string desc = "ISO 230-2 positioning of axis " + c.axis_name + ": " +
                     detail::count_phrase(rows.size(), "target position", "target positions");
  if (!rows.empty()) {
    desc += " from " + svg::exact(rows.front().position) + " to " +
            svg::exact(rows.back().position) + " " + c.position_unit;
    desc += any_up && any_down ? ", both directions" : any_up ? ", ↑ only" : ", ↓ only";
  }
  desc += "; mean deviation and mean ± 2s per direction";
  if (!c.unit.unit.empty()) desc += " in " + c.unit.unit;
  desc += ".";

  std::vector<LegendItem> legend;
  if (any_up) {
    legend.push_back({"mean ↑", true, kUpMean, kUpMarker, {}});
    legend.push_back(detail::line_item("mean ↑ ± 2s", kUpBand));
  }
  if (any_down) {
    legend.push_back({"mean ↓", true, kDownMean, kDownMarker, {}});
    legend.push_back(detail::line_item("mean ↓ ± 2s", kDownBand));
  }
  if (bidirectional) legend.push_back(detail::line_item("mean bidirectional", kBidirectional));
  const detail::Tally tally{rows.size(), skipped, std::nullopt, "non-finite direction",
                            "non-finite directions"};
  svg::Writer w;
  Box box;
  box.top = detail::open_chart(
      w, {kind::kPositioning, c.title, desc, c.description, size, tally, {}}, legend);
  box.bottom = detail::plot_bottom(size.height, true);
  std::vector<double> ys = {0};
  for (const Row& r : rows) {
    for (const auto* d : {&r.up, &r.down}) {
      if (!*d) continue;
      ys.push_back(((*d)->mean + 2 * (*d)->s) * scale);
      ys.push_back(((*d)->mean - 2 * (*d)->s) * scale);
    }
  }
  const auto [ymin, ymax] = std::minmax_element(ys.begin(), ys.end());
  const NiceAxis y_axis =
      rows.empty() ? nice_axis(-1, 1, 2)
                   : detail::padded_axis(*ymin, *ymax, detail::y_intervals(box.height()));
  const auto y_labels = detail::tick_labels(y_axis.ticks, y_axis.step);
  const detail::LeftEdge left = detail::left_edge(y_labels, true);
  box.left = left.plot_left;
  box.right = size.width - 16;
  const std::string x_title = detail::axis_title("target position " + c.axis_name, c.position_unit);

  if (rows.empty()) return detail::close_empty_chart(w, box);
  const double span = rows.back().position - rows.front().position;
  const double pad = span > 0 ? span * 0.03 : 1;
  const double xlo = rows.front().position - pad;
  const double xhi = rows.back().position + pad;
  const NiceAxis x_axis = detail::fitting_x_axis(xlo, xhi, box.width(), 12);
  const auto x_ticks = ticks_within(xlo, xhi, x_axis.step);
  const LinearScale x(xlo, xhi, box.left, box.right);
  const LinearScale y(y_axis.lo, y_axis.hi, box.bottom, box.top);

  detail::y_axis(w, box, y, y_axis.ticks, y_labels, detail::axis_title(c.quantity, c.unit.unit),
                 left.title_x);
  detail::x_axis(w, box, x, x_ticks, detail::tick_labels(x_ticks, x_axis.step), x_title);
  w.leaf("line", {{"class", "zero"},
                  {"x1", svg::coord(box.left)},
                  {"y1", svg::coord(y(0))},
                  {"x2", svg::coord(box.right)},
                  {"y2", svg::coord(y(0))},
                  {"stroke", std::string(kZeroLine.stroke)},
                  {"stroke-width", "1"}});

  // A polyline through the rows that have the direction, `k` standard deviations off the mean.
  auto series = [&](bool up, double k, const LineStyle& style, std::string_view cls) {
    svg::Path p;
    for (const Row& r : rows) {
      const auto& d = up ? r.up : r.down;
      if (d) p.vertex(x(r.position), y((d->mean + k * d->s) * scale));
    }
    if (!p.empty()) detail::styled_path(w, cls, p, style);
  };
  if (any_up) {
    series(true, 2, kUpBand, "band up plus");
    series(true, -2, kUpBand, "band up minus");
  }
  if (any_down) {
    series(false, 2, kDownBand, "band down plus");
    series(false, -2, kDownBand, "band down minus");
  }
  if (bidirectional) {
    svg::Path p;
    for (const Row& r : rows) {
      if (r.up && r.down) p.vertex(x(r.position), y((r.up->mean + r.down->mean) / 2 * scale));
    }
    detail::styled_path(w, "mean bidirectional", p, kBidirectional);
  }
  if (any_down) series(false, 0, kDownMean, "line down");
  if (any_up) series(true, 0, kUpMean, "line up");

  const int decimals = nice_step(y_axis.step.value() / 10).decimals();
  w.open("g", {{"class", "points"}});
  for (const Row& r : rows) {
    for (const bool up : {false, true}) {
      const auto& d = up ? r.up : r.down;
      if (!d) continue;
      std::string tip = svg::exact(r.position) + " " + c.position_unit + (up ? " ↑" : " ↓") +
                        ": mean " + detail::display_value(d->mean * scale, decimals, c.unit.unit) +
                        ", s " + detail::display_value(d->s * scale, decimals, c.unit.unit);
      detail::marker(w, up ? kUpMarker : kDownMarker, x(r.position), y(d->mean * scale),
                     {{"class", up ? "mean up" : "mean down"},
                      {"data-direction", up ? "up" : "down"},
                      {"data-target", svg::exact(r.position)},
                      {"data-value", svg::exact(d->mean)},
                      {"data-s", svg::exact(d->s)}},
                     tip);
    }
  }
  w.close("g");
  detail::plot_frame(
      w, box, {{"data-y-min", svg::exact(y_axis.lo)}, {"data-y-max", svg::exact(y_axis.hi)}});
  return detail::close_chart(w);
}

}  // namespace ncqual::charts
