// SPDX-License-Identifier: Apache-2.0
// Two judgements of one measurement set compared: what a plant looks at when it accepts a new
// solver version against its recorded checks (`ncqual replay --resolve`, docs/recordings.md).
#pragma once

#include "ncqual/common/model.hpp"

#include <string>
#include <vector>

namespace ncqual::solver {

struct CompareOptions {
  // A metric has moved when its value changed by more than this fraction of its tolerance band's
  // width (upper - lower; for a one-sided band, of its finite limit's magnitude) ...
  double band_fraction = 0.01;
  // ... and by more than this, in the metric's own unit (rounding in the last digits is not a
  // change).
  double floor = 1e-9;
  // A correction's offset has moved past this (mm or rad, as the offset is).
  double correction_tolerance = 1e-4;
};

struct ResultDifference {
  enum class Kind { Verdict, Metric, Band, MetricMissing, MetricNew, Causes, Correction, Reason };
  Kind kind = Kind::Verdict;
  std::string text;  // "verdict PASS -> FAIL", "metric x_dev_mm 0.0021 -> 0.0035 mm (...)"
};

// What differs between `recorded` and `fresh`, judgements of the same set: the verdict, each
// metric's value (beyond CompareOptions), its band and pass flag, metrics present in one only,
// the likely causes or their order, the correction (target, offsets beyond the tolerance), and
// the reason of a FAIL or INVALID. Empty when nothing does. Times and produced_by are not
// compared (the fresh result is made now, by this build).
std::vector<ResultDifference> compare_results(const CheckResult& recorded, const CheckResult& fresh,
                                              const CompareOptions& options = {});

std::string_view to_string(ResultDifference::Kind kind);

}  // namespace ncqual::solver
