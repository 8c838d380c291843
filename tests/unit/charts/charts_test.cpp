// SPDX-License-Identifier: Apache-2.0
// The charts: geometry worked out by hand from the layout and the data, what every chart's root
// carries, determinism, escaping, and the empty and non-finite cases.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "ncqual/charts/charts.hpp"
#include "svg_probe.hpp"

namespace charts = ncqual::charts;
using charts::test::Element;
using charts::test::elements;
using charts::test::only;
using charts::test::path_numbers;
using charts::test::with_class;

namespace {

constexpr std::int64_t kDay = 86'400'000'000'000;
constexpr std::int64_t kT0 = 20514 * kDay;  // 2026-03-02 00:00 UTC
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const charts::DisplayUnit kMicrons{1000, "µm"};

charts::TrendChart three_checks() {
  charts::TrendChart c;
  c.title = "T";
  c.quantity = "dx";
  c.unit = kMicrons;
  c.tolerance = {-0.010, 0.010};
  c.points = {{kT0, -0.004, false, "a"},
              {kT0 + kDay, 0.006, false, "b"},
              {kT0 + 2 * kDay, 0.010, false, "c"}};
  return c;
}

// ---- Trend ------------------------------------------------------------------------------------

TEST(Trend, AValueAtTheUpperToleranceIsDrawnOnTheBandsEdge) {
  const std::string svg = charts::trend_chart(three_checks());
  // On paper, 720 × 360: the title takes 28 px, one legend row ("check", "tolerance") 18 and a
  // gap 6, so the plot starts at y 52; below it 46 px of tick labels and axis title: it ends at
  // 360 - 46 = 314, 262 px high. The values in µm with the limits span -10..10, with 4 % room
  // -10.8..10.8; 262 / 45 ≈ 6 intervals of 21.6 / 6 = 3.6 -> step 5 -> the axis is -15..15.
  const Element plot = only(svg, "rect", "plot-area");
  EXPECT_EQ(plot.get("y"), "52.00");
  EXPECT_EQ(plot.get("height"), "262.00");
  EXPECT_EQ(plot.get("data-y-min"), "-15");
  EXPECT_EQ(plot.get("data-y-max"), "15");
  // +10 µm: 52 + 262 × (15 - 10) / 30 = 95.67; -10 µm: 52 + 262 × 25 / 30 = 270.33.
  const Element upper = only(svg, "line", "tolerance upper");
  EXPECT_EQ(upper.get("y1"), "95.67");
  EXPECT_EQ(upper.get("y2"), "95.67");
  EXPECT_EQ(only(svg, "line", "tolerance lower").get("y1"), "270.33");
  const Element band = only(svg, "rect", "tolerance-band");
  EXPECT_EQ(band.get("y"), "95.67");
  EXPECT_EQ(band.get("height"), "174.67");  // 262 × 20 / 30
  const auto points = with_class(svg, "circle", "point pass");
  ASSERT_EQ(points.size(), 3u);
  EXPECT_EQ(points[2].get("data-value"), "0.01");
  EXPECT_EQ(points[2].get("cy"), "95.67");   // at the limit is within it: a pass
  EXPECT_EQ(points[0].get("cy"), "217.93");  // -4 µm: 52 + 262 × 19 / 30
  EXPECT_EQ(points[0].get("data-time"), std::to_string(kT0));
  // The middle check is in the middle of the time axis (the padding is the same both sides).
  EXPECT_NEAR(points[1].num("cx"), plot.num("x") + plot.num("width") / 2, 0.01);
}

TEST(Trend, FailedChecksAndValuesOutsideTheBandAreRedDiamonds) {
  charts::TrendChart c = three_checks();
  c.points[0].failed = true;   // failed on another metric
  c.points[2].value = 0.0101;  // just outside, though not flagged
  const std::string svg = charts::trend_chart(c);
  const auto fails = with_class(svg, "path", "point fail");
  ASSERT_EQ(fails.size(), 2u);
  EXPECT_NE(
      svg.find("fill=\"#c8102e\" stroke=\"#000000\" stroke-width=\"0.80\" class=\"point fail\""),
      std::string::npos);
  EXPECT_EQ(with_class(svg, "circle", "point pass").size(), 1u);
  EXPECT_NE(svg.find("data-failed=\"2\""), std::string::npos);
  EXPECT_NE(svg.find(">failed check</text>"), std::string::npos);  // the legend says so
}

TEST(Trend, AOneSidedBandDrawsOnlyTheFiniteLimit) {
  charts::TrendChart c = three_checks();
  c.tolerance = {-charts::kNoLimit, 0.008};
  std::string svg = charts::trend_chart(c);
  EXPECT_EQ(with_class(svg, "line", "tolerance upper").size(), 1u);
  EXPECT_EQ(with_class(svg, "line", "tolerance lower").size(), 0u);
  EXPECT_EQ(with_class(svg, "rect", "tolerance-band").size(), 0u);
  EXPECT_EQ(with_class(svg, "path", "point fail").size(), 1u);  // 10 µm > 8 µm
  c.tolerance = {-0.005, kNaN};                                 // a NaN is no limit
  svg = charts::trend_chart(c);
  EXPECT_EQ(with_class(svg, "line", "tolerance upper").size(), 0u);
  EXPECT_EQ(with_class(svg, "line", "tolerance lower").size(), 1u);
}

TEST(Trend, ControlLimitsForecastAndMarkersAreDrawnWhereTheirValuesAre) {
  charts::TrendChart c = three_checks();
  c.control = charts::ControlLimits{0.001, -0.005, kNaN};
  charts::Forecast f;
  f.samples = {{kT0, 0.0, -0.002, 0.002}, {kT0 + 4 * kDay, 0.008, 0.004, 0.012}};
  f.crossing_ns = kT0 + 5 * kDay;  // beyond the samples: a line, no ring
  c.forecast = f;
  c.markers = {{kT0 + kDay / 2, "new stylus", charts::MarkerKind::Intervention},
               {kT0 + 3 * kDay, "comp", charts::MarkerKind::Compensation}};
  const std::string svg = charts::trend_chart(c);
  const Element plot = only(svg, "rect", "plot-area");
  const double lo = plot.num("data-y-min"), hi = plot.num("data-y-max");
  auto y_of = [&](double microns) {
    return plot.num("y") + plot.num("height") * (hi - microns) / (hi - lo);
  };
  EXPECT_NEAR(only(svg, "line", "control centre").num("y1"), y_of(1), 0.01);
  EXPECT_NEAR(only(svg, "line", "control lcl").num("y1"), y_of(-5), 0.01);
  EXPECT_NE(only(svg, "line", "control lcl").get("stroke-dasharray"), "");  // dashed
  EXPECT_TRUE(with_class(svg, "line", "control ucl").empty());              // NaN: not drawn
  // The fitted line from (t0, 0) to (t0 + 4 d, 8 µm); the band from 2 to 12 µm at its end.
  const auto fit = path_numbers(only(svg, "path", "forecast").get("d"));
  ASSERT_EQ(fit.size(), 4u);
  EXPECT_NEAR(fit[1], y_of(0), 0.01);
  EXPECT_NEAR(fit[3], y_of(8), 0.01);
  const auto band = path_numbers(only(svg, "path", "prediction-band").get("d"));
  ASSERT_EQ(band.size(), 8u);  // upper forwards, lower backwards
  EXPECT_NEAR(band[3], y_of(12), 0.01);
  EXPECT_NEAR(band[5], y_of(4), 0.01);
  // The time axis reaches the crossing; the markers are vertical lines across the plot.
  const Element crossing = only(svg, "line", "crossing");
  EXPECT_EQ(crossing.get("data-time"), std::to_string(kT0 + 5 * kDay));
  EXPECT_LT(crossing.num("x1"), plot.num("x") + plot.num("width"));
  EXPECT_TRUE(with_class(svg, "circle", "crossing-point").empty());
  const Element stylus = only(svg, "line", "marker intervention");
  EXPECT_EQ(stylus.get("y1"), plot.get("y"));
  EXPECT_NE(svg.find(">new stylus</text>"), std::string::npos);
  EXPECT_EQ(with_class(svg, "line", "marker compensation").size(), 1u);
  EXPECT_NE(svg.find("expected to cross a tolerance limit on 2026-03-07"), std::string::npos);
}

// The drift report of issue 37: 3,688 compensations on every trend. A chart given many markers
// groups them: the lines and labels cover at most a tenth of the plot's width, every marker is
// counted in a group, and the drift (56 daily checks, 0.74 µm a day) keeps its line and points.
TEST(Trend, DenseMarkersAreGroupedIntoATenthOfThePlotAtMost) {
  charts::TrendChart c;
  c.quantity = "center_dy_mm";
  c.unit = kMicrons;
  c.tolerance = {-0.025, 0.025};
  for (int d = 0; d < 56; ++d) {
    c.points.push_back({kT0 + d * kDay + kDay / 4, -0.00074 * d + (d % 2 ? 0.0005 : -0.0005), false,
                        "daily-" + std::to_string(d)});
  }
  const int kMarkers = 3688;
  for (int i = 0; i < kMarkers; ++i) {
    c.markers.push_back({kT0 + static_cast<std::int64_t>(i) * (56 * kDay / kMarkers),
                         "compensation work_offset:pm1", charts::MarkerKind::Compensation});
  }
  c.markers.push_back({kT0 + 30 * kDay, "intervention iv-1", charts::MarkerKind::Intervention});
  const std::string svg = charts::trend_chart(c);
  const Element plot = only(svg, "rect", "plot-area");
  std::vector<Element> lines = with_class(svg, "line", "marker compensation");
  const auto interventions = with_class(svg, "line", "marker intervention");
  lines.insert(lines.end(), interventions.begin(), interventions.end());
  ASSERT_FALSE(lines.empty());
  int counted = 0;
  double ink = 0;
  for (const Element& l : lines) {
    counted += std::stoi(l.get("data-count"));
    ink += l.num("stroke-width");
  }
  EXPECT_EQ(counted, kMarkers + 1) << "every marker in one group";
  ASSERT_EQ(interventions.size(), 1u) << "interventions are grouped apart from compensations";
  EXPECT_EQ(interventions[0].get("data-count"), "1");
  EXPECT_EQ(interventions[0].get("data-time"), std::to_string(kT0 + 30 * kDay)) << "its own date";
  // The labels: rotated text with a halo, each about 14 px across the plot.
  std::size_t labels = 0;
  for (const Element& t : elements(svg, "text")) labels += t.get("class") == "marker-label";
  ink += 14.0 * static_cast<double>(labels);
  EXPECT_LE(ink, 0.1 * plot.num("width")) << lines.size() << " lines, " << labels << " labels";
  // The drift: the data line through all 56 checks, and a marker for each.
  EXPECT_EQ(path_numbers(only(svg, "path", "data-line").get("d")).size(), 2u * 56);
  EXPECT_EQ(
      with_class(svg, "circle", "point pass").size() + with_class(svg, "path", "point fail").size(),
      56u);
  EXPECT_EQ(with_class(svg, "path", "point fail").size(), 22u);  // beyond -25 µm from day 34
  // A few markers far apart keep a line each, with their label.
  charts::TrendChart sparse = three_checks();
  sparse.markers = {{kT0 + kDay / 2, "new stylus", charts::MarkerKind::Intervention},
                    {kT0 + 3 * kDay / 2, "comp", charts::MarkerKind::Compensation}};
  const std::string few = charts::trend_chart(sparse);
  EXPECT_EQ(only(few, "line", "marker intervention").get("data-count"), "1");
  EXPECT_EQ(only(few, "line", "marker compensation").get("data-count"), "1");
  EXPECT_NE(few.find(">new stylus</text>"), std::string::npos);
}

TEST(Trend, TheCallersFormatterLabelsTheTimeAxis) {
  charts::TrendChart c = three_checks();
  c.time_label = [](std::int64_t t) { return "day " + std::to_string((t - kT0) / kDay); };
  const std::string svg = charts::trend_chart(c);
  EXPECT_NE(svg.find(">day 1</text>"), std::string::npos);
  EXPECT_EQ(svg.find(">2026-03-03"), std::string::npos);
  // Without it: UTC dates, here with the time of day (two days fit 12-hour ticks).
  EXPECT_NE(charts::trend_chart(three_checks()).find(">2026-03-03 00:00</text>"),
            std::string::npos);
}

// A zone's wall clock: ticks on its round times (here the midnights of a zone 1 h ahead of UTC),
// labelled with its dates, its text in the tooltips. Checked against the UTC chart of the same
// checks 1 h later, where the same labels must fall at the same places.
TEST(Trend, AZonesTicksFallOnItsMidnightsAndItsTextsAreItsOwn) {
  constexpr std::int64_t kHour = kDay / 24;
  charts::TrendChart zoned = three_checks();
  zoned.zone = {[](std::int64_t t) { return t + kHour; }, [](std::int64_t w) { return w - kHour; },
                [](std::int64_t t) { return charts::utc_date_time(t + kHour) + " +01:00"; }};
  charts::TrendChart later = three_checks();
  for (auto& p : later.points) p.time_ns += kHour;
  const auto labels = [](const std::string& svg) {
    static const std::regex kLabel("<text class=\"tick-label\" x=\"([^\"]+)\"[^>]*>([^<]*)</text>");
    std::vector<std::pair<std::string, std::string>> out;
    for (std::sregex_iterator i(svg.begin(), svg.end(), kLabel), end; i != end; ++i) {
      out.emplace_back((*i)[1], (*i)[2]);
    }
    return out;
  };
  const std::string svg = charts::trend_chart(zoned);
  const auto zoned_labels = labels(svg);
  EXPECT_EQ(zoned_labels, labels(charts::trend_chart(later)));
  EXPECT_NE(svg.find(">2026-03-03 00:00</text>"), std::string::npos) << svg;
  // Without the zone the same checks have their ticks at UTC midnights: elsewhere.
  EXPECT_NE(zoned_labels, labels(charts::trend_chart(three_checks())));
  EXPECT_NE(svg.find("b: 2026-03-03 01:00 +01:00, "), std::string::npos) << "b's tooltip";
}

TEST(Trend, NonFiniteValuesAreSkippedAndCounted) {
  charts::TrendChart c = three_checks();
  c.points.push_back({kT0 + 3 * kDay, kNaN, false, ""});
  c.points.push_back({kT0 + 4 * kDay, std::numeric_limits<double>::infinity(), true, ""});
  const std::string svg = charts::trend_chart(c);
  EXPECT_EQ(with_class(svg, "circle", "point pass").size(), 3u);
  EXPECT_TRUE(with_class(svg, "path", "point fail").empty());
  EXPECT_NE(svg.find("2 non-finite values skipped."), std::string::npos);
  EXPECT_NE(svg.find("data-skipped=\"2\""), std::string::npos);
}

// ---- Deviation vectors --------------------------------------------------------------------------

charts::DeviationVectorPlot two_points() {
  charts::DeviationVectorPlot c;
  c.title = "Z = 0";
  c.unit = kMicrons;
  c.tolerance = 0.005;
  c.magnification = 1000;
  c.points = {{0, 0, 0.010, 0, "P1", std::nullopt}, {100, 0, 0, 0, "P2", std::nullopt}};
  return c;
}

TEST(DeviationVectors, TenMicronsAtMagnificationThousandIsTenMillimetresLong) {
  const std::string svg = charts::deviation_vector_plot(two_points());
  const Element plot = only(svg, "rect", "plot-area");
  const double ppu_x = plot.num("width") / (plot.num("data-x-max") - plot.num("data-x-min"));
  const double ppu_y = plot.num("height") / (plot.num("data-y-max") - plot.num("data-y-min"));
  EXPECT_NEAR(ppu_x, ppu_y, 1e-9);  // one scale for both axes
  const auto groups = elements(svg, "g");
  std::vector<Element> vectors;
  for (const Element& g : groups) {
    if (g.get("class").rfind("vector ", 0) == 0) vectors.push_back(g);
  }
  ASSERT_EQ(vectors.size(), 2u);
  EXPECT_EQ(vectors[0].get("class"), "vector fail");  // 10 µm > 5 µm
  EXPECT_EQ(vectors[1].get("class"), "vector pass");
  EXPECT_EQ(vectors[0].get("data-value"), "0.01");
  // The nominal dot of P1 and the tip of its arrow head: 0.010 mm × 1000 = 10 mm to the right.
  const auto nominal = with_class(svg, "circle", "nominal");
  ASSERT_EQ(nominal.size(), 2u);
  const auto heads = with_class(svg, "path", "arrow-head");
  ASSERT_EQ(heads.size(), 1u);  // P2 has no deviation: no arrow
  const auto tip = path_numbers(heads[0].get("d"));
  EXPECT_NEAR(tip[0] - nominal[0].num("cx"), 10 * ppu_x, 0.011);
  EXPECT_NEAR(tip[1], nominal[0].num("cy"), 0.011);
  // The tolerance circle: 0.005 × 1000 = 5 mm in radius; P1 and P2 are 100 mm apart.
  const auto circles = with_class(svg, "circle", "tolerance");
  ASSERT_EQ(circles.size(), 2u);
  EXPECT_NEAR(circles[0].num("r"), 5 * ppu_x, 0.011);
  EXPECT_NEAR(nominal[1].num("cx") - nominal[0].num("cx"), 100 * ppu_x, 0.011);
  // The scale bar: its value (mm of deviation) × 1000 × px per mm is its drawn length.
  Element bar;
  for (const Element& g : groups) {
    if (g.get("class") == "scale-bar") bar = g;
  }
  EXPECT_NEAR(bar.num("data-value") * 1000 * ppu_x, bar.num("data-length"), 0.011);
  EXPECT_GE(bar.num("data-length"), 30);
  EXPECT_LE(bar.num("data-length"), 90);
}

TEST(DeviationVectors, AutomaticMagnificationComesFromTheLargestDeviationAndTheSpacing) {
  charts::DeviationVectorPlot c;
  c.tolerance = 0.010;
  for (int i = 0; i < 3; ++i) c.points.push_back({100.0 * i, 0, 0.003, 0, "", std::nullopt});
  c.points[1].dx = 0.012;
  // 0.8 × 100 mm / 0.012 mm = 6667 -> the 1-2-5 value below it: 5000 (the arrow 60 mm).
  EXPECT_EQ(charts::vector_magnification(c), 5000);
  c.points[1].dx = 0.004;  // the tolerance no longer counts: 0.8 × 100 / 0.004 = 20000
  EXPECT_EQ(charts::vector_magnification(c), 20000);
  // Known scale: 0.05 px per mm draws 0.004 × 20000 = 80 mm as 4 px; raised along the series
  // until at least 8 px: 50000 (10 px).
  EXPECT_EQ(charts::vector_magnification(c, 0.05), 50000);
  for (auto& p : c.points) p.dx = 0;                 // nothing to draw: the tolerance stands for it
  EXPECT_EQ(charts::vector_magnification(c), 5000);  // 0.8 × 100 / 0.010 = 8000 -> 5000
  c.magnification = 750;
  EXPECT_EQ(charts::vector_magnification(c), 750);
}

// The report's grid (pm1: 9 × 6 points, X 200..4200 mm every 500, Y 200..1700 every 300, issue
// 37): deviations of 10 to 60 µm against a tolerance of 150 µm were drawn ×500, 2 to 4 px long
// under 2.5 px dots. Now ×2000 (0.8 × 300 mm / 0.060 mm = 4000 -> 2000): the largest arrow is
// 120 mm of plot, at least 8 px; no arrow reaches the neighbouring point; the circles (300 mm at
// ×2000) would cover their neighbours and are left out, which the legend says.
TEST(DeviationVectors, AGridOfAFourMetreTableShowsItsArrows) {
  charts::DeviationVectorPlot c;
  c.unit = kMicrons;
  c.tolerance = 0.150;
  c.size = {720, 400};
  int k = 0;
  for (int j = 0; j < 6; ++j) {
    for (int i = 0; i < 9; ++i, ++k) {
      const double len = 0.010 + 0.050 * (k % 11) / 10.0;  // 10 .. 60 µm
      const double angle = 0.7 * k;
      c.points.push_back({200.0 + 500 * i, 200.0 + 300 * j, len * std::cos(angle),
                          len * std::sin(angle), "grid:" + std::to_string(k), std::nullopt});
    }
  }
  const std::string svg = charts::deviation_vector_plot(c);
  EXPECT_EQ(charts::vector_magnification(c), 2000);
  EXPECT_NE(svg.find("data-magnification=\"2000\""), std::string::npos);
  EXPECT_NE(svg.find("(arrows ×2000)"), std::string::npos) << "the scale bar says it";
  EXPECT_NE(svg.find("circles ×2000 would cover the neighbours, not drawn"), std::string::npos);
  EXPECT_TRUE(with_class(svg, "circle", "tolerance").empty());
  const Element plot = only(svg, "rect", "plot-area");
  const double ppu = plot.num("width") / (plot.num("data-x-max") - plot.num("data-x-min"));
  const auto nominal = with_class(svg, "circle", "nominal");
  const auto heads = with_class(svg, "path", "arrow-head");
  ASSERT_EQ(nominal.size(), 54u);
  ASSERT_EQ(heads.size(), 54u);
  double longest = 0;
  for (std::size_t i = 0; i < heads.size(); ++i) {
    const auto tip = path_numbers(heads[i].get("d"));
    const double px = std::hypot(tip[0] - nominal[i].num("cx"), tip[1] - nominal[i].num("cy"));
    longest = std::max(longest, px);
    EXPECT_LT(px, 0.8 * 300 * ppu + 0.02) << "reaches no neighbour: " << i;
  }
  EXPECT_GE(longest, 8.0);
  EXPECT_NEAR(longest, 0.060 * 2000 * ppu, 0.02);
}

TEST(DeviationVectors, TheCallersJudgementWins) {
  charts::DeviationVectorPlot c = two_points();
  c.points[0].out_of_tolerance = false;
  c.points[1].out_of_tolerance = true;
  const std::string svg = charts::deviation_vector_plot(c);
  EXPECT_NE(svg.find("<g class=\"vector pass\" data-label=\"P1\""), std::string::npos);
  EXPECT_NE(svg.find("<g class=\"vector fail\" data-label=\"P2\""), std::string::npos);
}

// ---- Point deviation ----------------------------------------------------------------------------

TEST(PointDeviation, PointsOutsideTheDashedLimitsAreRed) {
  charts::PointDeviationChart c;
  c.quantity = "Z deviation";
  c.unit = kMicrons;
  c.tolerance = {-0.015, 0.015};
  c.points = {{1, 0.004, ""}, {2, -0.0151, ""}, {3, 0.015, ""}, {4, kNaN, ""}};
  const std::string svg = charts::point_deviation_chart(c);
  const Element upper = only(svg, "line", "tolerance upper");
  EXPECT_NE(upper.get("stroke-dasharray"), "");
  const auto fails = with_class(svg, "rect", "point fail");
  ASSERT_EQ(fails.size(), 1u);
  EXPECT_EQ(fails[0].get("data-point"), "2");
  EXPECT_EQ(with_class(svg, "circle", "point pass").size(), 2u);
  EXPECT_NE(svg.find("1 non-finite value skipped."), std::string::npos);
  // Point 3 lies on the upper limit's line.
  const Element plot = only(svg, "rect", "plot-area");
  const auto pass = with_class(svg, "circle", "point pass");
  EXPECT_EQ(pass[1].get("data-point"), "3");
  EXPECT_EQ(pass[1].get("cy"), upper.get("y1"));
  EXPECT_GT(pass[1].num("cx"), pass[0].num("cx"));
  EXPECT_GT(plot.num("width"), 0);
}

// ---- ISO 230-2 positioning ----------------------------------------------------------------------

TEST(Positioning, MeansBandsAndTheBidirectionalMeanAreWhereTheValuesAre) {
  charts::PositioningChart c;
  c.unit = kMicrons;
  c.targets = {{0, charts::DirectionStats{0.002, 0.0005}, charts::DirectionStats{-0.002, 0.001}},
               {500, charts::DirectionStats{0.004, 0.0005}, charts::DirectionStats{0.0, 0.001}}};
  const std::string svg = charts::positioning_chart(c);
  const Element plot = only(svg, "rect", "plot-area");
  const double lo = plot.num("data-y-min"), hi = plot.num("data-y-max");
  auto y_of = [&](double microns) {
    return plot.num("y") + plot.num("height") * (hi - microns) / (hi - lo);
  };
  const auto up = with_class(svg, "path", "mean up");
  const auto down = with_class(svg, "path", "mean down");
  ASSERT_EQ(up.size(), 2u);
  ASSERT_EQ(down.size(), 2u);
  EXPECT_EQ(up[1].get("data-target"), "500");
  EXPECT_EQ(up[1].get("data-value"), "0.004");
  // ▲ at 4 µm: its apex 4.5 px above, its base 3.6 px below the value's y.
  const auto tri = path_numbers(up[1].get("d"));
  EXPECT_NEAR(tri[1] + 4.5, y_of(4), 0.011);
  // mean ↑ + 2s at 500: 4 + 2 × 0.5 = 5 µm; mean ↓ - 2s at 0: -2 - 2 × 1 = -4 µm.
  EXPECT_NEAR(path_numbers(only(svg, "path", "band up plus").get("d"))[3], y_of(5), 0.011);
  EXPECT_NEAR(path_numbers(only(svg, "path", "band down minus").get("d"))[1], y_of(-4), 0.011);
  // The bidirectional mean: (2 + -2) / 2 = 0 at 0, (4 + 0) / 2 = 2 µm at 500.
  const auto bi = path_numbers(only(svg, "path", "mean bidirectional").get("d"));
  EXPECT_NEAR(bi[1], y_of(0), 0.011);
  EXPECT_NEAR(bi[3], y_of(2), 0.011);
  c.show_bidirectional_mean = false;
  EXPECT_TRUE(with_class(charts::positioning_chart(c), "path", "mean bidirectional").empty());
}

// ---- Polar --------------------------------------------------------------------------------------

charts::PolarChart four_points() {
  constexpr double kPi = 3.14159265358979323846;
  charts::PolarChart c;
  c.unit = kMicrons;
  charts::PolarTrace t;
  t.label = "CCW";
  // Given out of order: the trace is drawn by angle.
  t.samples = {{kPi, -0.005}, {0, 0.005}, {3 * kPi / 2, 0.0025}, {kPi / 2, 0}};
  c.traces = {t};
  return c;
}

TEST(Polar, PointsAtZeroAndNinetyDegreesLieWhereComputed) {
  const charts::PolarChart c = four_points();
  // On paper, 520 × 560 without a title: the legend ("CCW", "reference circle") is one row from
  // y 8, the plot from 8 + 18 + 6 = 32 to 560 - 22 - 4 = 534 under it: centre (260, 283). The
  // outer ring: min(260 - 34 - 8, 502 / 2 - 17 - 4) = 218 px; the reference circle 0.6 × 218 =
  // 130.8 px. The largest deviation 5 µm -> rings nice(5 / 3) = 2 µm apart, ceil(5 / 2) = 3 on
  // each side: (218 - 130.8) / (3 × 2) = 14.533 px per µm.
  const charts::PolarGeometry g = charts::polar_geometry(c);
  EXPECT_DOUBLE_EQ(g.cx, 260);
  EXPECT_DOUBLE_EQ(g.cy, 283);
  EXPECT_DOUBLE_EQ(g.outer_px, 218);
  EXPECT_DOUBLE_EQ(g.reference_px, 130.8);
  EXPECT_DOUBLE_EQ(g.ring_step, 2);
  EXPECT_EQ(g.rings, 3);
  EXPECT_NEAR(g.px_per_unit, 14.5333, 1e-4);
  // 0°, +5 µm: x = 260 + 130.8 + 5 × 14.533 = 463.47, y = 283.
  // 90°, 0: (260, 283 - 130.8 = 152.20). 180°, -5 µm: x = 260 - (130.8 - 72.67) = 201.87.
  // 270°, +2.5 µm: y = 283 + 130.8 + 36.33 = 450.13. The gaps are 90° (> 60°): not closed.
  const std::string svg = charts::polar_chart(c);
  const Element trace = only(svg, "path", "trace");
  EXPECT_EQ(trace.get("d"), "M463.47 283.00 L260.00 152.20 L201.87 283.00 L260.00 450.13");
  EXPECT_EQ(trace.get("data-trace"), "CCW");
  const auto rings = with_class(svg, "circle", "ring");
  ASSERT_EQ(rings.size(), 6u);  // ±2, ±4, ±6 µm
  EXPECT_EQ(rings[0].get("data-value"), "-6");
  EXPECT_NEAR(rings[0].num("r"), 130.8 - 6 * 14.5333, 0.01);
  EXPECT_EQ(only(svg, "circle", "ring reference").get("r"), "130.80");
  EXPECT_NE(svg.find("scale: 2 µm per ring"), std::string::npos);
}

TEST(Polar, AFullCircleIsClosedAndAnArcIsNot) {
  constexpr double kPi = 3.14159265358979323846;
  charts::PolarChart c;
  c.unit = kMicrons;
  charts::PolarTrace full{"CW", {}};
  charts::PolarTrace arc{"arc", {}};
  for (int k = 0; k < 12; ++k) full.samples.push_back({k * kPi / 6, 0.001});
  for (int k = 0; k <= 6; ++k) arc.samples.push_back({-kPi / 2 + k * kPi / 6, 0.001});
  c.traces = {full, arc};
  const auto traces = with_class(charts::polar_chart(c), "path", "trace");
  ASSERT_EQ(traces.size(), 2u);
  EXPECT_EQ(traces[0].get("d").substr(traces[0].get("d").size() - 2), " Z");
  EXPECT_EQ(traces[1].get("d").find('Z'), std::string::npos);
  // The arc -90°..+90° starts after its gap, at -90° (straight down from the centre).
  const auto g = charts::polar_geometry(c);
  const auto arc_xy = path_numbers(traces[1].get("d"));
  EXPECT_NEAR(arc_xy[0], g.cx, 0.011);
  EXPECT_GT(arc_xy[1], g.cy);
  EXPECT_NE(traces[1].get("stroke-dasharray"), traces[0].get("stroke-dasharray"));
}

// ---- Error budget -------------------------------------------------------------------------------

TEST(Budget, BarsAreToScaleAndThoseOverTheAllowanceAreRed) {
  charts::BudgetChart c;
  c.unit = kMicrons;
  c.allowance = 0.020;
  c.contributions = {{"X scale", 0.005}, {"thermal", 0.025}, {"bad", kNaN}};
  c.total = charts::BudgetBar{"total (RSS)", std::hypot(0.005, 0.025)};
  const std::string svg = charts::budget_chart(c);
  const Element plot = only(svg, "rect", "plot-area");
  const auto x_of = [&](double microns) {
    return plot.num("x") + plot.num("width") * (microns - plot.num("data-x-min")) /
                               (plot.num("data-x-max") - plot.num("data-x-min"));
  };
  const Element small = only(svg, "rect", "bar contribution");
  const Element large = only(svg, "rect", "bar contribution over");
  const Element total = only(svg, "rect", "bar total over");
  EXPECT_EQ(small.get("x"), large.get("x"));
  EXPECT_NEAR(small.num("x"), x_of(0), 0.011);
  EXPECT_NEAR(large.num("width") / small.num("width"), 5, 0.01);
  EXPECT_EQ(large.get("fill"), "#c8102e");
  EXPECT_NEAR(only(svg, "line", "allowance").num("x1"), x_of(20), 0.011);
  EXPECT_GT(total.num("y"), large.num("y"));  // the total below the contributions
  EXPECT_NE(svg.find("1 non-finite value skipped."), std::string::npos);
}

// ---- Every chart --------------------------------------------------------------------------------

struct Drawn {
  std::string kind;
  std::function<std::string(const std::string& label, charts::Size size, bool empty)> draw;
};

// A chart of `kind` drawn by `draw` from `labelled(label)` at `size`, emptied by `clear` first
// when `empty`.
template <typename Chart, typename Labelled, typename Clear>
Drawn drawn(std::string kind, std::string (*draw)(const Chart&), Labelled labelled, Clear clear) {
  return {std::move(kind), [=](const std::string& label, charts::Size size, bool empty) {
            Chart c = labelled(label);
            c.size = size;
            if (empty) clear(c);
            return draw(c);
          }};
}

std::vector<Drawn> every_chart() {
  using Label = const std::string&;
  return {
      drawn(
          "trend", charts::trend_chart,
          [](Label label) {
            charts::TrendChart c = three_checks();
            c.title = c.quantity = c.description = label;
            c.points[0].label = label;
            c.markers = {{kT0, label, charts::MarkerKind::Intervention}};
            return c;
          },
          [](charts::TrendChart& c) { c.points.clear(); }),
      drawn(
          "deviation-vectors", charts::deviation_vector_plot,
          [](Label label) {
            charts::DeviationVectorPlot c = two_points();
            c.title = c.x_name = c.points[0].label = label;
            return c;
          },
          [](charts::DeviationVectorPlot& c) { c.points.clear(); }),
      drawn(
          "point-deviation", charts::point_deviation_chart,
          [](Label label) {
            charts::PointDeviationChart c;
            c.title = c.quantity = label;
            c.points = {{1, 0.001, label}, {2, 0.002, ""}};
            return c;
          },
          [](charts::PointDeviationChart& c) { c.points.clear(); }),
      drawn(
          "positioning", charts::positioning_chart,
          [](Label label) {
            charts::PositioningChart c;
            c.title = c.axis_name = label;
            c.targets = {{0, charts::DirectionStats{0.001, 0.0001}, std::nullopt},
                         {10, charts::DirectionStats{0.002, 0.0001}, std::nullopt}};
            return c;
          },
          [](charts::PositioningChart& c) { c.targets.clear(); }),
      drawn(
          "polar", charts::polar_chart,
          [](Label label) {
            charts::PolarChart c = four_points();
            c.title = c.traces[0].label = label;
            return c;
          },
          [](charts::PolarChart& c) { c.traces[0].samples.clear(); }),
      drawn(
          "budget", charts::budget_chart,
          [](Label label) {
            charts::BudgetChart c;
            c.title = c.allowance_label = label;
            c.contributions = {{label, 0.004}, {"b", 0.002}};
            c.allowance = 0.005;
            return c;
          },
          [](charts::BudgetChart& c) { c.contributions.clear(); }),
  };
}

TEST(EveryChart, RootTitleAndDescComeFirstWithTheSizeAsked) {
  for (const Drawn& d : every_chart()) {
    SCOPED_TRACE(d.kind);
    const std::string svg = d.draw("A chart", {800, 500}, false);
    EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 800 500\" "
                        "width=\"800\" height=\"500\" role=\"img\" class=\"ncqual-chart "
                        "ncqual-chart-" +
                            d.kind + "\" data-chart=\"" + d.kind + "\"",
                        0),
              0u);
    const std::size_t after_root = svg.find(">\n") + 2;
    EXPECT_EQ(svg.compare(after_root, 22, "<title>A chart</title>"), 0);
    EXPECT_EQ(svg.compare(after_root + 23, 6, "<desc>"), 0);
    EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
    EXPECT_EQ(svg.find("<script"), std::string::npos);
    EXPECT_EQ(svg.find("<style"), std::string::npos);
  }
}

TEST(EveryChart, SizesDefaultAndClamp) {
  for (const Drawn& d : every_chart()) {
    SCOPED_TRACE(d.kind);
    const auto root = elements(d.draw("x", {0, -5}, false), "svg")[0];
    EXPECT_GE(root.num("width"), 520);  // the chart's own default
    EXPECT_GE(root.num("height"), 320);
    const auto huge = elements(d.draw("x", {1e9, std::nan("")}, false), "svg")[0];
    EXPECT_EQ(huge.get("width"), "4000");
    EXPECT_EQ(huge.get("height"), root.get("height"));
    const auto tiny = elements(d.draw("x", {10, 10}, false), "svg")[0];
    EXPECT_EQ(tiny.get("width"), "160");
  }
}

TEST(EveryChart, TheSameInputGivesTheSameBytes) {
  for (const Drawn& d : every_chart()) {
    SCOPED_TRACE(d.kind);
    EXPECT_EQ(d.draw("same", {}, false), d.draw("same", {}, false));
    EXPECT_NE(d.draw("same", {}, false), d.draw("other", {}, false));
  }
}

TEST(EveryChart, HostileLabelsAreEscapedEverywhere) {
  const std::string hostile = "<&\"'>";
  for (const Drawn& d : every_chart()) {
    SCOPED_TRACE(d.kind);
    const std::string svg = d.draw("x " + hostile + " y", {}, false);
    EXPECT_EQ(svg.find(hostile), std::string::npos);
    EXPECT_EQ(svg.find("<&"), std::string::npos);
    EXPECT_NE(svg.find("x &lt;&amp;&quot;&#39;&gt; y"), std::string::npos);
    EXPECT_EQ(charts::test::first_text(svg, "title"), "x &lt;&amp;&quot;&#39;&gt; y");
  }
}

TEST(EveryChart, TinySizesAndLongLabelsStillGiveACompleteChart) {
  const std::string long_label(400, 'W');
  for (const Drawn& d : every_chart()) {
    SCOPED_TRACE(d.kind);
    const std::string svg = d.draw(long_label, {160, 160}, false);
    EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
    EXPECT_EQ(svg.find("nan"), std::string::npos);
    // Visible texts are cut with an ellipsis; the <title> keeps the whole label.
    EXPECT_NE(svg.find("WWW\xE2\x80\xA6</text>"), std::string::npos);
    EXPECT_EQ(charts::test::first_text(svg, "title"), long_label);
  }
}

TEST(EveryChart, ExtremeValuesDrawWithoutNaNs) {
  charts::TrendChart t = three_checks();
  t.points[0].value = 1e300;
  t.points[1].value = -1e300;
  const std::string trend = charts::trend_chart(t);
  EXPECT_EQ(trend.find("nan"), std::string::npos);
  EXPECT_EQ(with_class(trend, "path", "point fail").size(), 2u);
  charts::PolarChart p = four_points();
  p.ring_step = 1e-300;  // would need more rings than anyone can read: 50 at most
  const std::string polar = charts::polar_chart(p);
  EXPECT_EQ(with_class(polar, "circle", "ring").size(), 100u);
  EXPECT_EQ(polar.find("nan"), std::string::npos);
}

TEST(EveryChart, NoDataDrawsTheFrameAndSaysSo) {
  for (const Drawn& d : every_chart()) {
    SCOPED_TRACE(d.kind);
    const std::string svg = d.draw("empty", {}, true);
    EXPECT_NE(svg.find(">no data</text>"), std::string::npos);
    EXPECT_EQ(svg.find("data-value=\"0.00"), std::string::npos);
    EXPECT_EQ(svg.find("class=\"point"), std::string::npos);
    EXPECT_NE(svg.find("data-points=\"0\""), std::string::npos);
  }
}

}  // namespace
