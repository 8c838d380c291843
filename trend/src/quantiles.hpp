// SPDX-License-Identifier: Apache-2.0
// Quantiles of the Student t and standard normal distributions (Boost.Math), kept out of the
// public headers so that only ncqual_trend's sources include Boost.
#pragma once

namespace ncqual::trend::detail {

// The p-quantile of Student's t with df degrees of freedom (df >= 1, 0 < p < 1). The two-sided
// 95 % quantiles (p = 0.975) of df 1 to 1024 are memoized: the assessment asks for one per
// prefix of a series, and Boost computes each in a few microseconds.
double t_quantile(double p, double df);
// The p-quantile of the standard normal distribution (0 < p < 1).
double normal_quantile(double p);

}  // namespace ncqual::trend::detail
