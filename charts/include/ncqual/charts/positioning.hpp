// SPDX-License-Identifier: Apache-2.0
// The ISO 230-2 bidirectional positioning chart: at every target position the mean deviation
// approached from below (↑) and from above (↓), each with its band of mean ± 2s, as the
// standard's reports plot them, and optionally the mean bidirectional deviation.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ncqual/charts/chart.hpp"

namespace ncqual::charts {

// One direction at one target (caller's unit, e.g. mm): x̄ and s of the deviations.
struct DirectionStats {
  double mean = 0;
  double s = 0;
};

struct PositioningTarget {
  double position = 0;                 // the target position P_i (axis unit, e.g. mm)
  std::optional<DirectionStats> up;    // approached in + (↑)
  std::optional<DirectionStats> down;  // approached in − (↓)
};

struct PositioningChart {
  std::string title;
  std::string description;
  std::string axis_name = "X";             // the x axis: "target position X (mm)"
  std::string position_unit = "mm";        // the unit of the positions, as given
  std::string quantity = "deviation";      // the y axis' name
  DisplayUnit unit;                        // of the deviations, e.g. {1000, "µm"}
  std::vector<PositioningTarget> targets;  // any order
  bool show_bidirectional_mean = true;     // x̄_i = (x̄↑ + x̄↓) / 2 where both exist
  Size size;                               // default 720 × 380
};

inline constexpr Size kPositioningSize{720, 380};

// data-chart="positioning". Lines of mean ↑ (accent, solid, ▲), mean ↓ (black, long dashes, ▼),
// their mean ± 2s (thin, dashed / dotted), the bidirectional mean (grey, dash-dot). Markers:
// class "mean up|down", data-target, data-value (the mean, caller's unit), data-s. A target
// whose mean or s is not finite is skipped in that direction (counted in the <desc>).
std::string positioning_chart(const PositioningChart& chart);

}  // namespace ncqual::charts
