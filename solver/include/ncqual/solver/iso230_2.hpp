// SPDX-License-Identifier: Apache-2.0
// Evaluation of a linear-axis positioning test per ISO 230-2:2014 ("Determination of accuracy
// and repeatability of positioning of numerically controlled axes"), from the readings of a
// laser interferometer (or any length instrument) at targets P_i, i = 1..m, in cycles
// j = 1..n, approaching each target in the positive (up, ↑) and negative (down, ↓) direction.
//
// Definitions (ISO 230-2:2014 clause 3, the same formulas as the 2006 edition; all in mm):
//   x_ij          = P_ij - P_i                       positional deviation (measured - target)
//   x̄_i↑          = (1/n) Σ_j x_ij↑                  mean unidirectional positional deviation
//   s_i↑          = sqrt(Σ_j (x_ij↑ - x̄_i↑)² / (n-1)) estimator of the unidirectional
//                                                    (standard) uncertainty of positioning
//   B_i           = x̄_i↑ - x̄_i↓                      reversal value at a position
//   R_i↑ = 4 s_i↑, R_i↓ = 4 s_i↓                     unidirectional repeatability at a position
//   R_i           = max(2 s_i↑ + 2 s_i↓ + |B_i|, R_i↑, R_i↓)  bidirectional repeatability
//   x̄_i           = (x̄_i↑ + x̄_i↓) / 2                mean bidirectional positional deviation
// and for the axis:
//   B  = max_i |B_i|                 reversal value of the axis
//   B̄  = (1/m) Σ_i B_i (signed)      mean reversal value of the axis
//   R↑ = max_i R_i↑, R↓ = max_i R_i↓, R = max_i R_i          repeatability
//   E↑ = max_i x̄_i↑ - min_i x̄_i↑, E↓ likewise              unidirectional systematic deviation
//   E  = max_i(x̄_i↑, x̄_i↓) - min_i(x̄_i↑, x̄_i↓)             bidirectional systematic deviation
//   M  = max_i x̄_i - min_i x̄_i                              range of the mean bidirectional
//                                                           positional deviation
//   A↑ = max_i(x̄_i↑ + 2 s_i↑) - min_i(x̄_i↑ - 2 s_i↑), A↓ likewise   unidirectional accuracy
//   A  = max_i(x̄_i↑ + 2 s_i↑, x̄_i↓ + 2 s_i↓) - min_i(x̄_i↑ - 2 s_i↑, x̄_i↓ - 2 s_i↓)
//                                                           bidirectional accuracy
// (The 2 and 4 are a coverage factor k = 2 on s. Older documents, such as the 1988 edition and
// VDI/DGQ 3441, define repeatability and accuracy with other factors: their figures are not
// comparable with these.)
//
// The standard asks for at least 5 targets per metre and n = 5 cycles; this evaluation only
// needs what the formulas need (2 targets, 2 cycles) so that short checks can be evaluated too,
// and iso230_2_conformance says where a run's plan departs from the standard. Data with one
// approach direction only (a unidirectional test) is evaluated: the figures of the missing
// direction and the bidirectional ones (B_i, R_i, x̄_i, B, B̄, R, E, M, A) are then absent
// (std::nullopt), not 0.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::solver {

// The direction in which the axis approached the target: Up = moving in +, Down = moving in -.
enum class Approach { Up, Down };
std::string_view to_string(Approach a);  // "up", "down"

// One reading of the run. Cycle numbers only identify the cycle (any integers, usually 1..n).
struct PositioningReading {
  double target_mm = 0;  // P_i, the commanded target position
  int cycle = 0;         // j
  Approach direction = Approach::Up;
  double measured_mm = 0;  // P_ij, the actual position the instrument measured
};

// Why readings cannot be evaluated. `index` is the reading at fault (none when the readings as a
// whole are: too few targets, no readings); `first_index` the earlier reading a duplicate
// repeats. `message` names the fields and values but not the indices, so that a file reader
// can say lines instead.
struct ReadingProblem {
  std::optional<std::size_t> index;
  std::optional<std::size_t> first_index;
  std::string message;
};

// The first problem that makes the readings unusable, or nullopt. Checked in this order:
//   non-finite target_mm or measured_mm;
//   a duplicate (target, cycle, direction) (index = the later reading);
//   fewer than 2 distinct targets (index none);
//   a target and direction with fewer than 2 cycles (n - 1 = 0: no s_i);
//   a target measured in one direction only while the other direction has readings at other
//   targets (the bidirectional figures would be computed over a subset of the targets).
std::optional<ReadingProblem> find_iso230_2_problem(const std::vector<PositioningReading>& r);

// The figures of one target in one approach direction (mm).
struct DirectionFigures {
  int cycles = 0;      // n, readings at this target in this direction
  double mean_mm = 0;  // x̄_i↑ (or x̄_i↓)
  double s_mm = 0;     // s_i↑ (n - 1 in the denominator)
  double R_mm = 0;     // R_i↑ = 4 s_i↑
  double min_mm = 0;   // smallest and largest x_ij of the cycles (for the plots)
  double max_mm = 0;
};

// The figures of one target (mm). up/down absent when the test has no readings in that
// direction; B/R/mean absent unless both are present.
struct TargetFigures {
  double target_mm = 0;  // P_i
  std::optional<DirectionFigures> up;
  std::optional<DirectionFigures> down;
  std::optional<double> B_mm;     // B_i = x̄_i↑ - x̄_i↓
  std::optional<double> R_mm;     // R_i
  std::optional<double> mean_mm;  // x̄_i = (x̄_i↑ + x̄_i↓) / 2
};

// The axis figures (mm). *_up_mm absent without up readings, *_down_mm without down readings,
// the bidirectional ones (A, E, M, R, B, B_mean) unless both directions were measured.
struct Iso230_2Result {
  std::vector<TargetFigures> targets;  // ascending target_mm
  int cycles = 0;  // the largest n of any target and direction (the run's cycle count)
  bool has_up = false;
  bool has_down = false;
  std::optional<double> A_mm, A_up_mm, A_down_mm;
  std::optional<double> E_mm, E_up_mm, E_down_mm;
  std::optional<double> M_mm;
  std::optional<double> R_mm, R_up_mm, R_down_mm;
  std::optional<double> B_mm;       // max |B_i|
  std::optional<double> B_mean_mm;  // mean of B_i, signed
};

// Evaluates the readings (any order) per the definitions above. Throws std::invalid_argument
// "evaluate_iso230_2: readings[k]: <problem> (first at readings[f])" for the problems
// find_iso230_2_problem finds. Targets are grouped by exact equality of target_mm.
Iso230_2Result evaluate_iso230_2(const std::vector<PositioningReading>& readings);

// Where the run's test plan departs from ISO 230-2:2014 (the figures are still evaluated), one
// sentence each, empty when it conforms:
//  - fewer than 5 approaches in a direction at a target (the fewest, where, and the standard's 5);
//  - one direction only (the bidirectional figures are absent);
//  - fewer targets than 5 per metre of travel, with at least 5 in all (how many there are and
//    how many the travel needs);
//  - targets at one even interval (3 targets or more): the standard spaces them unevenly, e.g.
//    at random, so that periodic errors (a ball screw's pitch, a scale's period) are sampled
//    fairly rather than at one phase.
std::vector<std::string> iso230_2_conformance(const Iso230_2Result& result);

}  // namespace ncqual::solver
