// SPDX-License-Identifier: Apache-2.0
// Internal: the parts every chart draws the same way (the root element, the visible title, the
// legend, axes with grid and tick labels, markers, labels at the plot's edge, "no data"), and the
// estimate of text widths the layouts use. Not installed; the charts' .cpp files only.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ncqual/charts/axis.hpp"
#include "ncqual/charts/chart.hpp"
#include "ncqual/charts/svg.hpp"

namespace ncqual::charts::detail {

inline constexpr double kFontPx = 12;       // tick labels, legend, axis titles
inline constexpr double kSmallFontPx = 11;  // labels inside the plot
inline constexpr double kTitleFontPx = 14;
inline constexpr std::string_view kFontFamily = "DejaVu Sans, Verdana, Arial, sans-serif";

// The width of `text` in px at `font_px`, estimated on the wide side (DejaVu Sans: 0.62 em per
// character on average; digits are 0.64 em).
double text_width(std::string_view text, double font_px);

// `text` cut to fit `max_px` at `font_px`, with "…" at the end when cut.
std::string fit_text(std::string_view text, double max_px, double font_px);

// The size a caller asked for, or the default, clamped.
Size resolve_size(const Size& asked, Size fallback);

struct Box {
  double left = 0, top = 0, right = 0, bottom = 0;
  double width() const { return right - left; }
  double height() const { return bottom - top; }
  double centre_x() const { return (left + right) / 2; }
  double centre_y() const { return (top + bottom) / 2; }
};

// The root <svg> with its <title> and <desc>, a white background, and the visible title at the
// top left. Returns the y below the title (where a legend or the plot may start).
struct Head {
  std::string_view kind;  // data-chart
  std::string title;
  std::string desc;
  Size size;
  std::vector<svg::Attr> extra;  // more attributes of the root (data-points, ...)
};
double open_chart(svg::Writer& w, const Head& head);
void close_chart(svg::Writer& w);

// The numbers of a series for its <desc>: "12 points", "1 non-finite value skipped".
std::string count_phrase(std::size_t n, std::string_view one, std::string_view many);

// The end of every chart's <desc>: " N <what> skipped." when some were, then the caller's own
// description.
void end_description(std::string& desc, std::size_t skipped, std::string_view one,
                     std::string_view many, const std::string& description);

enum class Shape { None, Circle, Diamond, Square, TriangleUp, TriangleDown, Cross };

// A marker centred on (x, y), `size` px across. `extra` goes onto the element (class, data-*),
// `tooltip` becomes its <title> (shown on hover in a browser) when not empty.
struct MarkerStyle {
  Shape shape = Shape::Circle;
  double size = 7;
  std::string_view fill = palette::kAccent;
  std::string_view stroke = "#ffffff";
  double stroke_width = 1;
};
void marker(svg::Writer& w, const MarkerStyle& style, double x, double y,
            const std::vector<svg::Attr>& extra, std::string_view tooltip);

// A line style: stroke colour, width and dash pattern ("" solid).
struct LineStyle {
  std::string_view stroke = palette::kInk;
  double width = 1;
  std::string_view dash;
};
std::vector<svg::Attr> line_attrs(const LineStyle& s);

// One entry of a legend: a short line with the style (when `line`), a marker (when its shape is
// not None), or a filled box (when `area` is not empty), and the label.
struct LegendItem {
  std::string label;
  bool line = false;
  LineStyle line_style;
  MarkerStyle marker_style{Shape::None};
  std::string_view area;  // fill colour of a box swatch
};
// Rows the legend needs within `width` px.
int legend_rows(const std::vector<LegendItem>& items, double width);
inline constexpr double kLegendRowPx = 18;
// Draws the legend in rows from (left, top) within `width`; returns the y below it.
double draw_legend(svg::Writer& w, const std::vector<LegendItem>& items, double left, double top,
                   double width);

// The plot frame (a rectangle with class "plot-area" and the data range it shows as data-*).
void plot_frame(svg::Writer& w, const Box& box, const std::vector<svg::Attr>& extra = {});

// Horizontal grid lines and tick labels left of `box` at `ticks` (in the domain of `scale`),
// and the axis title rotated, centred on the plot's height, at `title_x`.
void y_axis(svg::Writer& w, const Box& box, const LinearScale& scale,
            const std::vector<double>& ticks, const std::vector<std::string>& labels,
            std::string_view title, double title_x);
// Vertical grid lines and tick labels below `box`, and the axis title centred below them.
// Returns the y below the title.
double x_axis(svg::Writer& w, const Box& box, const LinearScale& scale,
              const std::vector<double>& ticks, const std::vector<std::string>& labels,
              std::string_view title);

// "no data" in the middle of `box`.
void no_data(svg::Writer& w, const Box& box);

// Labels in the margin right of the plot, each at its y if it can, pushed apart so that none
// overlaps (at least one line apart) and kept within [top, bottom].
struct EdgeLabel {
  double y = 0;
  std::string text;
  std::string_view colour = palette::kDark;
};
void edge_labels(svg::Writer& w, std::vector<EdgeLabel> labels, double x, double top,
                 double bottom);
// The width the edge labels need (0 when there are none).
double edge_labels_width(const std::vector<EdgeLabel>& labels);

// The attributes of text that stays readable over lines and markers: a white halo.
std::vector<svg::Attr> halo_text_attrs(double x, double y, std::string_view anchor, double font_px);

// The y-axis tick labels for a numeric axis.
std::vector<std::string> tick_labels(const std::vector<double>& ticks, const TickStep& step);
// The widest of `labels` at kFontPx.
double widest(const std::vector<std::string>& labels, double font_px = kFontPx);

// "name (unit)", "name" without a unit.
std::string axis_title(std::string_view name, std::string_view unit);

// A value in display units for a sentence: e.g. "12.3 µm" with `decimals`.
std::string display_value(double display, int decimals, std::string_view unit);

}  // namespace ncqual::charts::detail

namespace ncqual::charts::detail {

// The vertical extent of a plot with an x axis below it: from `top` to above the tick labels
// (and the axis title when `x_title`) and `bottom_extra` more px.
inline double plot_bottom(double height, bool x_title, double bottom_extra = 0) {
  return height - (x_title ? 46 : 28) - bottom_extra;
}
// A value axis over [lo, hi] with 4 % of room at each end, so that no line or marker sits on the
// plot's frame.
NiceAxis padded_axis(double lo, double hi, int target_intervals);
// Intervals for a y axis of `plot_height` px: about one per 45 px, 2 to 10.
int y_intervals(double plot_height);
// The left edge of a plot whose y tick labels are `labels` (with room for a rotated axis title
// when `y_title`), and where that title goes.
struct LeftEdge {
  double plot_left = 0;
  double title_x = 0;
};
LeftEdge left_edge(const std::vector<std::string>& labels, bool y_title);

// A numeric x axis whose labels fit: the nice axis over [lo, hi] with the most intervals (at
// most `max_intervals`) whose tick labels stay 14 px apart or more over `width` px.
NiceAxis fitting_x_axis(double lo, double hi, double width, int max_intervals = 10);

}  // namespace ncqual::charts::detail
