// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/compare.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace ncqual::solver {

namespace {

std::string number(double v) {
  std::ostringstream out;
  out.precision(6);
  out << v;
  return out.str();
}

// How far a metric's value may move without counting as moved.
double allowance(const Metric& m, const CompareOptions& o) {
  const bool lower = std::isfinite(m.lower);
  const bool upper = std::isfinite(m.upper);
  double width = 0;
  if (lower && upper) {
    width = m.upper - m.lower;
  } else if (lower || upper) {
    width = std::abs(lower ? m.lower : m.upper);
  }
  return std::max(o.floor, o.band_fraction * width);
}

bool same_number(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

std::string causes_text(const std::vector<std::string>& causes) {
  std::string out;
  for (const auto& c : causes) out += (out.empty() ? "" : ", ") + c;
  return out.empty() ? "(none)" : out;
}

}  // namespace

std::string_view to_string(ResultDifference::Kind kind) {
  switch (kind) {
    case ResultDifference::Kind::Verdict: return "verdict";
    case ResultDifference::Kind::Metric: return "metric";
    case ResultDifference::Kind::Band: return "band";
    case ResultDifference::Kind::MetricMissing: return "metric_missing";
    case ResultDifference::Kind::MetricNew: return "metric_new";
    case ResultDifference::Kind::Causes: return "causes";
    case ResultDifference::Kind::Correction: return "correction";
    case ResultDifference::Kind::Reason: return "reason";
  }
  return "?";
}

std::vector<ResultDifference> compare_results(const CheckResult& recorded, const CheckResult& fresh,
                                              const CompareOptions& options) {
  using Kind = ResultDifference::Kind;
  std::vector<ResultDifference> out;
  if (recorded.verdict != fresh.verdict) {
    out.push_back({Kind::Verdict, "verdict " + std::string(to_string(recorded.verdict)) + " -> " +
                                      std::string(to_string(fresh.verdict))});
  }
  std::map<std::string, const Metric*> fresh_metrics;
  for (const auto& m : fresh.metrics) fresh_metrics[m.name] = &m;
  for (const auto& old : recorded.metrics) {
    const auto it = fresh_metrics.find(old.name);
    if (it == fresh_metrics.end()) {
      out.push_back({Kind::MetricMissing, "metric " + old.name + " is no longer reported (was " +
                                              number(old.value) + " " + old.unit + ")"});
      continue;
    }
    const Metric& now = *it->second;
    fresh_metrics.erase(it);
    const double moved = now.value - old.value;
    const double allowed = allowance(old, options);
    if ((std::isnan(old.value) != std::isnan(now.value)) ||
        (!std::isnan(moved) && std::abs(moved) > allowed)) {
      out.push_back(
          {Kind::Metric,
           "metric " + old.name + " " + number(old.value) + " -> " + number(now.value) + " " +
               now.unit + " (moved " + number(moved) + ", more than " + number(allowed) + ")" +
               (old.pass != now.pass ? now.pass ? ", now within its band" : ", now outside its band"
                                     : "")});
    } else if (old.pass != now.pass) {
      out.push_back({Kind::Metric, "metric " + old.name + " " + number(old.value) + " -> " +
                                       number(now.value) + " " + now.unit + " now " +
                                       (now.pass ? "within" : "outside") + " its band"});
    }
    if (!same_number(old.lower, now.lower) || !same_number(old.upper, now.upper) ||
        old.unit != now.unit) {
      out.push_back({Kind::Band, "metric " + old.name + " band [" + number(old.lower) + ", " +
                                     number(old.upper) + "] " + old.unit + " -> [" +
                                     number(now.lower) + ", " + number(now.upper) + "] " +
                                     now.unit});
    }
  }
  for (const auto& m : fresh.metrics) {
    if (fresh_metrics.count(m.name) != 0) {
      out.push_back({Kind::MetricNew,
                     "metric " + m.name + " is new (" + number(m.value) + " " + m.unit + ")"});
    }
  }
  if (recorded.likely_causes != fresh.likely_causes) {
    std::vector<std::string> a = recorded.likely_causes;
    std::vector<std::string> b = fresh.likely_causes;
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    out.push_back({Kind::Causes, std::string(a == b ? "causes reordered: " : "causes changed: ") +
                                     causes_text(recorded.likely_causes) + " -> " +
                                     causes_text(fresh.likely_causes)});
  }
  if (recorded.correction.has_value() != fresh.correction.has_value()) {
    out.push_back({Kind::Correction, recorded.correction ? "the correction is no longer made"
                                                         : "a correction is now made (" +
                                                               fresh.correction->target + ")"});
  } else if (recorded.correction) {
    const Correction& a = *recorded.correction;
    const Correction& b = *fresh.correction;
    std::map<std::string, double> offsets;
    for (const auto& o : b.offsets) offsets[o.name] = o.value;
    bool differs = a.target != b.target || a.offsets.size() != b.offsets.size();
    std::string detail;
    for (const auto& o : a.offsets) {
      const auto it = offsets.find(o.name);
      if (it == offsets.end()) {
        differs = true;
        detail += " " + o.name + " no longer set;";
      } else if (std::abs(it->second - o.value) > options.correction_tolerance) {
        differs = true;
        detail += " " + o.name + " " + number(o.value) + " -> " + number(it->second) + ";";
      }
    }
    if (differs) {
      out.push_back({Kind::Correction,
                     "correction of " + a.target + (a.target != b.target ? " -> " + b.target : "") +
                         " changed:" + (detail.empty() ? " its offsets" : detail)});
    }
  }
  if (recorded.verdict != Verdict::Pass && recorded.verdict == fresh.verdict &&
      recorded.reason != fresh.reason) {
    out.push_back({Kind::Reason, "reason \"" + recorded.reason + "\" -> \"" + fresh.reason + "\""});
  }
  return out;
}

}  // namespace ncqual::solver
