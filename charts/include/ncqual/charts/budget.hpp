// SPDX-License-Identifier: Apache-2.0
// The error budget bar chart: one horizontal bar per contribution to the error at the tool tip,
// the total (e.g. their RSS) as a distinct bar below them, and the allowance as a vertical line,
// so that what uses most of the budget and whether the total fits are seen at once.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "ncqual/charts/chart.hpp"

namespace ncqual::charts {

struct BudgetBar {
  std::string label;  // the source, e.g. "X scale", "probe"
  double value = 0;   // its contribution, caller's unit
};

struct BudgetChart {
  std::string title;
  std::string description;
  std::string quantity = "contribution";  // the x axis' name
  DisplayUnit unit;                       // e.g. {1000, "µm"} for values in mm
  std::vector<BudgetBar> contributions;   // top to bottom, in the given order
  std::optional<BudgetBar> total;         // below the contributions, in black
  double allowance = std::numeric_limits<double>::quiet_NaN();  // not finite: no line
  std::string allowance_label = "allowance";
  Size size;  // default 720 × 360
};

inline constexpr Size kBudgetSize{720, 360};

// data-chart="budget"; bars <rect class="bar contribution|total [over]"> with data-label and
// data-value (caller's unit). A bar longer than the allowance is red. Non-finite values are
// skipped (counted in the <desc>).
std::string budget_chart(const BudgetChart& chart);

}  // namespace ncqual::charts
