// SPDX-License-Identifier: Apache-2.0
// compare_results (solver/include/ncqual/solver/compare.hpp): two judgements of one
// measurement set, built by hand. The allowances are worked out by hand from CompareOptions'
// defaults: 1% of the band's width (of the finite limit for a one-sided band), at least 1e-9,
// and 1e-4 for a correction's offsets.
#include "ncqual/solver/compare.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

using Kind = ResultDifference::Kind;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Metric metric(const std::string& name, double value, double lower, double upper, bool pass,
              const std::string& unit = "mm") {
  Metric m;
  m.name = name;
  m.value = value;
  m.unit = unit;
  m.lower = lower;
  m.upper = upper;
  m.pass = pass;
  return m;
}

// A PASS of a positioning check: two metrics, two likely causes, a correction.
CheckResult recorded_result() {
  CheckResult r;
  r.machine_id = "pm1";
  r.request_id = "req-1";
  r.kind = CheckKind::MonumentPositioning;
  r.verdict = Verdict::Pass;
  r.metrics = {metric("x_dev_mm", 0.002, -0.01, 0.01, true),
               metric("y_dev_mm", -0.003, -0.01, 0.01, true)};
  r.likely_causes = {"thermal_drift", "probe_calibration"};
  Correction c;
  c.target = "machine:work_offset";
  c.offsets = {{"dx", 0.0100, "mm"}, {"dy", -0.0200, "mm"}};
  r.correction = c;
  r.time_ns = 1'700'000'000'000'000'000;
  r.produced_by = "ncqual-solver 0.1.0 (git aaaaaaa)";
  return r;
}

std::vector<Kind> kinds(const std::vector<ResultDifference>& d) {
  std::vector<Kind> out;
  out.reserve(d.size());
  for (const auto& x : d) out.push_back(x.kind);
  return out;
}

std::string all_text(const std::vector<ResultDifference>& d) {
  std::string out;
  for (const auto& x : d) out += "[" + std::string(to_string(x.kind)) + "] " + x.text + "\n";
  return out;
}

TEST(CompareResults, IdenticalResultsDifferInNothing) {
  const CheckResult r = recorded_result();
  EXPECT_TRUE(compare_results(r, r).empty()) << all_text(compare_results(r, r));
}

TEST(CompareResults, TimesAndProducedByAreNotCompared) {
  const CheckResult recorded = recorded_result();
  CheckResult fresh = recorded;
  fresh.time_ns += 3'600'000'000'000;
  fresh.produced_by = "ncqual-solver 0.2.0 (git bbbbbbb)";
  const auto d = compare_results(recorded, fresh);
  EXPECT_TRUE(d.empty()) << all_text(d);
}

TEST(CompareResults, VerdictPassToFail) {
  const CheckResult recorded = recorded_result();
  CheckResult fresh = recorded;
  fresh.verdict = Verdict::Fail;
  fresh.reason = "x out of tolerance";
  const auto d = compare_results(recorded, fresh);
  ASSERT_EQ(d.size(), 1U) << all_text(d);
  EXPECT_EQ(d[0].kind, Kind::Verdict);
  EXPECT_NE(d[0].text.find("PASS -> FAIL"), std::string::npos) << d[0].text;
}

// Band [-0.01, 0.01]: width 0.02, 1% of it 0.0002. 0.00019 is within, 0.00021 beyond.
TEST(CompareResults, MetricMovedWithinOnePercentOfItsBandIsNoDifference) {
  const CheckResult recorded = recorded_result();
  CheckResult fresh = recorded;
  fresh.metrics[0].value = 0.002 + 0.00019;
  const auto d = compare_results(recorded, fresh);
  EXPECT_TRUE(d.empty()) << all_text(d);

  fresh.metrics[0].value = 0.002 - 0.00019;
  EXPECT_TRUE(compare_results(recorded, fresh).empty());
}

TEST(CompareResults, MetricMovedBeyondOnePercentOfItsBandIsADifference) {
  const CheckResult recorded = recorded_result();
  CheckResult fresh = recorded;
  fresh.metrics[0].value = 0.002 + 0.00021;
  const auto d = compare_results(recorded, fresh);
  ASSERT_EQ(d.size(), 1U) << all_text(d);
  EXPECT_EQ(d[0].kind, Kind::Metric);
  EXPECT_NE(d[0].text.find("x_dev_mm"), std::string::npos) << d[0].text;
  EXPECT_NE(d[0].text.find("0.002 -> 0.00221"), std::string::npos) << d[0].text;

  fresh.metrics[0].value = 0.002 - 0.00021;  // downwards too
  EXPECT_EQ(kinds(compare_results(recorded, fresh)), std::vector<Kind>{Kind::Metric});
}

// Lower limit -inf, upper 0.05: the allowance is 1% of 0.05 = 0.0005.
TEST(CompareResults, OneSidedBandUsesOnePercentOfItsFiniteLimit) {
  CheckResult recorded = recorded_result();
  recorded.metrics = {metric("runout_mm", 0.01, -kInf, 0.05, true)};
  CheckResult fresh = recorded;
  fresh.metrics[0].value = 0.01 + 0.00049;
  EXPECT_TRUE(compare_results(recorded, fresh).empty())
      << all_text(compare_results(recorded, fresh));
  fresh.metrics[0].value = 0.01 + 0.00051;
  EXPECT_EQ(kinds(compare_results(recorded, fresh)), std::vector<Kind>{Kind::Metric});

  // The other side: lower 0.02, upper +inf, 1% of 0.02 = 0.0002.
  recorded.metrics = {metric("gap_mm", 0.5, 0.02, kInf, true)};
  fresh = recorded;
  fresh.metrics[0].value = 0.5 + 0.00019;
  EXPECT_TRUE(compare_results(recorded, fresh).empty());
  fresh.metrics[0].value = 0.5 + 0.00021;
  EXPECT_EQ(kinds(compare_results(recorded, fresh)), std::vector<Kind>{Kind::Metric});
}

// No finite limit: only the floor (1e-9) is left.
TEST(CompareResults, UnboundedMetricMovesPastTheFloor) {
  CheckResult recorded = recorded_result();
  recorded.metrics = {metric("info_mm", 1.0, -kInf, kInf, true)};
  CheckResult fresh = recorded;
  fresh.metrics[0].value = 1.0 + 5e-10;
  EXPECT_TRUE(compare_results(recorded, fresh).empty());
  fresh.metrics[0].value = 1.0 + 5e-9;
  EXPECT_EQ(kinds(compare_results(recorded, fresh)), std::vector<Kind>{Kind::Metric});
}

TEST(CompareResults, NaNBecomingANumberIsADifference) {
  CheckResult recorded = recorded_result();
  recorded.metrics[0].value = kNaN;
  recorded.metrics[0].pass = false;
  CheckResult fresh = recorded;
  EXPECT_TRUE(compare_results(recorded, fresh).empty()) << "NaN against NaN is no change";

  fresh.metrics[0].value = 0.002;
  auto d = compare_results(recorded, fresh);
  ASSERT_EQ(d.size(), 1U) << all_text(d);
  EXPECT_EQ(d[0].kind, Kind::Metric);

  // And back: a number becoming NaN.
  d = compare_results(fresh, recorded);
  ASSERT_EQ(d.size(), 1U) << all_text(d);
  EXPECT_EQ(d[0].kind, Kind::Metric);
}

TEST(CompareResults, MetricMissingAndNew) {
  const CheckResult recorded = recorded_result();
  CheckResult fresh = recorded;
  fresh.metrics.erase(fresh.metrics.begin() + 1);  // y_dev_mm no longer reported
  fresh.metrics.push_back(metric("z_dev_mm", 0.001, -0.01, 0.01, true));
  const auto d = compare_results(recorded, fresh);
  ASSERT_EQ(kinds(d), (std::vector<Kind>{Kind::MetricMissing, Kind::MetricNew})) << all_text(d);
  EXPECT_NE(d[0].text.find("y_dev_mm"), std::string::npos) << d[0].text;
  EXPECT_NE(d[1].text.find("z_dev_mm"), std::string::npos) << d[1].text;
}

TEST(CompareResults, MetricOrderIsNotCompared) {
  const CheckResult recorded = recorded_result();
  CheckResult fresh = recorded;
  std::swap(fresh.metrics[0], fresh.metrics[1]);
  const auto d = compare_results(recorded, fresh);
  EXPECT_TRUE(d.empty()) << all_text(d);
}

TEST(CompareResults, BandChanged) {
  const CheckResult recorded = recorded_result();
  CheckResult fresh = recorded;
  fresh.metrics[0].lower = -0.02;
  fresh.metrics[0].upper = 0.02;
  auto d = compare_results(recorded, fresh);
  ASSERT_EQ(kinds(d), std::vector<Kind>{Kind::Band}) << all_text(d);
  EXPECT_NE(d[0].text.find("x_dev_mm"), std::string::npos) << d[0].text;
  EXPECT_NE(d[0].text.find("[-0.01, 0.01]"), std::string::npos) << d[0].text;
  EXPECT_NE(d[0].text.find("[-0.02, 0.02]"), std::string::npos) << d[0].text;

  // An infinite limit is the same band when it stays infinite, another when it becomes finite.
  CheckResult one_sided = recorded_result();
  one_sided.metrics = {metric("runout_mm", 0.01, -kInf, 0.05, true)};
  EXPECT_TRUE(compare_results(one_sided, one_sided).empty());
  CheckResult closed = one_sided;
  closed.metrics[0].lower = 0;
  EXPECT_EQ(kinds(compare_results(one_sided, closed)), std::vector<Kind>{Kind::Band});

  // The unit is part of the band.
  fresh = recorded;
  fresh.metrics[0].unit = "um";
  EXPECT_EQ(kinds(compare_results(recorded, fresh)), std::vector<Kind>{Kind::Band});
}

TEST(CompareResults, CausesReorderedAndChanged) {
  const CheckResult recorded = recorded_result();
  CheckResult fresh = recorded;
  fresh.likely_causes = {"probe_calibration", "thermal_drift"};
  auto d = compare_results(recorded, fresh);
  ASSERT_EQ(kinds(d), std::vector<Kind>{Kind::Causes}) << all_text(d);
  EXPECT_NE(d[0].text.find("reordered"), std::string::npos) << d[0].text;
  EXPECT_EQ(d[0].text.find("changed"), std::string::npos) << d[0].text;

  fresh.likely_causes = {"thermal_drift", "axis_squareness"};
  d = compare_results(recorded, fresh);
  ASSERT_EQ(kinds(d), std::vector<Kind>{Kind::Causes}) << all_text(d);
  EXPECT_NE(d[0].text.find("changed"), std::string::npos) << d[0].text;
  EXPECT_EQ(d[0].text.find("reordered"), std::string::npos) << d[0].text;
  EXPECT_NE(d[0].text.find("axis_squareness"), std::string::npos) << d[0].text;

  fresh.likely_causes.clear();  // none at all: changed
  d = compare_results(recorded, fresh);
  ASSERT_EQ(kinds(d), std::vector<Kind>{Kind::Causes}) << all_text(d);
  EXPECT_NE(d[0].text.find("changed"), std::string::npos) << d[0].text;
}

TEST(CompareResults, CorrectionAddedAndRemoved) {
  const CheckResult with = recorded_result();
  CheckResult without = with;
  without.correction.reset();

  auto d = compare_results(without, with);
  ASSERT_EQ(kinds(d), std::vector<Kind>{Kind::Correction}) << all_text(d);
  EXPECT_NE(d[0].text.find("now made"), std::string::npos) << d[0].text;
  EXPECT_NE(d[0].text.find("machine:work_offset"), std::string::npos) << d[0].text;

  d = compare_results(with, without);
  ASSERT_EQ(kinds(d), std::vector<Kind>{Kind::Correction}) << all_text(d);
  EXPECT_NE(d[0].text.find("no longer made"), std::string::npos) << d[0].text;

  EXPECT_TRUE(compare_results(without, without).empty());
}

// correction_tolerance 1e-4: dx 0.0100 -> 0.01005 is within, 0.0100 -> 0.0102 beyond.
TEST(CompareResults, CorrectionOffsetMovedPastItsTolerance) {
  const CheckResult recorded = recorded_result();
  CheckResult fresh = recorded;
  fresh.correction->offsets[0].value = 0.01005;
  auto d = compare_results(recorded, fresh);
  EXPECT_TRUE(d.empty()) << all_text(d);

  fresh.correction->offsets[0].value = 0.0102;
  d = compare_results(recorded, fresh);
  ASSERT_EQ(kinds(d), std::vector<Kind>{Kind::Correction}) << all_text(d);
  EXPECT_NE(d[0].text.find("dx"), std::string::npos) << d[0].text;
  EXPECT_EQ(d[0].text.find("dy"), std::string::npos) << d[0].text;

  // A looser tolerance takes it back.
  CompareOptions loose;
  loose.correction_tolerance = 1e-3;
  EXPECT_TRUE(compare_results(recorded, fresh, loose).empty());
}

TEST(CompareResults, CorrectionTargetOrOffsetsChanged) {
  const CheckResult recorded = recorded_result();
  CheckResult fresh = recorded;
  fresh.correction->target = "fixture:F1";
  auto d = compare_results(recorded, fresh);
  ASSERT_EQ(kinds(d), std::vector<Kind>{Kind::Correction}) << all_text(d);
  EXPECT_NE(d[0].text.find("fixture:F1"), std::string::npos) << d[0].text;

  fresh = recorded;
  fresh.correction->offsets.pop_back();  // dy no longer set
  d = compare_results(recorded, fresh);
  ASSERT_EQ(kinds(d), std::vector<Kind>{Kind::Correction}) << all_text(d);
  EXPECT_NE(d[0].text.find("dy"), std::string::npos) << d[0].text;

  fresh = recorded;
  fresh.correction->offsets.push_back({"dz", 0.003, "mm"});  // a new offset
  d = compare_results(recorded, fresh);
  EXPECT_EQ(kinds(d), std::vector<Kind>{Kind::Correction}) << all_text(d);
}

TEST(CompareResults, ReasonChangedOnAnEqualFailVerdict) {
  CheckResult recorded = recorded_result();
  recorded.verdict = Verdict::Fail;
  recorded.reason = "x_dev_mm out of tolerance";
  CheckResult fresh = recorded;
  fresh.reason = "x_dev_mm and y_dev_mm out of tolerance";
  auto d = compare_results(recorded, fresh);
  ASSERT_EQ(kinds(d), std::vector<Kind>{Kind::Reason}) << all_text(d);
  EXPECT_NE(d[0].text.find("x_dev_mm out of tolerance"), std::string::npos) << d[0].text;
  EXPECT_NE(d[0].text.find("x_dev_mm and y_dev_mm out of tolerance"), std::string::npos)
      << d[0].text;

  recorded.verdict = fresh.verdict = Verdict::Invalid;
  EXPECT_EQ(kinds(compare_results(recorded, fresh)), std::vector<Kind>{Kind::Reason});

  // A PASS has no reason to compare.
  recorded.verdict = fresh.verdict = Verdict::Pass;
  EXPECT_TRUE(compare_results(recorded, fresh).empty());
}

TEST(CompareResults, PassFlagFlipWithinTheAllowanceIsStillReported) {
  const CheckResult recorded = recorded_result();
  CheckResult fresh = recorded;
  fresh.metrics[0].value = 0.002 + 0.00001;  // far within 0.0002
  fresh.metrics[0].pass = false;
  auto d = compare_results(recorded, fresh);
  ASSERT_EQ(kinds(d), std::vector<Kind>{Kind::Metric}) << all_text(d);
  EXPECT_NE(d[0].text.find("x_dev_mm"), std::string::npos) << d[0].text;
  EXPECT_NE(d[0].text.find("outside its band"), std::string::npos) << d[0].text;

  d = compare_results(fresh, recorded);
  ASSERT_EQ(kinds(d), std::vector<Kind>{Kind::Metric}) << all_text(d);
  EXPECT_NE(d[0].text.find("within its band"), std::string::npos) << d[0].text;
}

TEST(CompareResults, PassFlagFlipBeyondTheAllowanceIsOneDifference) {
  const CheckResult recorded = recorded_result();
  CheckResult fresh = recorded;
  fresh.metrics[0].value = 0.012;
  fresh.metrics[0].pass = false;
  const auto d = compare_results(recorded, fresh);
  ASSERT_EQ(kinds(d), std::vector<Kind>{Kind::Metric}) << all_text(d);
  EXPECT_NE(d[0].text.find("now outside its band"), std::string::npos) << d[0].text;
}

TEST(CompareResults, SeveralDifferencesInOrder) {
  const CheckResult recorded = recorded_result();
  CheckResult fresh = recorded;
  fresh.verdict = Verdict::Fail;
  fresh.metrics[0].value = 0.02;
  fresh.metrics[0].pass = false;
  fresh.likely_causes = {"probe_calibration", "thermal_drift"};
  fresh.correction.reset();
  const auto d = compare_results(recorded, fresh);
  EXPECT_EQ(kinds(d),
            (std::vector<Kind>{Kind::Verdict, Kind::Metric, Kind::Causes, Kind::Correction}))
      << all_text(d);
}

TEST(CompareResults, KindNames) {
  EXPECT_EQ(to_string(Kind::Verdict), "verdict");
  EXPECT_EQ(to_string(Kind::Metric), "metric");
  EXPECT_EQ(to_string(Kind::Band), "band");
  EXPECT_EQ(to_string(Kind::MetricMissing), "metric_missing");
  EXPECT_EQ(to_string(Kind::MetricNew), "metric_new");
  EXPECT_EQ(to_string(Kind::Causes), "causes");
  EXPECT_EQ(to_string(Kind::Correction), "correction");
  EXPECT_EQ(to_string(Kind::Reason), "reason");
}

}  // namespace
}  // namespace ncqual::solver
