// SPDX-License-Identifier: Apache-2.0
#include "ncqual/charts/polar.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "frame.hpp"

namespace ncqual::charts {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::array<LineStyle, 3> kTraceStyles = {
    {{palette::kAccent, 1.8, ""}, {palette::kInk, 1.6, "7 3"}, {palette::kGrey, 1.4, "1.5 2.5"}}};
constexpr double kCaptionPx = 22;
constexpr double kAngleLabelRoom = 34;

const LineStyle& trace_style(std::size_t i) {
  return kTraceStyles[std::min(i, kTraceStyles.size() - 1)];
}

std::vector<LegendItem> legend_of(const PolarChart& c) {
  std::vector<LegendItem> legend;
  for (std::size_t i = 0; i < c.traces.size(); ++i) {
    legend.push_back(detail::line_item(
        c.traces[i].label.empty() ? "trace " + std::to_string(i + 1) : c.traces[i].label,
        trace_style(i)));
  }
  legend.push_back(detail::line_item("reference circle", {palette::kGrey, 1.6, ""}));
  return legend;
}

// The finite samples of a trace, by angle in [0, 2π).
std::vector<PolarSample> usable_samples(const PolarTrace& t, std::size_t* skipped) {
  std::vector<PolarSample> out;
  for (const PolarSample& s : t.samples) {
    if (!std::isfinite(s.angle_rad) || !std::isfinite(s.deviation)) {
      ++*skipped;
      continue;
    }
    double a = std::fmod(s.angle_rad, 2 * kPi);
    if (a < 0) a += 2 * kPi;
    out.push_back({a, s.deviation});
  }
  std::stable_sort(out.begin(), out.end(), [](const PolarSample& a, const PolarSample& b) {
    return a.angle_rad < b.angle_rad;
  });
  return out;
}

double largest_deviation(const PolarChart& c) {
  double m = 0;
  std::size_t ignored = 0;
  for (const PolarTrace& t : c.traces) {
    for (const PolarSample& s : usable_samples(t, &ignored)) m = std::max(m, std::abs(s.deviation));
  }
  return m * std::abs(detail::display_scale(c.unit));
}

}  // namespace

PolarGeometry polar_geometry(const PolarChart& c) {
  const Size size = detail::resolve_size(c.size, kPolarSize);
  const double title_bottom = c.title.empty() ? 8 : 28;
  const double top =
      title_bottom + detail::legend_rows(legend_of(c), size.width - 16) * detail::kLegendRowPx + 6;
  const double bottom = size.height - kCaptionPx - 4;
  PolarGeometry g;
  g.cx = size.width / 2;
  g.cy = (top + bottom) / 2;
  g.outer_px = std::max(20.0, std::min(size.width / 2 - kAngleLabelRoom - 8,
                                       (bottom - top) / 2 - kAngleLabelRoom / 2 - 4));
  g.reference_px = 0.6 * g.outer_px;
  const double largest = largest_deviation(c);
  if (c.ring_step && std::isfinite(*c.ring_step) && *c.ring_step > 0) {
    g.ring_step = *c.ring_step;
  } else {
    g.ring_step = largest > 0 ? nice_step(largest / 3).value() : 1;
  }
  g.rings = static_cast<int>(std::clamp(std::ceil(largest / g.ring_step - 1e-9), 1.0, 50.0));
  g.px_per_unit = (g.outer_px - g.reference_px) / (g.rings * g.ring_step);
  return g;
}

std::string polar_chart(const PolarChart& c) {
  const Size size = detail::resolve_size(c.size, kPolarSize);
  const double scale = detail::display_scale(c.unit);
  const PolarGeometry g = polar_geometry(c);

  std::size_t skipped = 0;
  std::vector<std::vector<PolarSample>> traces;
  std::size_t points = 0;
  for (const PolarTrace& t : c.traces) {
    traces.push_back(usable_samples(t, &skipped));
    points += traces.back().size();
  }
  const TickStep ring_tick = nice_step(g.ring_step);
  const int decimals = std::max(ring_tick.decimals(), nice_step(g.ring_step / 10).decimals());

  std::string desc = "Polar plot of a circular test in the " + c.u_name + c.v_name + " plane: ";
  for (std::size_t i = 0; i < traces.size(); ++i) {
    if (i > 0) desc += "; ";
    desc += (c.traces[i].label.empty() ? "trace " + std::to_string(i + 1) : c.traces[i].label) +
            " " + detail::count_phrase(traces[i].size(), "point", "points");
    if (!traces[i].empty()) {
      const auto [lo, hi] = std::minmax_element(
          traces[i].begin(), traces[i].end(),
          [](const PolarSample& a, const PolarSample& b) { return a.deviation < b.deviation; });
      desc += ", radial deviation " + detail::display_value(lo->deviation * scale, decimals, "") +
              " to " + detail::display_value(hi->deviation * scale, decimals, c.unit.unit);
    }
  }
  if (traces.empty()) desc += "no trace";
  desc += ". Deviations drawn magnified around the reference circle, " +
          detail::display_value(g.ring_step, ring_tick.decimals(), c.unit.unit) +
          " per ring; angles counter-clockwise from +" + c.u_name + ".";

  const detail::Tally tally{points, skipped, std::nullopt, "non-finite sample",
                            "non-finite samples"};
  svg::Writer w;
  detail::open_chart(w,
                     {kind::kPolar,
                      c.title,
                      desc,
                      c.description,
                      size,
                      tally,
                      {{"data-ring-step", svg::exact(g.ring_step)}}},
                     legend_of(c));

  auto at = [&](double angle, double r) {
    return std::pair<double, double>{g.cx + r * std::cos(angle), g.cy - r * std::sin(angle)};
  };

  // Spokes every 30° and their angle labels.
  w.open("g", {{"class", "grid"}});
  const double inner = g.reference_px - g.rings * g.ring_step * g.px_per_unit;
  for (int deg = 0; deg < 360; deg += 30) {
    const double a = deg * kPi / 180;
    const auto [x0, y0] = at(a, inner);
    const auto [x1, y1] = at(a, g.outer_px);
    w.leaf("line", {{"x1", svg::coord(x0)},
                    {"y1", svg::coord(y0)},
                    {"x2", svg::coord(x1)},
                    {"y2", svg::coord(y1)},
                    {"stroke", std::string(palette::kGrid)},
                    {"stroke-width", "1"}});
    const auto [lx, ly] = at(a, g.outer_px + 8);
    const double ca = std::cos(a);
    const std::string anchor = ca > 0.3 ? "start" : ca < -0.3 ? "end" : "middle";
    const double sa = std::sin(a);
    const double dy = sa > 0.3 ? 0 : sa < -0.3 ? 10 : 4;
    const std::string label = std::to_string(deg) + "°";
    w.text("text",
           {{"class", "angle-label"},
            {"x", svg::coord(lx)},
            {"y", svg::coord(ly + dy)},
            {"text-anchor", anchor},
            {"fill", std::string(palette::kInk)}},
           detail::fit_text(label, kAngleLabelRoom + 6, detail::kFontPx));
  }
  w.close("g");

  // Rings: the reference circle solid, the others dashed; their values up the 90° spoke.
  w.open("g", {{"class", "rings"}});
  const int label_every = g.rings > 4 ? (g.rings + 3) / 4 : 1;
  std::vector<std::pair<double, std::string>> ring_labels;
  for (int i = -g.rings; i <= g.rings; ++i) {
    const double value = i * g.ring_step;
    const double r = g.reference_px + value * g.px_per_unit;
    const bool reference = i == 0;
    w.leaf("circle", {{"class", reference ? "ring reference" : "ring"},
                      {"cx", svg::coord(g.cx)},
                      {"cy", svg::coord(g.cy)},
                      {"r", svg::coord(r)},
                      {"fill", "none"},
                      {"stroke", std::string(reference ? palette::kGrey : palette::kLightGrey)},
                      {"stroke-width", reference ? "1.6" : "0.8"},
                      {"stroke-dasharray", reference ? "" : "3 3"},
                      {"data-value", svg::exact(value)}});
    if (i % label_every == 0) {
      std::string text = detail::display_value(value, ring_tick.decimals(), "");
      if (value > 0) text = "+" + text;
      ring_labels.emplace_back(r, text);
    }
  }
  w.close("g");

  // The traces.
  for (std::size_t i = 0; i < traces.size(); ++i) {
    const auto& s = traces[i];
    if (s.empty()) continue;
    // Start after the largest gap; close the path unless that gap is more than 60°.
    std::size_t start = 0;
    double gap = s.front().angle_rad + 2 * kPi - s.back().angle_rad;
    for (std::size_t k = 1; k < s.size(); ++k) {
      const double d = s[k].angle_rad - s[k - 1].angle_rad;
      if (d > gap) {
        gap = d;
        start = k;
      }
    }
    svg::Path p;
    for (std::size_t k = 0; k < s.size(); ++k) {
      const PolarSample& q = s[(start + k) % s.size()];
      const auto [px, py] = at(q.angle_rad, g.reference_px + q.deviation * scale * g.px_per_unit);
      p.vertex(px, py);
    }
    if (gap <= kPi / 3 && s.size() > 2) p.close();
    auto attrs = detail::line_attrs(trace_style(i));
    attrs.insert(attrs.begin(), {{"class", "trace"},
                                 {"d", p.str()},
                                 {"data-trace", c.traces[i].label},
                                 {"data-points", std::to_string(s.size())}});
    attrs.emplace_back("stroke-linejoin", "round");
    w.leaf("path", attrs);
  }

  // Ring values over everything, with a halo.
  w.open("g", {{"class", "ring-labels"}});
  for (const auto& [r, text] : ring_labels) {
    w.text("text", detail::halo_text_attrs(g.cx + 4, g.cy - r + 4, "start", 10), text);
  }
  w.close("g");

  const std::string caption =
      "scale: " + detail::display_value(g.ring_step, ring_tick.decimals(), c.unit.unit) +
      " per ring, reference circle 0, outwards +; 0° = +" + c.u_name + ", 90° = +" + c.v_name;
  w.text("text",
         {{"class", "caption"},
          {"x", svg::coord(size.width / 2)},
          {"y", svg::coord(size.height - 10)},
          {"text-anchor", "middle"},
          {"fill", std::string(palette::kInk)}},
         detail::fit_text(caption, size.width - 16, detail::kFontPx));
  if (points == 0) {
    w.text("text",
           {{"class", "no-data"},
            {"x", svg::coord(g.cx)},
            {"y", svg::coord(g.cy + 5)},
            {"text-anchor", "middle"},
            {"font-size", "14"},
            {"fill", std::string(palette::kGrey)}},
           "no data");
  }
  return detail::close_chart(w);
}

}  // namespace ncqual::charts
