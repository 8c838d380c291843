// SPDX-License-Identifier: Apache-2.0
// What every chart shares: its size, the display unit of its values, and the look (one accent
// colour, red for what is out of tolerance, black and greys for the rest; dash patterns and
// marker shapes tell the series apart in greyscale too).
#pragma once

#include <string>
#include <string_view>

namespace ncqual::charts {

// The size of the chart in CSS pixels (the SVG's width, height and viewBox). A zero, negative
// or non-finite side takes the chart's default; the others are clamped to 160..4000.
struct Size {
  double width = 0;
  double height = 0;
};

// How values in the caller's unit are shown: display value = value × scale, labelled `unit`.
// Values in mm shown as µm: {1000, "µm"}.
struct DisplayUnit {
  double scale = 1;
  std::string unit;
};

// The colours the charts use (printable: black and greys, one accent, red).
namespace palette {
inline constexpr std::string_view kInk = "#000000";
inline constexpr std::string_view kDark = "#333333";
inline constexpr std::string_view kGrey = "#6e6e6e";
inline constexpr std::string_view kLightGrey = "#b4b4b4";
inline constexpr std::string_view kGrid = "#e2e2e2";
inline constexpr std::string_view kBand = "#eeeeee";
inline constexpr std::string_view kAccent = "#1f5fa8";
inline constexpr std::string_view kAccentLight = "#cddcf0";
inline constexpr std::string_view kRed = "#c8102e";
}  // namespace palette

// The value of every chart's data-chart attribute (and its class "ncqual-chart-<kind>").
namespace kind {
inline constexpr std::string_view kTrend = "trend";
inline constexpr std::string_view kDeviationVectors = "deviation-vectors";
inline constexpr std::string_view kPointDeviation = "point-deviation";
inline constexpr std::string_view kPositioning = "positioning";
inline constexpr std::string_view kPolar = "polar";
inline constexpr std::string_view kBudget = "budget";
}  // namespace kind

}  // namespace ncqual::charts
