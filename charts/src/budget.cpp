// SPDX-License-Identifier: Apache-2.0
#include "ncqual/charts/budget.hpp"

#include <algorithm>
#include <cmath>

#include "frame.hpp"

namespace ncqual::charts {
namespace {

constexpr std::string_view kContributionFill = "#9a9a9a";
constexpr std::string_view kTotalFill = palette::kInk;
constexpr LineStyle kAllowanceLine{palette::kRed, 2, "6 3"};

}  // namespace

std::string budget_chart(const BudgetChart& c) {
  const Size size = detail::resolve_size(c.size, kBudgetSize);
  const double scale = detail::display_scale(c.unit);
  const bool has_allowance = std::isfinite(c.allowance);

  struct Bar {
    const BudgetBar* bar;
    bool total;
  };
  std::vector<Bar> bars;
  std::size_t skipped = 0;
  for (const BudgetBar& b : c.contributions) {
    if (std::isfinite(b.value)) {
      bars.push_back({&b, false});
    } else {
      ++skipped;
    }
  }
  if (c.total) {
    if (std::isfinite(c.total->value)) {
      bars.push_back({&*c.total, true});
    } else {
      ++skipped;
    }
  }
  auto over = [&](double v) { return has_allowance && v > c.allowance; };
  const bool any_over =
      std::any_of(bars.begin(), bars.end(), [&](const Bar& b) { return over(b.bar->value); });
  const bool has_total = !bars.empty() && bars.back().total;

  double shown_max = 0;
  for (const Bar& b : bars) shown_max = std::max(shown_max, std::abs(b.bar->value * scale));
  const int decimals = shown_max > 0 ? std::max(0, nice_step(shown_max / 100).decimals()) : 1;
  auto dv = [&](double v) { return detail::display_value(v * scale, decimals, c.unit.unit); };

  std::string desc = "Error budget: " + detail::count_phrase(bars.size() - (has_total ? 1 : 0),
                                                             "contribution", "contributions");
  if (!bars.empty()) {
    const auto largest =
        std::max_element(bars.begin(), bars.end() - (has_total ? 1 : 0),
                         [](const Bar& a, const Bar& b) { return a.bar->value < b.bar->value; });
    if (largest != bars.end() - (has_total ? 1 : 0)) {
      desc += ", the largest " + largest->bar->label + " at " + dv(largest->bar->value);
    }
  }
  if (has_total) desc += "; " + bars.back().bar->label + " " + dv(bars.back().bar->value);
  if (has_allowance) {
    desc += "; " + c.allowance_label + " " + dv(c.allowance);
    if (has_total) desc += over(bars.back().bar->value) ? " (exceeded)" : " (within)";
  }
  desc += ".";

  std::vector<LegendItem> legend;
  if (!bars.empty()) {
    legend.push_back(detail::area_item("contribution", kContributionFill));
    if (has_total) legend.push_back(detail::area_item("total", kTotalFill));
    if (any_over) legend.push_back(detail::area_item("over the allowance", palette::kRed));
    if (has_allowance) legend.push_back(detail::line_item(c.allowance_label, kAllowanceLine));
  }
  svg::Writer w;
  const double top = detail::open_chart(
      w, {kind::kBudget, c.title, desc, c.description, size, {bars.size(), skipped}, {}}, legend);

  Box box;
  box.top = top + (has_allowance ? 16 : 0);
  box.bottom = detail::plot_bottom(size.height, true);
  std::vector<std::string> labels;
  labels.reserve(bars.size());
  for (const Bar& b : bars) labels.push_back(b.bar->label);
  const double label_room = std::min(detail::widest(labels), size.width * 0.35);
  box.left = std::round(8 + label_room + 10);
  box.right = size.width - 16;

  double lo = 0, hi = 0;
  for (const Bar& b : bars) {
    lo = std::min(lo, b.bar->value * scale);
    hi = std::max(hi, b.bar->value * scale);
  }
  if (has_allowance) hi = std::max(hi, c.allowance * scale);
  // Room right of the longest bar for its value.
  const double value_room = 8 + detail::text_width(dv(hi / scale), detail::kFontPx);
  const double frac = std::clamp(value_room / std::max(box.width(), 1.0), 0.0, 0.4);
  hi += (hi - lo) * frac / (1 - frac);
  const NiceAxis x_axis = detail::fitting_x_axis(lo, hi, box.width(), 10);
  const LinearScale x(x_axis.lo, x_axis.hi, box.left, box.right);

  if (bars.empty()) return detail::close_empty_chart(w, box);
  detail::x_axis(w, box, x, x_axis.ticks, detail::tick_labels(x_axis.ticks, x_axis.step),
                 detail::axis_title(c.quantity, c.unit.unit));

  const double row = box.height() / static_cast<double>(bars.size());
  const double bar_h = std::min(22.0, row * 0.68);
  const double x0 = x(0);
  w.open("g", {{"class", "bars"}});
  for (std::size_t i = 0; i < bars.size(); ++i) {
    const Bar& b = bars[i];
    const double cy = box.top + row * (static_cast<double>(i) + 0.5);
    if (b.total && i > 0) {
      const double ry = box.top + row * static_cast<double>(i);
      w.leaf("line", {{"class", "total-rule"},
                      {"x1", svg::coord(8)},
                      {"y1", svg::coord(ry)},
                      {"x2", svg::coord(box.right)},
                      {"y2", svg::coord(ry)},
                      {"stroke", std::string(palette::kInk)},
                      {"stroke-width", "1"}});
    }
    const double xv = x(b.bar->value * scale);
    const bool is_over = over(b.bar->value);
    const std::string_view fill = is_over   ? palette::kRed
                                  : b.total ? kTotalFill
                                            : kContributionFill;
    std::string cls = b.total ? "bar total" : "bar contribution";
    if (is_over) cls += " over";
    w.open("rect", {{"class", cls},
                    {"x", svg::coord(std::min(x0, xv))},
                    {"y", svg::coord(cy - bar_h / 2)},
                    {"width", svg::coord(std::abs(xv - x0))},
                    {"height", svg::coord(bar_h)},
                    {"fill", std::string(fill)},
                    {"stroke", b.total ? std::string(palette::kInk) : ""},
                    {"stroke-width", b.total ? "1.5" : ""},
                    {"data-label", b.bar->label},
                    {"data-value", svg::exact(b.bar->value)}});
    w.text("title", {},
           b.bar->label + ": " + dv(b.bar->value) + (is_over ? " (over the allowance)" : ""));
    w.close("rect");
    w.text("text",
           {{"class", b.total ? "bar-label total" : "bar-label"},
            {"x", svg::coord(box.left - 8)},
            {"y", svg::coord(cy + 4)},
            {"text-anchor", "end"},
            {"font-weight", b.total ? "bold" : ""},
            {"fill", std::string(palette::kInk)}},
           detail::fit_text(b.bar->label, label_room, detail::kFontPx * (b.total ? 1.08 : 1)));
    const std::string value_text = dv(b.bar->value);
    const bool negative = xv < x0;
    w.text("text",
           detail::halo_text_attrs(negative ? xv - 5 : xv + 5, cy + 4, negative ? "end" : "start",
                                   detail::kFontPx),
           value_text);
  }
  w.close("g");
  detail::plot_frame(
      w, box, {{"data-x-min", svg::exact(x_axis.lo)}, {"data-x-max", svg::exact(x_axis.hi)}});
  if (has_allowance) {
    const double xa = x(c.allowance * scale);
    auto attrs = detail::line_attrs(kAllowanceLine);
    attrs.insert(attrs.begin(), {{"class", "allowance"},
                                 {"x1", svg::coord(xa)},
                                 {"y1", svg::coord(box.top - 4)},
                                 {"x2", svg::coord(xa)},
                                 {"y2", svg::coord(box.bottom)},
                                 {"data-value", svg::exact(c.allowance)}});
    w.leaf("line", attrs);
    const std::string text = detail::fit_text(c.allowance_label + " " + dv(c.allowance),
                                              size.width - 16, detail::kFontPx);
    const double tw = detail::text_width(text, detail::kFontPx);
    // Centred on the line, kept within the chart.
    const double tx = std::max(8 + tw / 2, std::min(xa, size.width - 8 - tw / 2));
    w.text("text",
           {{"class", "allowance-label"},
            {"x", svg::coord(tx)},
            {"y", svg::coord(box.top - 7)},
            {"text-anchor", "middle"},
            {"fill", std::string(palette::kRed)}},
           text);
  }
  return detail::close_chart(w);
}

}  // namespace ncqual::charts
