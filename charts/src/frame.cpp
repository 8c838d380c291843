// SPDX-License-Identifier: Apache-2.0
#include "frame.hpp"

#include <algorithm>
#include <cmath>

namespace ncqual::charts::detail {
namespace {

// Width of one character in em, on the wide side of DejaVu Sans (the widest of the fonts the
// charts name).
double char_em(unsigned char c) {
  if (c >= '0' && c <= '9') return 0.64;
  if (c == ' ') return 0.32;
  if (std::string_view(".,:;'|!il()[]").find(static_cast<char>(c)) != std::string_view::npos) {
    return 0.36;
  }
  if (c >= 'A' && c <= 'Z') return c == 'M' || c == 'W' ? 0.9 : 0.72;
  if (c == 'm' || c == 'w') return 0.9;
  if (c >= 'a' && c <= 'z') return 0.6;
  return 0.7;
}

}  // namespace

double text_width(std::string_view text, double font_px) {
  double em = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      em += char_em(c);
    } else if ((c & 0xC0) != 0x80) {
      em += 0.84;  // a non-ASCII character (counted at its lead byte): µ, °, ±, −, …
    }
  }
  return em * font_px;
}

std::string fit_text(std::string_view text, double max_px, double font_px) {
  if (text_width(text, font_px) <= max_px) return std::string(text);
  const std::string_view ellipsis = "\xE2\x80\xA6";
  std::string out;
  double used = text_width(ellipsis, font_px);
  std::size_t i = 0;
  while (i < text.size()) {
    std::size_t n = 1;
    while (i + n < text.size() && (static_cast<unsigned char>(text[i + n]) & 0xC0) == 0x80) ++n;
    const double w = text_width(text.substr(i, n), font_px);
    if (used + w > max_px) break;
    out.append(text.substr(i, n));
    used += w;
    i += n;
  }
  return out + std::string(ellipsis);
}

Size resolve_size(const Size& asked, Size fallback) {
  auto side = [](double v, double def) {
    if (!std::isfinite(v) || v <= 0) return def;
    return std::clamp(v, 160.0, 4000.0);
  };
  return {side(asked.width, fallback.width), side(asked.height, fallback.height)};
}

namespace {

// The root, its <title> and <desc>, the background and the visible title; returns the y below the
// title.
double open_root(svg::Writer& w, const Head& head) {
  const std::string width = svg::fixed(head.size.width, 0);
  const std::string height = svg::fixed(head.size.height, 0);
  std::vector<svg::Attr> attrs = {
      {"xmlns", "http://www.w3.org/2000/svg"},
      {"viewBox", "0 0 " + width + " " + height},
      {"width", width},
      {"height", height},
      {"role", "img"},
      {"class", "ncqual-chart ncqual-chart-" + std::string(head.kind)},
      {"data-chart", std::string(head.kind)},
      {"font-family", std::string(kFontFamily)},
      {"font-size", svg::fixed(kFontPx, 0)},
  };
  attrs.emplace_back("data-points", std::to_string(head.tally.points));
  attrs.emplace_back("data-skipped", std::to_string(head.tally.skipped));
  if (head.tally.failed) attrs.emplace_back("data-failed", std::to_string(*head.tally.failed));
  attrs.insert(attrs.end(), head.extra.begin(), head.extra.end());
  w.open("svg", attrs);
  w.text("title", {}, head.title);
  std::string desc = head.desc;
  if (head.tally.skipped > 0) {
    desc += " " + count_phrase(head.tally.skipped, head.tally.one, head.tally.many) + " skipped.";
  }
  if (!head.description.empty()) desc += " " + std::string(head.description);
  w.text("desc", {}, desc);
  w.leaf("rect", {{"x", "0"},
                  {"y", "0"},
                  {"width", width},
                  {"height", height},
                  {"fill", "#ffffff"},
                  {"class", "background"}});
  if (head.title.empty()) return 8;
  w.text("text",
         {{"class", "chart-title"},
          {"x", "8"},
          {"y", "19"},
          {"font-size", svg::fixed(kTitleFontPx, 0)},
          {"font-weight", "bold"},
          {"fill", std::string(palette::kInk)}},
         fit_text(head.title, head.size.width - 16, kTitleFontPx * 1.08));
  return 28;
}

}  // namespace

double open_chart(svg::Writer& w, const Head& head, const std::vector<LegendItem>& legend) {
  const double top = open_root(w, head);
  return draw_legend(w, legend, 8, top, head.size.width - 16) + 6;
}

std::string close_chart(svg::Writer& w) {
  w.close("svg");
  return w.take();
}

std::string count_phrase(std::size_t n, std::string_view one, std::string_view many) {
  return std::to_string(n) + " " + std::string(n == 1 ? one : many);
}

std::string exact_display(double display, std::string_view unit) {
  return svg::exact(display) + (unit.empty() ? "" : " " + std::string(unit));
}

std::string tolerance_sentence(double lower, double upper, double scale, std::string_view unit) {
  const bool has_lower = std::isfinite(lower);
  const bool has_upper = std::isfinite(upper);
  if (!has_lower && !has_upper) return "";
  std::string s = " Tolerance:";
  if (has_lower) s += " lower " + exact_display(lower * scale, unit);
  if (has_lower && has_upper) s += ",";
  if (has_upper) s += " upper " + exact_display(upper * scale, unit);
  return s + ".";
}

double display_scale(const DisplayUnit& unit) {
  return std::isfinite(unit.scale) && unit.scale != 0 ? unit.scale : 1;
}

void marker(svg::Writer& w, const MarkerStyle& style, double x, double y,
            const std::vector<svg::Attr>& extra, std::string_view tooltip) {
  if (style.shape == Shape::None) return;
  const double r = style.size / 2;
  std::vector<svg::Attr> attrs;
  std::string_view tag = "path";
  svg::Path p;
  switch (style.shape) {
    case Shape::Circle:
      tag = "circle";
      attrs = {{"cx", svg::coord(x)}, {"cy", svg::coord(y)}, {"r", svg::coord(r)}};
      break;
    case Shape::Square:
      tag = "rect";
      attrs = {{"x", svg::coord(x - r * 0.85)},
               {"y", svg::coord(y - r * 0.85)},
               {"width", svg::coord(r * 1.7)},
               {"height", svg::coord(r * 1.7)}};
      break;
    case Shape::Diamond:
      p.move_to(x, y - r).line_to(x + r, y).line_to(x, y + r).line_to(x - r, y).close();
      break;
    case Shape::TriangleUp:
      p.move_to(x, y - r).line_to(x + r, y + r * 0.8).line_to(x - r, y + r * 0.8).close();
      break;
    case Shape::TriangleDown:
      p.move_to(x, y + r).line_to(x + r, y - r * 0.8).line_to(x - r, y - r * 0.8).close();
      break;
    case Shape::Cross: {
      const double a = r * 0.75;
      p.move_to(x - a, y - a).line_to(x + a, y + a).move_to(x - a, y + a).line_to(x + a, y - a);
      break;
    }
    case Shape::None: return;
  }
  if (tag == "path") attrs = {{"d", p.str()}};
  const bool cross = style.shape == Shape::Cross;
  attrs.emplace_back("fill", cross ? "none" : std::string(style.fill));
  attrs.emplace_back("stroke", cross ? std::string(style.fill) : std::string(style.stroke));
  attrs.emplace_back("stroke-width", svg::fixed(cross ? 2 : style.stroke_width, 2));
  attrs.insert(attrs.end(), extra.begin(), extra.end());
  if (tooltip.empty()) {
    w.leaf(tag, attrs);
  } else {
    w.open(tag, attrs);
    w.text("title", {}, tooltip);
    w.close(tag);
  }
}

std::vector<svg::Attr> line_attrs(const LineStyle& s) {
  return {{"fill", "none"},
          {"stroke", std::string(s.stroke)},
          {"stroke-width", svg::fixed(s.width, 2)},
          {"stroke-dasharray", std::string(s.dash)}};
}

LegendItem line_item(std::string label, const LineStyle& style) {
  return {std::move(label), true, style, {Shape::None}, {}};
}

LegendItem marker_item(std::string label, const MarkerStyle& style) {
  return {std::move(label), false, {}, style, {}};
}

LegendItem area_item(std::string label, std::string_view fill) {
  return {std::move(label), false, {}, {Shape::None}, fill};
}

namespace {
constexpr double kSwatchPx = 26;
constexpr double kItemGapPx = 16;

double item_width(const LegendItem& item) {
  return kSwatchPx + 6 + text_width(item.label, kFontPx) + kItemGapPx;
}
}  // namespace

int legend_rows(const std::vector<LegendItem>& items, double width) {
  if (items.empty()) return 0;
  int rows = 1;
  double x = 0;
  for (const LegendItem& item : items) {
    const double iw = std::min(item_width(item), width);
    if (x > 0 && x + iw > width) {
      ++rows;
      x = 0;
    }
    x += iw;
  }
  return rows;
}

double draw_legend(svg::Writer& w, const std::vector<LegendItem>& items, double left, double top,
                   double width) {
  if (items.empty()) return top;
  w.open("g", {{"class", "legend"}});
  double x = 0;
  double row_top = top;
  for (const LegendItem& item : items) {
    const double iw = std::min(item_width(item), width);
    if (x > 0 && x + iw > width) {
      row_top += kLegendRowPx;
      x = 0;
    }
    const double cy = row_top + kLegendRowPx / 2;
    const double sx = left + x;
    if (!item.area.empty()) {
      w.leaf("rect", {{"x", svg::coord(sx)},
                      {"y", svg::coord(cy - 5)},
                      {"width", svg::coord(kSwatchPx)},
                      {"height", "10"},
                      {"fill", std::string(item.area)},
                      {"stroke", "none"}});
    }
    if (item.line) {
      auto attrs = line_attrs(item.line_style);
      attrs.insert(attrs.begin(), {{"x1", svg::coord(sx)},
                                   {"y1", svg::coord(cy)},
                                   {"x2", svg::coord(sx + kSwatchPx)},
                                   {"y2", svg::coord(cy)}});
      w.leaf("line", attrs);
    }
    marker(w, item.marker_style, sx + kSwatchPx / 2, cy, {}, "");
    w.text("text",
           {{"x", svg::coord(sx + kSwatchPx + 6)},
            {"y", svg::coord(cy + 4)},
            {"fill", std::string(palette::kInk)}},
           fit_text(item.label, width - kSwatchPx - 6, kFontPx));
    x += iw;
  }
  w.close("g");
  return row_top + kLegendRowPx;
}

void plot_frame(svg::Writer& w, const Box& box, const std::vector<svg::Attr>& extra) {
  std::vector<svg::Attr> attrs = {{"class", "plot-area"},
                                  {"x", svg::coord(box.left)},
                                  {"y", svg::coord(box.top)},
                                  {"width", svg::coord(box.width())},
                                  {"height", svg::coord(box.height())},
                                  {"fill", "none"},
                                  {"stroke", std::string(palette::kInk)},
                                  {"stroke-width", "1"}};
  attrs.insert(attrs.end(), extra.begin(), extra.end());
  w.leaf("rect", attrs);
}

void y_axis(svg::Writer& w, const Box& box, const LinearScale& scale,
            const std::vector<double>& ticks, const std::vector<std::string>& labels,
            std::string_view title, double title_x) {
  w.open("g", {{"class", "axis y-axis"}});
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    const double y = scale(ticks[i]);
    if (y < box.top - 0.5 || y > box.bottom + 0.5) continue;
    w.leaf("line", {{"x1", svg::coord(box.left)},
                    {"y1", svg::coord(y)},
                    {"x2", svg::coord(box.right)},
                    {"y2", svg::coord(y)},
                    {"stroke", std::string(palette::kGrid)},
                    {"stroke-width", "1"}});
    w.leaf("line", {{"x1", svg::coord(box.left - 4)},
                    {"y1", svg::coord(y)},
                    {"x2", svg::coord(box.left)},
                    {"y2", svg::coord(y)},
                    {"stroke", std::string(palette::kInk)},
                    {"stroke-width", "1"}});
    if (i < labels.size()) {
      w.text("text",
             {{"class", "tick-label"},
              {"x", svg::coord(box.left - 7)},
              {"y", svg::coord(y + 4)},
              {"text-anchor", "end"},
              {"fill", std::string(palette::kInk)}},
             labels[i]);
    }
  }
  if (!title.empty()) {
    const std::string x = svg::coord(title_x);
    const std::string y = svg::coord(box.centre_y());
    w.text("text",
           {{"class", "axis-title"},
            {"x", x},
            {"y", y},
            {"text-anchor", "middle"},
            {"transform", "rotate(-90 " + x + " " + y + ")"},
            {"fill", std::string(palette::kInk)}},
           fit_text(title, box.height(), kFontPx));
  }
  w.close("g");
}

double x_axis(svg::Writer& w, const Box& box, const LinearScale& scale,
              const std::vector<double>& ticks, const std::vector<std::string>& labels,
              std::string_view title) {
  w.open("g", {{"class", "axis x-axis"}});
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    const double x = scale(ticks[i]);
    if (x < box.left - 0.5 || x > box.right + 0.5) continue;
    w.leaf("line", {{"x1", svg::coord(x)},
                    {"y1", svg::coord(box.top)},
                    {"x2", svg::coord(x)},
                    {"y2", svg::coord(box.bottom)},
                    {"stroke", std::string(palette::kGrid)},
                    {"stroke-width", "1"}});
    w.leaf("line", {{"x1", svg::coord(x)},
                    {"y1", svg::coord(box.bottom)},
                    {"x2", svg::coord(x)},
                    {"y2", svg::coord(box.bottom + 4)},
                    {"stroke", std::string(palette::kInk)},
                    {"stroke-width", "1"}});
    if (i < labels.size()) {
      w.text("text",
             {{"class", "tick-label"},
              {"x", svg::coord(x)},
              {"y", svg::coord(box.bottom + 17)},
              {"text-anchor", "middle"},
              {"fill", std::string(palette::kInk)}},
             labels[i]);
    }
  }
  double below = box.bottom + 22;
  if (!title.empty()) {
    w.text("text",
           {{"class", "axis-title"},
            {"x", svg::coord(box.centre_x())},
            {"y", svg::coord(box.bottom + 36)},
            {"text-anchor", "middle"},
            {"fill", std::string(palette::kInk)}},
           fit_text(title, box.width(), kFontPx));
    below = box.bottom + 40;
  }
  w.close("g");
  return below;
}

void no_data(svg::Writer& w, const Box& box) {
  w.text("text",
         {{"class", "no-data"},
          {"x", svg::coord(box.centre_x())},
          {"y", svg::coord(box.centre_y() + 5)},
          {"text-anchor", "middle"},
          {"font-size", "14"},
          {"fill", std::string(palette::kGrey)}},
         "no data");
}

std::string close_empty_chart(svg::Writer& w, const Box& box,
                              const std::vector<svg::Attr>& frame_extra) {
  plot_frame(w, box, frame_extra);
  no_data(w, box);
  return close_chart(w);
}

void styled_path(svg::Writer& w, std::string_view cls, const svg::Path& path,
                 const LineStyle& style) {
  auto attrs = line_attrs(style);
  attrs.insert(attrs.begin(), {{"class", std::string(cls)}, {"d", path.str()}});
  w.leaf("path", attrs);
}

void horizontal_line(svg::Writer& w, const Box& box, double y, const LineStyle& style,
                     std::string_view cls, double value) {
  auto attrs = line_attrs(style);
  attrs.insert(attrs.begin(), {{"class", std::string(cls)},
                               {"x1", svg::coord(box.left)},
                               {"y1", svg::coord(y)},
                               {"x2", svg::coord(box.right)},
                               {"y2", svg::coord(y)},
                               {"data-value", svg::exact(value)}});
  w.leaf("line", attrs);
}

double edge_labels_width(const std::vector<EdgeLabel>& labels) {
  double wmax = 0;
  for (const EdgeLabel& l : labels) wmax = std::max(wmax, text_width(l.text, kSmallFontPx));
  return labels.empty() ? 0 : wmax + 8;
}

void edge_labels(svg::Writer& w, std::vector<EdgeLabel> labels, double x, double top,
                 double bottom) {
  if (labels.empty()) return;
  constexpr double kLine = 13;
  std::stable_sort(labels.begin(), labels.end(),
                   [](const EdgeLabel& a, const EdgeLabel& b) { return a.y < b.y; });
  // Push down what overlaps the label above, then up what runs past the bottom.
  for (std::size_t i = 0; i < labels.size(); ++i) {
    labels[i].y = std::max(labels[i].y, top + kLine / 2);
    if (i > 0) labels[i].y = std::max(labels[i].y, labels[i - 1].y + kLine);
  }
  for (std::size_t i = labels.size(); i-- > 0;) {
    const double limit = i + 1 < labels.size() ? labels[i + 1].y - kLine : bottom - kLine / 2;
    labels[i].y = std::min(labels[i].y, limit);
  }
  w.open("g", {{"class", "edge-labels"}});
  for (const EdgeLabel& l : labels) {
    w.text("text",
           {{"x", svg::coord(x)},
            {"y", svg::coord(l.y + 4)},
            {"font-size", svg::fixed(kSmallFontPx, 0)},
            {"fill", std::string(l.colour)}},
           l.text);
  }
  w.close("g");
}

std::vector<svg::Attr> halo_text_attrs(double x, double y, std::string_view anchor,
                                       double font_px) {
  return {{"x", svg::coord(x)},
          {"y", svg::coord(y)},
          {"text-anchor", std::string(anchor)},
          {"font-size", svg::fixed(font_px, 0)},
          {"fill", std::string(palette::kInk)},
          {"stroke", "#ffffff"},
          {"stroke-width", "3"},
          {"stroke-linejoin", "round"},
          {"paint-order", "stroke"}};
}

std::vector<std::string> tick_labels(const std::vector<double>& ticks, const TickStep& step) {
  std::vector<std::string> out;
  out.reserve(ticks.size());
  for (const double t : ticks) out.push_back(tick_label(t, step));
  return out;
}

double widest(const std::vector<std::string>& labels, double font_px) {
  double wmax = 0;
  for (const std::string& l : labels) wmax = std::max(wmax, text_width(l, font_px));
  return wmax;
}

std::string axis_title(std::string_view name, std::string_view unit) {
  if (unit.empty()) return std::string(name);
  if (name.empty()) return "(" + std::string(unit) + ")";
  return std::string(name) + " (" + std::string(unit) + ")";
}

std::string display_value(double display, int decimals, std::string_view unit) {
  std::string s = svg::typographic_minus(svg::fixed(display, decimals));
  if (!unit.empty()) s += " " + std::string(unit);
  return s;
}

}  // namespace ncqual::charts::detail

namespace ncqual::charts::detail {

NiceAxis padded_axis(double lo, double hi, int target_intervals) {
  const double pad = (hi - lo) * 0.04;
  return nice_axis(lo - pad, hi + pad, target_intervals);
}

int y_intervals(double plot_height) {
  return std::clamp(static_cast<int>(std::lround(plot_height / 45)), 2, 10);
}

LeftEdge left_edge(const std::vector<std::string>& labels, bool y_title) {
  LeftEdge e;
  e.title_x = 19;
  const double start = y_title ? 26 : 8;
  e.plot_left = std::round(start + widest(labels) + 11);
  return e;
}

NiceAxis fitting_x_axis(double lo, double hi, double width, int max_intervals) {
  NiceAxis axis = nice_axis(lo, hi, 1);
  for (int n = max_intervals; n >= 1; --n) {
    axis = nice_axis(lo, hi, n);
    const auto labels = tick_labels(axis.ticks, axis.step);
    const double spacing =
        axis.ticks.size() > 1 ? width / static_cast<double>(axis.ticks.size() - 1) : width;
    if (widest(labels) + 14 <= spacing) return axis;
  }
  return axis;
}

}  // namespace ncqual::charts::detail
