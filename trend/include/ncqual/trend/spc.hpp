// SPDX-License-Identifier: Apache-2.0
// Statistical process control of one metric: the individuals chart (one value per check, so no
// subgroups), the Western Electric rules, EWMA and tabular CUSUM charts, process capability and
// the pass rate (docs/trends.md).
//
// References:
//   [M]   D. C. Montgomery, Introduction to Statistical Quality Control, 6th ed., Wiley 2009:
//         §6.4 the individuals chart (sigma = MR-bar / d2, d2 = 1.128 for moving ranges of two),
//         chapter 5's sensitizing rules (the Western Electric rules), §9.1 the tabular CUSUM (K,
//         H, N+, the new mean mu0 + K + C+/N+; Example 9.1), §9.2 the EWMA chart (time-varying
//         limits; Example 9.2), §8.3 the capability ratios Cp, Cpk, Cpu, Cpl and the performance
//         ratios Pp, Ppk.
//   [WE]  Western Electric Co., Statistical Quality Control Handbook, 1956: the four rules.
//   [NIST] NIST/SEMATECH e-Handbook of Statistical Methods, §6.3.2.4 (EWMA), §6.3.2.3 (CUSUM),
//         §6.1.6 (capability).
//   [W]   E. B. Wilson, Probable inference, the law of succession, and statistical inference,
//         JASA 22 (1927): the score interval of the pass rate.
//
// Values are taken as given (the metric's unit). Entries that are not finite are skipped: they
// neither count in a rule's window nor move an EWMA or CUSUM; every index reported refers to the
// caller's vector.
#pragma once

#include "ncqual/trend/series.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::trend {

// d2 for moving ranges of two consecutive values: the tabulated 1.128 of [M] Appendix VI (the
// exact value is 2/sqrt(pi) = 1.12838; the table's is what a hand calculation uses).
inline constexpr double kD2 = 1.128;
// The fewest points a baseline may be estimated from.
inline constexpr std::size_t kMinBaselinePoints = 5;

// The reference an individuals chart is drawn against: estimated from the first `points` finite
// values of the segment (Phase I of [M] §6.4).
struct Baseline {
  std::size_t points = 0;          // values used
  double mean = 0;                 // centre line
  double mean_moving_range = 0;    // MR-bar = mean of |x_i - x_{i-1}| over the baseline
  double sigma_within = 0;         // MR-bar / d2: short-term sigma; the charts' sigma
  double sigma_overall = 0;        // sample standard deviation (n - 1), long-term sigma
  double upper_control_limit = 0;  // mean + 3 sigma_within
  double lower_control_limit = 0;  // mean - 3 sigma_within
  // Non-empty when no baseline could be estimated: fewer finite values than asked for ("not
  // enough points: 7 of 10"), `points` below kMinBaselinePoints, or no variation (all moving
  // ranges zero: the limits would collapse onto the centre line).
  std::string error;

  bool ok() const { return error.empty(); }
};
Baseline baseline(const std::vector<double>& values, std::size_t points = 10);

// A Western Electric rule holding for the window that ends at `index` ([WE], [M] chapter 5):
//   rule 1  the point is beyond 3 sigma (outside the control limits)
//   rule 2  2 of the last 3 points beyond 2 sigma, on the same side
//   rule 3  4 of the last 5 points beyond 1 sigma, on the same side
//   rule 4  the last 8 points on the same side of the centre line
// "Beyond" is strict (|x - mean| > k sigma) and so is "on a side" (a point on the centre line
// breaks a run). A rule holds at every index whose window meets it, so a rule "fires" at the
// first such index and stays on while later windows still meet it.
struct RuleSignal {
  int rule = 0;  // 1..4
  std::size_t index = 0;
  Side side = Side::Above;
};
// Every (rule, index) that holds, by index and then by rule. Empty when the baseline is not ok.
// `only`: the rules on that side of the centre line only (a one-sided metric: watched_side).
std::vector<RuleSignal> western_electric(const std::vector<double>& values, const Baseline& base,
                                         std::optional<Side> only = std::nullopt);
// The first signal of `rule` in signals; std::nullopt when it never holds.
std::optional<RuleSignal> first_signal(const std::vector<RuleSignal>& signals, int rule);

// EWMA chart ([M] §9.2, [NIST] §6.3.2.4): z_0 = centre, z_i = lambda x_i + (1 - lambda) z_{i-1}
// for the i-th finite value, limits centre ± L sigma sqrt(lambda / (2 - lambda) (1 - (1 -
// lambda)^(2i))), which start narrow and widen to their asymptote. A signal is z_i strictly
// beyond its limit. Defaults lambda = 0.2, L = 3 ([M]'s usual choice for small shifts).
struct Ewma {
  double lambda = 0.2;
  double width = 3;  // L
  double centre = 0;
  double sigma = 0;
  // Per input index (a non-finite value repeats the previous z and limits; before the first
  // finite value they are the centre).
  std::vector<double> z, lower_limit, upper_limit;
  std::optional<std::size_t> first_signal;
  Side first_side = Side::Above;
  std::string error;  // lambda outside (0, 1], L <= 0, sigma <= 0 or not finite

  bool ok() const { return error.empty(); }
  // Whether z at index is beyond a limit, and on which side.
  std::optional<Side> signal_at(std::size_t index) const;
};
Ewma ewma(const std::vector<double>& values, double centre, double sigma, double lambda = 0.2,
          double width = 3);

// Tabular CUSUM ([M] §9.1, [NIST] §6.3.2.3), with K = k sigma and H = h sigma:
//   C+_i = max(0, x_i - (centre + K) + C+_{i-1}),  C-_i = max(0, (centre - K) - x_i + C-_{i-1}),
// C+_0 = C-_0 = 0; N+ and N- count the consecutive values for which C+ (C-) has been non-zero.
// A signal is C+ > H (up) or C- > H (down). The sums are never reset after a signal: ncqual
// restarts a series only at a recorded intervention or compensation (restart_after), so a sum
// stays above H for as long as the shift lasts. The estimated mean after an upward shift is
// centre + K + C+_i / N+_i, after a downward one centre - K - C-_i / N-_i ([M] §9.1).
// Defaults k = 0.5 (detects a shift of 1 sigma), h = 5.
struct Cusum {
  double centre = 0;
  double sigma = 0;
  double k = 0;  // K, in the values' unit
  double h = 0;  // H, in the values' unit
  // Per input index (a non-finite value repeats the previous sums and counts).
  std::vector<double> upper, lower;                   // C+, C-
  std::vector<std::size_t> upper_count, lower_count;  // N+, N-
  std::optional<std::size_t> first_up, first_down;
  // The estimated new mean at the first signal of each side.
  std::optional<double> mean_at_first_up, mean_at_first_down;
  std::string error;  // k < 0, h <= 0, sigma <= 0 or not finite

  bool ok() const { return error.empty(); }
  // The estimated mean at index, for a shift on `side` (centre when that sum is zero).
  double estimated_mean(std::size_t index, Side side) const;
};
Cusum cusum(const std::vector<double>& values, double centre, double sigma, double k = 0.5,
            double h = 5);

// Process capability against the tolerance band ([M] §8.3, [NIST] §6.1.6), from the finite
// values given (the assessment passes the segment since the last restart):
//   Cp  = (U - L) / (6 sigma_within)     Pp  = (U - L) / (6 sigma_overall)
//   Cpu = (U - mean) / (3 sigma_within)  Ppu = (U - mean) / (3 sigma_overall)
//   Cpl = (mean - L) / (3 sigma_within)  Ppl = (mean - L) / (3 sigma_overall)
//   Cpk = min(Cpu, Cpl)                  Ppk = min(Ppu, Ppl)
// sigma_within = MR-bar / d2 (short term, insensitive to a slow drift), sigma_overall the sample
// standard deviation (which a drift inflates: Ppk well below Cpk says the process moves).
// A one-sided band has only Cpu (no lower limit) or Cpl (no upper limit): Cp and Pp are not
// defined (std::nullopt), and Cpk is that one ratio (min(Cpu, Cpl) with the missing side at
// +infinity). With no limit at all, or a sigma of zero, the ratios it needs are std::nullopt.
struct Capability {
  std::size_t points = 0;
  double mean = 0;
  double sigma_within = 0;
  double sigma_overall = 0;
  std::optional<double> cp, cpk, cpu, cpl;
  std::optional<double> pp, ppk, ppu, ppl;
  std::string error;  // fewer than min_points finite values, or an invalid band

  bool ok() const { return error.empty(); }
};
Capability capability(const std::vector<double>& values, const Band& band,
                      std::size_t min_points = 5);

// Counts of verdicts over some period.
struct VerdictCounts {
  std::size_t pass = 0;
  std::size_t fail = 0;
  std::size_t invalid = 0;  // the check could not judge the machine (instrument, data)
};
// pass / (pass + fail), with the Wilson score interval at `confidence` ([W]): an invalid check
// says nothing about the machine, so it is not in the rate. The interval tells 9 of 10 from 900
// of 1000. rate and its bounds are std::nullopt when nothing was judged.
struct PassRate {
  std::size_t judged = 0;  // pass + fail
  std::optional<double> rate, lower, upper;
};
PassRate pass_rate(const VerdictCounts& counts, double confidence = 0.95);

}  // namespace ncqual::trend
