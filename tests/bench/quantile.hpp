// SPDX-License-Identifier: Apache-2.0
// What the benches share to summarise latencies.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace ncqual::bench {

// Nearest-rank quantile, q in [0, 1] (0 for no values).
inline double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
}

}  // namespace ncqual::bench
