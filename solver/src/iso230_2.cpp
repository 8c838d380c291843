// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/iso230_2.hpp"

#include "result_building.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>

namespace ncqual::solver {
namespace {

// The readings of one target, by direction, as indices into the input.
struct TargetReadings {
  std::vector<std::size_t> up;
  std::vector<std::size_t> down;
  const std::vector<std::size_t>& of(Approach a) const { return a == Approach::Up ? up : down; }
};

std::map<double, TargetReadings> group(const std::vector<PositioningReading>& r) {
  std::map<double, TargetReadings> targets;
  for (std::size_t i = 0; i < r.size(); ++i) {
    auto& t = targets[r[i].target_mm];
    (r[i].direction == Approach::Up ? t.up : t.down).push_back(i);
  }
  return targets;
}

DirectionFigures figures(const std::vector<PositioningReading>& r,
                         const std::vector<std::size_t>& indices) {
  DirectionFigures f;
  f.cycles = static_cast<int>(indices.size());
  double sum = 0;
  f.min_mm = f.max_mm = r[indices.front()].measured_mm - r[indices.front()].target_mm;
  for (std::size_t i : indices) {
    const double x = r[i].measured_mm - r[i].target_mm;
    sum += x;
    f.min_mm = std::min(f.min_mm, x);
    f.max_mm = std::max(f.max_mm, x);
  }
  f.mean_mm = sum / static_cast<double>(indices.size());
  double ss = 0;
  for (std::size_t i : indices) {
    const double d = r[i].measured_mm - r[i].target_mm - f.mean_mm;
    ss += d * d;
  }
  f.s_mm = std::sqrt(ss / static_cast<double>(indices.size() - 1));
  f.R_mm = 4 * f.s_mm;
  return f;
}

// max - min of the values, or nullopt when there are none.
struct Range {
  std::optional<double> lo, hi;
  void add(double v) {
    lo = lo ? std::min(*lo, v) : v;
    hi = hi ? std::max(*hi, v) : v;
  }
  void add_low(double v) { lo = lo ? std::min(*lo, v) : v; }
  void add_high(double v) { hi = hi ? std::max(*hi, v) : v; }
  std::optional<double> width() const {
    if (!lo || !hi) return std::nullopt;
    return *hi - *lo;
  }
};

struct Maximum {
  std::optional<double> value;
  void add(double v) { value = value ? std::max(*value, v) : v; }
};

}  // namespace

std::string_view to_string(Approach a) { return a == Approach::Up ? "up" : "down"; }

std::optional<ReadingProblem> find_iso230_2_problem(const std::vector<PositioningReading>& r) {
  if (r.empty()) return ReadingProblem{std::nullopt, std::nullopt, "no readings"};
  for (std::size_t i = 0; i < r.size(); ++i) {
    if (!std::isfinite(r[i].target_mm)) {
      return ReadingProblem{
          i, std::nullopt,
          "target_mm = " + detail::quote_number(r[i].target_mm) + " is not a finite number"};
    }
    if (!std::isfinite(r[i].measured_mm)) {
      return ReadingProblem{
          i, std::nullopt,
          "measured_mm = " + detail::quote_number(r[i].measured_mm) + " is not a finite number"};
    }
  }
  std::map<std::tuple<double, int, Approach>, std::size_t> seen;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const auto [it, fresh] =
        seen.emplace(std::make_tuple(r[i].target_mm, r[i].cycle, r[i].direction), i);
    if (!fresh) {
      return ReadingProblem{i, it->second,
                            "target_mm = " + detail::quote_number(r[i].target_mm) +
                                ", cycle = " + std::to_string(r[i].cycle) +
                                ", direction = " + std::string(to_string(r[i].direction)) +
                                ": a second reading of the same target, cycle and direction"};
    }
  }
  const auto targets = group(r);
  if (targets.size() < 2) {
    return ReadingProblem{
        std::nullopt, std::nullopt,
        "only 1 target (target_mm = " + detail::quote_number(targets.begin()->first) +
            "); ISO 230-2 needs at least 2 targets"};
  }
  bool any_up = false, any_down = false;
  for (const auto& [target, t] : targets) {
    any_up = any_up || !t.up.empty();
    any_down = any_down || !t.down.empty();
  }
  for (const auto& [target, t] : targets) {
    for (Approach a : {Approach::Up, Approach::Down}) {
      const auto& idx = t.of(a);
      if (idx.size() == 1) {
        return ReadingProblem{idx.front(), std::nullopt,
                              "target_mm = " + detail::quote_number(target) +
                                  ", direction = " + std::string(to_string(a)) +
                                  ": 1 cycle; at least 2 are needed for the standard "
                                  "uncertainty s (n - 1 in its denominator)"};
      }
    }
  }
  for (const auto& [target, t] : targets) {
    for (Approach a : {Approach::Up, Approach::Down}) {
      const Approach other = a == Approach::Up ? Approach::Down : Approach::Up;
      const bool other_elsewhere = other == Approach::Up ? any_up : any_down;
      if (!t.of(a).empty() && t.of(other).empty() && other_elsewhere) {
        return ReadingProblem{t.of(a).front(), std::nullopt,
                              "target_mm = " + detail::quote_number(target) + " has " +
                                  std::string(to_string(a)) + " readings but no " +
                                  std::string(to_string(other)) +
                                  " readings, while other targets do"};
      }
    }
  }
  return std::nullopt;
}

Iso230_2Result evaluate_iso230_2(const std::vector<PositioningReading>& readings) {
  if (const auto p = find_iso230_2_problem(readings)) {
    std::string what = "evaluate_iso230_2: ";
    if (p->index) what += "readings[" + std::to_string(*p->index) + "]: ";
    what += p->message;
    if (p->first_index) what += " (first at readings[" + std::to_string(*p->first_index) + "])";
    throw std::invalid_argument(what);
  }
  Iso230_2Result out;
  Range e_up, e_down, e_both, m_range, a_up, a_down;
  Maximum r_up, r_down, r_both, b_abs;
  double b_sum = 0;
  // The figures of one target in one direction, added to that direction's axis figures.
  const auto direction = [&](const std::vector<std::size_t>& indices, bool& has, Range& e, Range& a,
                             Maximum& r) {
    const DirectionFigures d = figures(readings, indices);
    has = true;
    out.cycles = std::max(out.cycles, d.cycles);
    e.add(d.mean_mm);
    e_both.add(d.mean_mm);
    a.add_high(d.mean_mm + 2 * d.s_mm);
    a.add_low(d.mean_mm - 2 * d.s_mm);
    r.add(d.R_mm);
    return d;
  };
  for (const auto& [target, t] : group(readings)) {
    TargetFigures f;
    f.target_mm = target;
    if (!t.up.empty()) f.up = direction(t.up, out.has_up, e_up, a_up, r_up);
    if (!t.down.empty()) f.down = direction(t.down, out.has_down, e_down, a_down, r_down);
    if (f.up && f.down) {
      f.B_mm = f.up->mean_mm - f.down->mean_mm;
      f.R_mm = std::max(
          {2 * f.up->s_mm + 2 * f.down->s_mm + std::abs(*f.B_mm), f.up->R_mm, f.down->R_mm});
      f.mean_mm = (f.up->mean_mm + f.down->mean_mm) / 2;
      m_range.add(*f.mean_mm);
      r_both.add(*f.R_mm);
      b_abs.add(std::abs(*f.B_mm));
      b_sum += *f.B_mm;
    }
    out.targets.push_back(f);
  }
  out.E_up_mm = e_up.width();
  out.E_down_mm = e_down.width();
  out.A_up_mm = a_up.width();
  out.A_down_mm = a_down.width();
  out.R_up_mm = r_up.value;
  out.R_down_mm = r_down.value;
  if (out.has_up && out.has_down) {
    // find_iso230_2_problem guarantees both directions at every target here.
    Range a;
    a.add_high(*a_up.hi);
    a.add_high(*a_down.hi);
    a.add_low(*a_up.lo);
    a.add_low(*a_down.lo);
    out.A_mm = a.width();
    out.E_mm = e_both.width();
    out.M_mm = m_range.width();
    out.R_mm = r_both.value;
    out.B_mm = b_abs.value;
    out.B_mean_mm = b_sum / static_cast<double>(out.targets.size());
  }
  return out;
}

std::vector<std::string> iso230_2_conformance(const Iso230_2Result& r) {
  std::vector<std::string> out;
  if (r.targets.empty()) return out;
  const auto text = detail::quote_number;
  // The fewest approaches in any measured direction at any target, and where.
  int fewest = std::numeric_limits<int>::max();
  std::string where;
  for (const TargetFigures& t : r.targets) {
    for (const auto& [d, name] : {std::pair{&t.up, "up (+)"}, std::pair{&t.down, "down (-)"}}) {
      if (*d && (*d)->cycles < fewest) {
        fewest = (*d)->cycles;
        where = text(t.target_mm) + " mm " + name;
      }
    }
  }
  if (fewest < 5) {
    out.push_back(std::to_string(fewest) + " approach(es) at target " + where +
                  ": ISO 230-2 asks for 5 in each direction at each target");
  }
  if (r.has_up != r.has_down) {
    out.push_back(std::string("measured in one direction only (") + (r.has_up ? "up" : "down") +
                  "): ISO 230-2 approaches each target in both; the bidirectional figures and "
                  "the reversal B are not given");
  }
  const double travel = r.targets.back().target_mm - r.targets.front().target_mm;
  const auto needed = static_cast<std::size_t>(std::max(5.0, std::ceil(5.0 * travel / 1000.0)));
  if (r.targets.size() < needed) {
    out.push_back(std::to_string(r.targets.size()) + " targets over " + text(travel) +
                  " mm of travel: ISO 230-2 asks for at least 5 per metre and 5 in all (" +
                  std::to_string(needed) + " here)");
  }
  if (r.targets.size() >= 3) {
    const double first = r.targets[1].target_mm - r.targets[0].target_mm;
    bool even = first > 0;
    for (std::size_t i = 2; i < r.targets.size() && even; ++i) {
      const double interval = r.targets[i].target_mm - r.targets[i - 1].target_mm;
      even = std::abs(interval - first) <= 1e-6 * std::max(1.0, first);
    }
    if (even) {
      out.push_back("targets at one even interval of " + text(first) +
                    " mm: ISO 230-2 spaces them unevenly (e.g. at random) so that periodic "
                    "errors, a ball screw's pitch or a scale's period, are not sampled at one "
                    "phase");
    }
  }
  return out;
}

}  // namespace ncqual::solver
