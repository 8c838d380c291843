// SPDX-License-Identifier: Apache-2.0
// ncqual_charts_gallery OUTDIR: every chart of ncqual_charts drawn from sample data, each into
// OUTDIR/<name>.svg, all of them inline in OUTDIR/gallery.html (the page people and the browser
// test look at), and OUTDIR/manifest.tsv: name, data-chart, what the tests expect of it (a comma
// list of "empty": says "no data", "skips": counts skipped non-finite values, "hostile": hostile
// labels; "-" for none), and what the sample shows. The
// samples cover the ordinary case of every chart and the awkward ones: one-sided tolerance
// bands, no data, non-finite values, hostile labels (<&"'>), a partial arc, one direction only.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "ncqual/charts/charts.hpp"

namespace charts = ncqual::charts;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::int64_t kDay = 86'400'000'000'000;
constexpr std::int64_t kHour = 3'600'000'000'000;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// 2026-03-02 00:00 UTC.
constexpr std::int64_t kStart = 1'772'409'600LL * 1'000'000'000;
const std::string kHostile = "<&\"'> ]]> \x01 \xff";  // markup, quotes, a control, a non-UTF-8 byte

const charts::DisplayUnit kMicrons{1000, "µm"};

struct Sample {
  std::string name;
  std::string kind;
  std::string expect;
  std::string note;
  std::string svg;
};

// A trend without points yet: what every trend sample sets first.
charts::TrendChart trend(std::string title, std::string quantity, charts::DisplayUnit unit,
                         charts::ToleranceBand tolerance) {
  charts::TrendChart c;
  c.title = std::move(title);
  c.quantity = std::move(quantity);
  c.unit = std::move(unit);
  c.tolerance = tolerance;
  return c;
}

charts::TrendChart drifting_trend() {
  charts::TrendChart c =
      trend("Monument check 3: centre dx, machine PM1", "centre dx", kMicrons, {-0.010, 0.010});
  for (int i = 0; i < 40; ++i) {
    const double drift = i < 22 ? 0.00018 * i : 0.00018 * (i - 22) - 0.001;
    const double noise = 0.0012 * std::sin(i * 2.3) + 0.0006 * std::cos(i * 5.1);
    charts::TrendPoint p;
    p.time_ns = kStart + i * 3 * kDay + (i % 3) * kHour;
    p.value = drift + noise;
    p.label = "daily-" + std::to_string(1000 + i);
    if (i == 17) p.value = 0.0112;  // out of tolerance: a red diamond whatever `failed` says
    if (i == 30) p.failed = true;   // failed on another metric of the same check
    c.points.push_back(p);
  }
  c.control = charts::ControlLimits{0.0012, -0.0041, 0.0065};
  charts::Forecast f;
  const std::int64_t from = kStart + 22 * 3 * kDay;
  for (int k = 0; k <= 20; ++k) {
    const std::int64_t t = from + k * 10 * kDay;
    const double days = static_cast<double>(t - from) / kDay;
    const double fitted = -0.001 + 0.00006 * days;
    const double half = 0.0022 + 0.00000012 * days * days;
    f.samples.push_back({t, fitted, fitted - half, fitted + half});
  }
  f.crossing_ns = from + static_cast<std::int64_t>(0.011 / 0.00006 * kDay);
  c.forecast = f;
  c.markers = {
      {kStart + 33 * kDay, "spindle replaced", charts::MarkerKind::Intervention},
      {kStart + 66 * kDay - 8 * kHour, "zero offsets re-issued", charts::MarkerKind::Compensation},
      {kStart + 66 * kDay, "crash on B axis", charts::MarkerKind::Intervention}};
  return c;
}

// The drift scenario as the report of issue 37 drew it: 56 daily checks of Y creeping 0.74 µm a
// day, and a compensation every 22 minutes (3,688 in 8 weeks) with an intervention among them:
// grouped into a tenth of the plot's width at most.
charts::TrendChart dense_markers() {
  charts::TrendChart c =
      trend("Drift under 3,688 compensations (grouped)", "center_dy_mm", kMicrons, {-0.025, 0.025});
  for (int d = 0; d < 56; ++d) {
    c.points.push_back({kStart + d * kDay + 6 * kHour, -0.00074 * d + 0.0012 * std::sin(d * 2.3),
                        false, "daily-" + std::to_string(d)});
  }
  for (int i = 0; i < 3688; ++i) {
    c.markers.push_back({kStart + static_cast<std::int64_t>(i) * (56 * kDay / 3688),
                         "compensation work_offset:pm1", charts::MarkerKind::Compensation});
  }
  c.markers.push_back({kStart + 35 * kDay, "intervention iv-7", charts::MarkerKind::Intervention});
  return c;
}

// pm1's grid plane (9 × 6 points, 500 × 300 mm apart) with 10..60 µm deviations and the
// 150 µm tolerance: the automatic magnification (×2000), circles left out.
charts::DeviationVectorPlot pm1_grid_plane() {
  charts::DeviationVectorPlot c;
  c.title = "pm1 grid, plane Z = 600 mm, automatic magnification";
  c.unit = kMicrons;
  c.tolerance = 0.150;
  c.size = {720, 400};
  int k = 0;
  for (int j = 0; j < 6; ++j) {
    for (int i = 0; i < 9; ++i, ++k) {
      const double x = 200.0 + 500 * i;
      const double y = 200.0 + 300 * j;
      // A scale error along X (up to 40 µm), a squareness (up to 15 µm), a little noise.
      c.points.push_back({x, y, 0.00001 * x + 0.004 * std::sin(k),
                          0.00001 * x * 0.3 + 0.003 * std::cos(2.0 * k),
                          "grid:" + std::to_string(k), std::nullopt});
    }
  }
  return c;
}

charts::TrendChart one_sided_upper() {
  charts::TrendChart c = trend("Fixture flatness (upper limit only)", "flatness", kMicrons,
                               {-charts::kNoLimit, 0.015});
  for (int i = 0; i < 12; ++i) {
    c.points.push_back({kStart + i * 7 * kDay, 0.004 + 0.0007 * i + 0.001 * std::sin(i), false,
                        "weekly-" + std::to_string(i)});
  }
  c.points[11].value = 0.0162;
  return c;
}

charts::TrendChart one_sided_lower() {
  // NaN: no upper limit.
  charts::TrendChart c =
      trend("Probe trigger margin (lower limit only), one day", "margin", {1, "mm"}, {0.2, kNaN});
  for (int i = 0; i < 16; ++i) {
    c.points.push_back(
        {kStart + i * kHour + 6 * kHour, 0.6 - 0.02 * i + 0.03 * std::cos(i), false, ""});
  }
  return c;
}

charts::TrendChart empty_trend() {
  return trend("Trend without checks yet", "centre dy", kMicrons, {-0.01, 0.01});
}

charts::TrendChart nan_trend() {
  charts::TrendChart c =
      trend("Trend with non-finite values (skipped)", "centre dz", kMicrons, {-0.008, 0.008});
  const double values[] = {0.001,  kNaN,   0.002, std::numeric_limits<double>::infinity(),
                           -0.003, 0.0015, -kNaN};
  int i = 0;
  for (const double v : values) c.points.push_back({kStart + (i++) * kDay, v, false, ""});
  c.points.push_back({kStart + 10 * kDay, 0.0, false, "single finite after gaps"});
  return c;
}

charts::TrendChart hostile_trend() {
  charts::TrendChart c = one_sided_upper();
  c.title = "Hostile " + kHostile;
  c.description = kHostile;
  c.quantity = kHostile;
  c.unit = {1000, kHostile};
  c.points[2].label = kHostile;
  c.markers = {{kStart + 20 * kDay, kHostile, charts::MarkerKind::Intervention}};
  c.time_label = [](std::int64_t t) { return "<" + charts::utc_date(t) + "&>"; };
  c.time_title = kHostile;
  return c;
}

charts::DeviationVectorPlot grid_plane() {
  charts::DeviationVectorPlot c;
  c.title = "Monthly grid, plane Z = 250 mm";
  c.unit = kMicrons;
  c.tolerance = 0.010;
  c.magnification = 10000;
  int n = 1;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 5; ++i) {
      const double x = -400 + 200 * i;
      const double y = -300 + 200 * j;
      charts::PlaneDeviation p;
      p.x = x;
      p.y = y;
      // A scale error in X, a squareness error, and a local bump.
      p.dx = 0.000012 * x + 0.000004 * y;
      p.dy = -0.000006 * y + 0.0015 * std::sin(i + j);
      p.label = "P" + std::to_string(n++);
      c.points.push_back(p);
    }
  }
  c.points[4].dx = 0.0105;  // (400, -300): out of tolerance
  c.points[4].dy = 0.0042;
  c.points[13].out_of_tolerance = true;  // judged out in 3D by the caller
  return c;
}

charts::DeviationVectorPlot grid_auto_nan() {
  charts::DeviationVectorPlot c = grid_plane();
  c.title = "Grid, plane Z = 50 mm, automatic magnification, one point NaN";
  c.magnification.reset();
  c.points[7].dx = kNaN;
  return c;
}

charts::DeviationVectorPlot grid_empty() {
  charts::DeviationVectorPlot c = grid_plane();
  c.title = "Grid plane without points";
  c.magnification.reset();
  c.points.clear();
  return c;
}

charts::PointDeviationChart point_deviation() {
  charts::PointDeviationChart c;
  c.title = "Z deviation by point number, plane Z = 250 mm";
  c.quantity = "Z deviation";
  c.unit = kMicrons;
  c.tolerance = {-0.015, 0.015};
  for (int i = 1; i <= 24; ++i) {
    c.points.push_back({i, 0.006 * std::sin(i * 0.7) + 0.0003 * i, "P" + std::to_string(i)});
  }
  c.points[18].value = 0.0171;
  c.points[5].value = kNaN;
  return c;
}

charts::PositioningChart positioning(bool both) {
  charts::PositioningChart c;
  c.title = both ? "ISO 230-2 positioning, X axis (5 runs)" : "ISO 230-2, Y axis, ↑ only";
  c.axis_name = both ? "X" : "Y";
  c.unit = kMicrons;
  for (int i = 0; i <= 10; ++i) {
    const double pos = i * 100.0 + (i % 3) * 3.7;
    const double pitch = 0.0018 * std::sin(pos / 60);
    charts::PositioningTarget t;
    t.position = pos;
    t.up = charts::DirectionStats{0.0000045 * pos + pitch + 0.0015, 0.0004 + 0.00003 * i};
    if (both) t.down = charts::DirectionStats{0.0000045 * pos + pitch - 0.0015, 0.0005};
    c.targets.push_back(t);
  }
  return c;
}

charts::PolarChart polar(bool arc) {
  charts::PolarChart c;
  c.title = arc ? "Circular test, YZ plane, 180° arc"
                : "Circular test, XY plane, R 150 mm, F 1000 mm/min";
  c.unit = kMicrons;
  if (arc) {
    c.u_name = "Y";
    c.v_name = "Z";
  }
  for (const bool ccw : {true, false}) {
    if (arc && !ccw) continue;
    charts::PolarTrace t;
    t.label = ccw ? "CCW" : "CW";
    const int n = 360;
    for (int k = 0; k < n; ++k) {
      const double a = (arc ? kPi : 2 * kPi) * k / n;
      // An ellipse (scale mismatch), a squareness term, reversal spikes at the quadrants.
      double d = 0.004 * std::cos(2 * a) + 0.0025 * std::sin(2 * a) + (ccw ? 0.0008 : -0.0008);
      for (int q = 0; q < 4; ++q) {
        const double off = std::remainder(a - q * kPi / 2, 2 * kPi);
        d += 0.005 * std::exp(-off * off * 400) * (ccw ? 1 : -1) * (off > 0 ? 1 : 0);
      }
      t.samples.push_back({a, d});
    }
    c.traces.push_back(t);
  }
  return c;
}

charts::BudgetChart budget(bool over) {
  charts::BudgetChart c;
  c.title = over ? "Error budget today: over the allowance" : "Error budget at the tool tip (RSS)";
  c.unit = kMicrons;
  c.allowance = 0.020;
  c.contributions = {{"X scale", 0.0062},         {"Y scale", 0.0048},
                     {"squareness XY", 0.0071},   {"C axis zero", 0.0039},
                     {"probe (stylus)", 0.0021},  {"fixture pre-calibration", 0.0085},
                     {"thermal growth Z", 0.0102}};
  if (over) c.contributions[6].value = 0.0213;
  double sum = 0;
  for (const auto& b : c.contributions) sum += b.value * b.value;
  c.total = charts::BudgetBar{"total (RSS)", std::sqrt(sum)};
  return c;
}

charts::BudgetChart budget_empty() {
  charts::BudgetChart c;
  c.title = "Error budget with only a non-finite contribution";
  c.unit = kMicrons;
  c.allowance = 0.02;
  c.contributions = {{"unknown", kNaN}};
  return c;
}

std::vector<Sample> samples() {
  using charts::kind::kBudget, charts::kind::kDeviationVectors, charts::kind::kPointDeviation,
      charts::kind::kPolar, charts::kind::kPositioning, charts::kind::kTrend;
  std::vector<Sample> s;
  auto add = [&](std::string name, std::string_view kind, std::string note, std::string svg) {
    // What the tests check of it, from the sample's name.
    std::string expect;
    auto flag = [&](bool on, std::string_view what) {
      if (!on) return;
      if (!expect.empty()) expect += ",";
      expect += what;
    };
    flag(name.find("empty") != std::string::npos, "empty");
    flag(name.find("nan") != std::string::npos || name == "point-deviation" ||
             name == "budget-empty",
         "skips");
    flag(name.rfind("hostile", 0) == 0, "hostile");
    if (expect.empty()) expect = "-";
    s.push_back({std::move(name), std::string(kind), expect, std::move(note), std::move(svg)});
  };
  add("trend", kTrend, "drift, control limits, forecast with crossing, interventions",
      charts::trend_chart(drifting_trend()));
  add("trend-upper-only", kTrend, "one-sided band (upper)", charts::trend_chart(one_sided_upper()));
  add("trend-lower-only", kTrend, "one-sided band (lower; the upper limit NaN), hours",
      charts::trend_chart(one_sided_lower()));
  add("trend-empty", kTrend, "no data", charts::trend_chart(empty_trend()));
  add("trend-dense-markers", kTrend, "3,688 compensations grouped, the drift visible",
      charts::trend_chart(dense_markers()));
  add("trend-nan", kTrend, "non-finite values", charts::trend_chart(nan_trend()));
  add("vectors", kDeviationVectors, "grid plane, magnification 10000",
      charts::deviation_vector_plot(grid_plane()));
  add("vectors-auto-nan", kDeviationVectors, "automatic magnification, a NaN point",
      charts::deviation_vector_plot(grid_auto_nan()));
  add("vectors-empty", kDeviationVectors, "no data", charts::deviation_vector_plot(grid_empty()));
  add("vectors-pm1", kDeviationVectors, "pm1's 4.2 m grid, 10-60 µm, automatic ×2000",
      charts::deviation_vector_plot(pm1_grid_plane()));
  add("point-deviation", kPointDeviation, "Z deviation by point, a NaN",
      charts::point_deviation_chart(point_deviation()));
  add("positioning", kPositioning, "bidirectional", charts::positioning_chart(positioning(true)));
  add("positioning-up-only", kPositioning, "one direction",
      charts::positioning_chart(positioning(false)));
  add("polar", kPolar, "CCW and CW", charts::polar_chart(polar(false)));
  add("polar-arc", kPolar, "partial arc", charts::polar_chart(polar(true)));
  add("budget", kBudget, "within the allowance", charts::budget_chart(budget(false)));
  add("budget-over", kBudget, "over the allowance", charts::budget_chart(budget(true)));
  add("budget-empty", kBudget, "non-finite only", charts::budget_chart(budget_empty()));

  // Hostile labels in every chart.
  add("hostile-trend", kTrend, "hostile labels", charts::trend_chart(hostile_trend()));
  {
    auto c = grid_plane();
    c.title = kHostile;
    c.description = kHostile;
    c.x_name = kHostile;
    c.unit.unit = kHostile;
    c.points[0].label = kHostile;
    add("hostile-vectors", kDeviationVectors, "hostile labels", charts::deviation_vector_plot(c));
  }
  {
    auto c = point_deviation();
    c.title = kHostile;
    c.quantity = kHostile;
    c.number_title = kHostile;
    c.points[0].label = kHostile;
    add("hostile-point-deviation", kPointDeviation, "hostile labels",
        charts::point_deviation_chart(c));
  }
  {
    auto c = positioning(true);
    c.title = kHostile;
    c.axis_name = kHostile;
    c.position_unit = kHostile;
    add("hostile-positioning", kPositioning, "hostile labels", charts::positioning_chart(c));
  }
  {
    auto c = polar(false);
    c.title = kHostile;
    c.traces[0].label = kHostile;
    c.u_name = kHostile;
    add("hostile-polar", kPolar, "hostile labels", charts::polar_chart(c));
  }
  {
    auto c = budget(true);
    c.title = kHostile;
    c.contributions[0].label = kHostile;
    c.allowance_label = kHostile;
    c.total->label = kHostile;
    add("hostile-budget", kBudget, "hostile labels", charts::budget_chart(c));
  }
  return s;
}

bool write(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) {
    std::cerr << "ncqual_charts_gallery: cannot write " << path << "\n";
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: ncqual_charts_gallery OUTDIR\n";
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    std::cerr << "ncqual_charts_gallery: cannot create " << dir << ": " << ec.message() << "\n";
    return 1;
  }
  const auto all = samples();
  std::string html =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      "<title>ncqual charts gallery</title>\n<style>\n"
      "body { font-family: DejaVu Sans, Verdana, Arial, sans-serif; margin: 16px; color: #000; "
      "background: #fff; }\n"
      "main { display: flex; flex-wrap: wrap; gap: 16px; align-items: flex-start; }\n"
      "figure { margin: 0; border: 1px solid #ccc; padding: 4px; break-inside: avoid; }\n"
      "figcaption { font-size: 12px; color: #444; padding: 2px 4px; }\n"
      "svg { display: block; max-width: 100%; height: auto; }\n"
      "</style>\n</head>\n<body>\n<h1>ncqual charts gallery</h1>\n<main>\n";
  std::string manifest;
  for (const Sample& s : all) {
    if (!write(dir / (s.name + ".svg"), "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" + s.svg)) {
      return 1;
    }
    html += "<figure id=\"" + s.name + "\">\n" + s.svg + "<figcaption>" + s.name + ".svg — " +
            charts::svg::escape(s.note) + "</figcaption>\n</figure>\n";
    manifest += s.name + "\t" + s.kind + "\t" + s.expect + "\t" + s.note + "\n";
  }
  html += "</main>\n</body>\n</html>\n";
  if (!write(dir / "gallery.html", html) || !write(dir / "manifest.tsv", manifest)) return 1;
  std::cout << "wrote " << all.size() << " charts and gallery.html to " << dir.string() << "\n";
  return 0;
}
