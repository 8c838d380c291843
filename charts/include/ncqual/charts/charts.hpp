// SPDX-License-Identifier: Apache-2.0
// Every chart of ncqual_charts (docs/charts.md): include this, or the chart's own header.
#pragma once

#include "ncqual/charts/axis.hpp"
#include "ncqual/charts/budget.hpp"
#include "ncqual/charts/chart.hpp"
#include "ncqual/charts/point_deviation.hpp"
#include "ncqual/charts/polar.hpp"
#include "ncqual/charts/positioning.hpp"
#include "ncqual/charts/svg.hpp"
#include "ncqual/charts/trend.hpp"
#include "ncqual/charts/vector_plot.hpp"
