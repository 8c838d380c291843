// SPDX-License-Identifier: Apache-2.0
// Internal: the parts every chart draws the same way (the root element, the visible title, the
// legend, axes with grid and tick labels, markers, labels at the plot's edge, "no data"), and the
// estimate of text widths the layouts use. Not installed; the charts' .cpp files only.
#pragma once

#include <cstdint>
#include <optional>
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

// The numbers of a series for its <desc>: "12 points", "1 non-finite value skipped".
std::string count_phrase(std::size_t n, std::string_view one, std::string_view many);

// A value in display units as exactly as it was given, for the <desc>: "0.0125 mm".
std::string exact_display(double display, std::string_view unit);

// " Tolerance: lower …, upper …." for the <desc> of a chart with a tolerance band (only its finite
// limits; "" without any), the limits in display units.
std::string tolerance_sentence(double lower, double upper, double scale, std::string_view unit);

// The factor from the caller's unit to the display unit: `unit.scale`, 1 when it is 0 or not
// finite.
double display_scale(const DisplayUnit& unit);

// Pointers to the items that are `usable`, in their order; the others are counted in `skipped`.
template <typename T, typename Usable>
std::vector<const T*> usable_items(const std::vector<T>& items, Usable usable,
                                   std::size_t& skipped) {
  std::vector<const T*> out;
  for (const T& item : items) {
    if (usable(item)) {
      out.push_back(&item);
    } else {
      ++skipped;
    }
  }
  return out;
}

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
LegendItem line_item(std::string label, const LineStyle& style);
LegendItem marker_item(std::string label, const MarkerStyle& style);
LegendItem area_item(std::string label, std::string_view fill);
// Rows the legend needs within `width` px.
int legend_rows(const std::vector<LegendItem>& items, double width);
inline constexpr double kLegendRowPx = 18;
// Draws the legend in rows from (left, top) within `width`; returns the y below it.
double draw_legend(svg::Writer& w, const std::vector<LegendItem>& items, double left, double top,
                   double width);

// What a chart counts, for the root's data-points, data-skipped and data-failed (when counted),
// and for the end of its <desc> (" 2 non-finite values skipped.").
struct Tally {
  Tally(std::size_t points_, std::size_t skipped_, std::optional<std::size_t> failed_ = {},
        std::string_view one_ = "non-finite value", std::string_view many_ = "non-finite values")
      : points(points_), skipped(skipped_), failed(failed_), one(one_), many(many_) {}
  std::size_t points;
  std::size_t skipped;
  std::optional<std::size_t> failed;
  std::string_view one;  // what is skipped, one and more
  std::string_view many;
};

// The opening every chart shares: the root <svg> with its <title> and <desc>, a white background,
// the visible title at the top left and the legend below it.
struct Head {
  std::string_view kind;  // data-chart
  std::string title;
  std::string desc;              // the chart's own sentences; the tally's and `description` follow
  std::string_view description;  // the caller's, the end of the <desc>
  Size size;
  Tally tally;
  std::vector<svg::Attr> extra;  // more attributes of the root (data-magnification, ...)
};
// Returns the y 6 px below the legend (or the title), where the plot may start.
double open_chart(svg::Writer& w, const Head& head, const std::vector<LegendItem>& legend);
// Closes the root; returns the chart.
std::string close_chart(svg::Writer& w);

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
// The end of a chart without data: the frame, "no data" in it; returns the chart.
std::string close_empty_chart(svg::Writer& w, const Box& box,
                              const std::vector<svg::Attr>& frame_extra = {});

// A <path class="`cls`"> of `style` along `path`.
void styled_path(svg::Writer& w, std::string_view cls, const svg::Path& path,
                 const LineStyle& style);
// A horizontal <line class="`cls`"> across `box` at `y` px with data-value `value`.
void horizontal_line(svg::Writer& w, const Box& box, double y, const LineStyle& style,
                     std::string_view cls, double value);

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

namespace ncqual::charts {
// The drawing vocabulary, without detail:: in the charts' .cpp files (the only ones that include
// this header).
using detail::Box;
using detail::EdgeLabel;
using detail::LegendItem;
using detail::LineStyle;
using detail::MarkerStyle;
using detail::Shape;
}  // namespace ncqual::charts

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
