// SPDX-License-Identifier: Apache-2.0
// The weekly fixture checks. The code follows the procedure of the patent ("Probe Checks of
// Fixture"):
//   0. make sure the touches, the configuration and the fixture config can support a verdict;
//   1. turn each touch's latched axis readouts into a stylus ball centre (nominal kinematics);
//   2. the point of the face each touch met: the ball centre moved by the ball radius along the
//      approach;
//   3. each pogo's measured position: X and Y midway between its opposite side faces, Z of its
//      top reference face;
//   4. deltas = measured - commanded (commanded from the fixture config and the configuration);
//   5. pre-calibration: judge the deltas; on failure they become the zero offsets;
//      post-calibration: judge the deltas; on failure order the likely causes by a fit of the
//      deltas against the commanded positions (6; the fit itself: fixture_delta_fit.cpp).
#include "ncqual/solver/fixture_checks.hpp"

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/fixture.hpp"
#include "ncqual/common/kinematics.hpp"
#include "result_building.hpp"
#include "touch_input.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <utility>

namespace ncqual::solver {

namespace fixture_checks {
namespace {
constexpr const char* kAxisName[] = {"x", "y", "z"};
}

std::string pogo_metric_name(std::string_view pogo, int axis) {
  return "pogo_" + std::string(pogo) + "_d" + kAxisName[axis] + "_mm";
}

std::string post_metric_name(int configuration, std::string_view pogo, int axis) {
  return "cfg" + std::to_string(configuration) + "_" + pogo_metric_name(pogo, axis);
}

std::string fit_metric_name(int delta_axis, int commanded_axis) {
  return std::string("fixture_fit_d") + kAxisName[delta_axis] + "_per_" +
         kAxisName[commanded_axis] + (delta_axis == commanded_axis ? "_ppm" : "_urad");
}
}  // namespace fixture_checks

namespace {

using namespace fixture_checks;
using detail::format_number;
using detail::format_vector;

constexpr const char* kAxisLower[] = {"x", "y", "z"};
constexpr const char* kAxisUpper[] = {"X", "Y", "Z"};
constexpr std::size_t kReasonListLimit = 5;

enum class Stage { Pre, Post };

std::string_view check_name(Stage stage) {
  return stage == Stage::Pre ? "the fixture pre-calibration" : "the fixture post-calibration";
}

// ---- Step 0: can the input support a verdict? ---------------------------------------------

std::optional<std::string> why_fixture_unusable(const MachineConfig& m, Stage stage) {
  if (!m.fixture) {
    return detail::machine_where(m) + ": has no `fixture:` section; " +
           std::string(check_name(stage)) + " needs the fixture's geometry and configurations";
  }
  const FixtureConfig& f = *m.fixture;
  const std::string where = detail::machine_where(m) + ": fixture '" + f.fixture_id + "': ";
  if (f.columns() < 1) return where + "fixture.columns: no columns";
  if (f.rows() < 2) {
    return where + "fixture.rows: " + std::to_string(f.rows()) +
           " rows, the alternate-row configurations need at least 2";
  }
  const auto all_finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  if (!all_finite(f.column_home_x_mm)) return where + "fixture.columns: a home X is not finite";
  if (!all_finite(f.row_home_y_mm)) return where + "fixture.rows: a home Y is not finite";
  if (f.z_planes_mm.empty() || !all_finite(f.z_planes_mm)) {
    return where + "fixture.z_planes_mm: needs at least one finite plane";
  }
  if (!f.origin_mm.allFinite()) {
    return where + "fixture.origin_mm = " + format_vector(f.origin_mm) + " is not finite";
  }
  if (!(std::isfinite(f.block_size_mm) && f.block_size_mm > 0)) {
    return where + "fixture.reference_block.size_mm = " + format_number(f.block_size_mm) +
           " must be positive";
  }
  const PostCalibrationPattern& p = f.postcalibration;
  if (stage == Stage::Post &&
      (p.z_mm.empty() || p.y_offsets_mm.empty() || p.x_offsets_mm.empty() || !all_finite(p.z_mm) ||
       !all_finite(p.y_offsets_mm) || !all_finite(p.x_offsets_mm))) {
    return where + "fixture.postcalibration: z, y_offsets and x_offsets need finite values";
  }
  return std::nullopt;
}

// The tolerance of each delta axis: fixture_d<axis>_mm, else fixture_delta_mm.
struct AxisTolerances {
  Tolerance band[3];
  double half_width(int axis) const {
    return std::max((band[axis].upper - band[axis].lower) / 2, 1e-12);
  }
};

std::optional<std::string> read_tolerances(const MachineConfig& m, Stage stage,
                                           AxisTolerances* out) {
  const std::string_view per_axis[] = {kToleranceDx, kToleranceDy, kToleranceDz};
  for (int a = 0; a < 3; ++a) {
    const Tolerance* band = detail::find_tolerance(m, per_axis[a]);
    if (!band) band = detail::find_tolerance(m, kToleranceDelta);
    if (!band) {
      return detail::machine_where(m) + ": tolerances." + std::string(per_axis[a]) +
             " (or tolerances." + std::string(kToleranceDelta) + ") is not configured; " +
             std::string(check_name(stage)) + " judges the " + kAxisLower[a] + " deltas with it";
    }
    out->band[a] = *band;
  }
  return std::nullopt;
}

// fixture_configuration of the set's parameters: std::nullopt when absent; `error` set when
// present but not an integer in 0 .. 2n-1.
std::optional<int> read_configuration(const MeasurementSet& set, const FixtureConfig& f,
                                      std::string* error) {
  const NamedValue* value = find_value(set.parameters, kConfigurationParameter);
  if (!value) return std::nullopt;
  const int count = f.precalibration_configuration_count();
  const double k = value->value;
  if (!std::isfinite(k) || k != std::floor(k) || k < 0 || k > count - 1) {
    *error = "MeasurementSet.parameters['" + std::string(kConfigurationParameter) +
             "'] = " + format_number(k) + " is not an integer in 0.." + std::to_string(count - 1) +
             " (the pre-calibration configurations of fixture '" + f.fixture_id + "')";
    return std::nullopt;
  }
  return static_cast<int>(k);
}

// The pogos each configuration places and the check expects probed, by configuration index
// (pre-calibration: only [k] is non-empty).
struct Expected {
  std::vector<std::vector<PogoPlacement>> configurations;
  RowSelection rows = RowSelection::All;
  std::optional<int> k;
  int configuration_count = 0;  // valid indices 0 .. count-1 in the features
};

// ---- Steps 1 to 3: touches to pogo positions ------------------------------------------------

constexpr int kFaceCount = 5;

// One expected pogo of one configuration and the face coordinates its touches measured.
struct ProbedPogo {
  int configuration = 0;
  PogoPlacement placement;
  double face_sum[kFaceCount] = {};  // coordinate of the face along its normal's axis
  int face_count[kFaceCount] = {};
};

int normal_axis(PogoFace face) {
  switch (face) {
    case PogoFace::XMinus:
    case PogoFace::XPlus: return 0;
    case PogoFace::YMinus:
    case PogoFace::YPlus: return 1;
    default: return 2;
  }
}

struct Probed {
  std::vector<ProbedPogo> pogos;  // in configuration order, then placement order
  std::map<std::pair<int, std::string>, std::size_t> index;
  std::string error;
};

Probed expected_pogos(const Expected& expected) {
  Probed probed;
  for (std::size_t j = 0; j < expected.configurations.size(); ++j) {
    for (const PogoPlacement& placement : expected.configurations[j]) {
      ProbedPogo pogo;
      pogo.configuration = static_cast<int>(j);
      pogo.placement = placement;
      probed.index[{pogo.configuration, placement.pogo}] = probed.pogos.size();
      probed.pogos.push_back(pogo);
    }
  }
  return probed;
}

// Checks every touch (finite, unit approach, head at home, a feature of this fixture and
// configuration, approach along the face's inward normal) and adds, for each, the face point
//   p = b + r u     (b the nominal ball centre, u the approach, r the nominal ball radius)
// along the face normal's axis to its pogo.
Probed read_touches(const MeasurementSet& set, const MachineConfig& m, const Expected& expected,
                    Stage stage) {
  const FixtureConfig& f = *m.fixture;
  Probed probed = expected_pogos(expected);
  if (set.touches.empty()) {
    probed.error = "MeasurementSet.touches is empty: " + std::string(check_name(stage)) +
                   " needs five touches (top, x-, x+, y-, y+) per probed pogo";
    return probed;
  }
  for (std::size_t i = 0; i < set.touches.size(); ++i) {
    const Touch& t = set.touches[i];
    if (auto why = detail::why_touch_not_finite(t, i)) {
      probed.error = *why;
      return probed;
    }
    if (!detail::head_at(t.axes, 0, 0)) {
      probed.error = detail::touch_field(i, "axes") + ": head at " + detail::describe_head(t.axes) +
                     "; the fixture is probed with the head at home (A = 0, C = 0)";
      return probed;
    }
    const std::string feature_field = detail::touch_field(i, "feature") + " = '" + t.feature + "'";
    const auto feature = parse_pogo_touch_feature(t.feature);
    if (!feature) {
      probed.error = feature_field +
                     ": expected 'pogo:<C#R#>:cfg<index>:<top|x-|x+|y-|y+>', e.g. "
                     "'pogo:C2R3:cfg4:x-'";
      return probed;
    }
    if (!fixture_has_pogo(f, feature->id)) {
      probed.error = feature_field + ": fixture '" + f.fixture_id + "' has no pogo " +
                     feature->pogo + " (C1R1 to C" + std::to_string(f.columns()) + "R" +
                     std::to_string(f.rows()) + ")";
      return probed;
    }
    if (stage == Stage::Pre && feature->configuration != *expected.k) {
      probed.error = feature_field + ": configuration " + std::to_string(feature->configuration) +
                     ", but the set is of pre-calibration configuration " +
                     std::to_string(*expected.k) + " (MeasurementSet.parameters['" +
                     std::string(kConfigurationParameter) + "'])";
      return probed;
    }
    if (feature->configuration >= expected.configuration_count) {
      probed.error = feature_field + ": configuration " + std::to_string(feature->configuration) +
                     " is not a post-calibration configuration of fixture '" + f.fixture_id +
                     "' (0.." + std::to_string(expected.configuration_count - 1) + ")";
      return probed;
    }
    const auto it = probed.index.find({feature->configuration, feature->pogo});
    if (it == probed.index.end()) {
      probed.error = feature_field + ": pogo " + feature->pogo + " is not probed in " +
                     std::string(check_name(stage)) + " configuration " +
                     std::to_string(feature->configuration) + " (" +
                     std::string(to_string(expected.rows)) + ")";
      return probed;
    }
    const Eigen::Vector3d inward = approach_direction(feature->face);
    if (t.approach.dot(inward) < 1 - detail::kUnitTolerance) {
      probed.error = detail::touch_field(i, "approach") + " = " + format_vector(t.approach) +
                     ": a '" + std::string(to_string(feature->face)) +
                     "' touch must approach along " + format_vector(inward);
      return probed;
    }
    // Steps 1 and 2: nominal ball centre, then the point of the face.
    const Eigen::Vector3d b = stylus_ball_centre(t.axes, m.probe);
    const Eigen::Vector3d p = detail::contact_point(b, t.approach, m.probe.ball_radius_mm);
    ProbedPogo& pogo = probed.pogos[it->second];
    const int face = static_cast<int>(feature->face);
    pogo.face_sum[face] += p[normal_axis(feature->face)];
    pogo.face_count[face] += 1;
  }
  // Every expected pogo needs all five faces.
  for (const ProbedPogo& pogo : probed.pogos) {
    for (PogoFace face : kPogoFaces) {
      if (pogo.face_count[static_cast<int>(face)] == 0) {
        probed.error = "MeasurementSet.touches: pogo " + pogo.placement.pogo + " of " +
                       std::string(check_name(stage)) + " configuration " +
                       std::to_string(pogo.configuration) + " has no '" +
                       std::string(to_string(face)) + "' touch (feature '" +
                       pogo_touch_feature(pogo.placement.pogo, pogo.configuration, face) + "')";
        return probed;
      }
    }
  }
  return probed;
}

double face_mean(const ProbedPogo& pogo, PogoFace face) {
  const int i = static_cast<int>(face);
  return pogo.face_sum[i] / pogo.face_count[i];
}

// Step 3 and 4: the measured position of each pogo and its delta against the command.
//   x = (x_{x-} + x_{x+}) / 2,  y = (y_{y-} + y_{y+}) / 2,  z = z_top      (machine frame)
//   delta = (x, y, z) - (origin + c)
// The side faces' mean does not depend on the ball radius (it enters both with opposite signs).
// Their distance, x_{x+} - x_{x-}, must be the block size: else the touches missed the block.
std::vector<PogoDelta> pogo_deltas(const Probed& probed, const FixtureConfig& f, Stage stage,
                                   std::string* error) {
  std::vector<PogoDelta> deltas;
  const double limit = std::min(kBlockSizeOffLimitMm, kBlockSizeOffLimitFraction * f.block_size_mm);
  for (const ProbedPogo& pogo : probed.pogos) {
    const double x_minus = face_mean(pogo, PogoFace::XMinus);
    const double x_plus = face_mean(pogo, PogoFace::XPlus);
    const double y_minus = face_mean(pogo, PogoFace::YMinus);
    const double y_plus = face_mean(pogo, PogoFace::YPlus);
    const struct {
      const char* faces;
      double size;
    } sizes[] = {{"'x-' and 'x+'", x_plus - x_minus}, {"'y-' and 'y+'", y_plus - y_minus}};
    for (const auto& s : sizes) {
      const double off = s.size - f.block_size_mm;
      if (!(std::abs(off) <= limit)) {
        *error = "MeasurementSet.touches: pogo " + pogo.placement.pogo + " of " +
                 std::string(check_name(stage)) + " configuration " +
                 std::to_string(pogo.configuration) + ": its " + s.faces + " faces are " +
                 format_number(s.size) + " mm apart, " + format_number(off) +
                 " mm from fixture.reference_block.size_mm = " + format_number(f.block_size_mm) +
                 " (limit " + format_number(limit) + " mm): the touches missed the reference block";
        return {};
      }
    }
    const Eigen::Vector3d measured((x_minus + x_plus) / 2, (y_minus + y_plus) / 2,
                                   face_mean(pogo, PogoFace::Top));
    deltas.push_back({pogo.placement.pogo, pogo.configuration, pogo.placement.commanded_mm,
                      measured - f.to_machine(pogo.placement.commanded_mm)});
  }
  return deltas;
}

// ---- Step 5: metrics and verdict ----------------------------------------------------------------

// Per pogo and axis, then the worst case of each axis (the signed delta of largest magnitude).
std::vector<Metric> delta_metrics(const std::vector<PogoDelta>& deltas, const AxisTolerances& tol,
                                  Stage stage) {
  std::vector<Metric> metrics;
  Eigen::Vector3d worst = Eigen::Vector3d::Zero();
  for (const PogoDelta& d : deltas) {
    for (int a = 0; a < 3; ++a) {
      const std::string name = stage == Stage::Pre ? pogo_metric_name(d.pogo, a)
                                                   : post_metric_name(d.configuration, d.pogo, a);
      metrics.push_back(detail::judged_metric(name, d.delta_mm[a], "mm", tol.band[a]));
      if (!(std::abs(d.delta_mm[a]) <= std::abs(worst[a]))) worst[a] = d.delta_mm[a];
    }
  }
  const std::string_view worst_names[] = {kMaxDx, kMaxDy, kMaxDz};
  for (int a = 0; a < 3; ++a) {
    metrics.push_back(detail::judged_metric(worst_names[a], worst[a], "mm", tol.band[a]));
  }
  return metrics;
}

// "n of N metrics out of tolerance: <first few>; and m more"
std::string out_of_band_summary(const std::vector<Metric>& metrics) {
  std::vector<const Metric*> out;
  for (const Metric& metric : metrics) {
    if (!metric.pass) out.push_back(&metric);
  }
  if (out.empty()) return "";
  std::string text = std::to_string(out.size()) + " of " + std::to_string(metrics.size()) +
                     " metrics out of tolerance: ";
  for (std::size_t i = 0; i < out.size() && i < kReasonListLimit; ++i) {
    text += (i ? "; " : "") + detail::describe_out_of_band(*out[i]);
  }
  if (out.size() > kReasonListLimit) {
    text += "; and " + std::to_string(out.size() - kReasonListLimit) + " more";
  }
  return text;
}

// The zero offsets: every probed pogo's delta along each axis, "C2R3.dx" = delta_x (mm).
Correction zero_offsets(const std::vector<PogoDelta>& deltas, const FixtureConfig& f) {
  Correction correction;
  correction.target = std::string(kZeroOffsetsTargetPrefix) + f.fixture_id;
  for (const PogoDelta& d : deltas) {
    for (int a = 0; a < 3; ++a) {
      correction.offsets.push_back(NamedValue{zero_offset_name(d.pogo, a), d.delta_mm[a], "mm"});
    }
  }
  return correction;
}

// ---- Step 6 (post-calibration): what the deltas' pattern says ---------------------------------

struct Evidence {
  bool significant = false;
  double ratio = 0;  // largest significant effect / tolerance half-width
  std::vector<std::string> terms;
};

struct Diagnosis {
  Evidence misalignment;
  Evidence nonlinearity;
  std::string text;
};

std::string slope_text(const FixtureDeltaFit& fit, int i, int j) {
  const double v = fit.slope(i, j) * 1e6;
  return std::string("d") + kAxisLower[i] + "/d" + kAxisUpper[j] + " " + format_number(v) +
         (i == j ? " ppm" : " urad") + " (+-" +
         format_number(fit.slope_standard_error(i, j) * 1e6) + ")";
}

// Judges the fit: a slope M(i, j) matters when its effect over the probed travel of axis j,
// |M(i, j)| span_j, reaches kSignificantFractionOfTolerance of the tolerance half-width of delta
// axis i and |M(i, j)| >= kSignificantSigmas standard errors; off the diagonal it is a
// misalignment, on it a scale error (nonlinearity). A residual shared by the points at one
// commanded coordinate (systematic_fraction >= kSystematicFraction) as large as that fraction of
// the tolerance is a nonlinearity (curvature over travel).
Diagnosis diagnose(const FixtureDeltaFit& fit, const AxisTolerances& tol) {
  Diagnosis d;
  std::string text =
      "fit of the deltas against the commanded positions (common slopes, one "
      "intercept per pogo; " +
      std::to_string(fit.points) + " points, " + std::to_string(fit.pogos) + " pogos): ";
  if (!fit.error.empty()) {
    d.text = text + fit.error;
    return d;
  }
  std::string slopes;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (!fit.fitted[j]) continue;
      slopes += (slopes.empty() ? "" : ", ") + slope_text(fit, i, j);
      const double effect = std::abs(fit.slope(i, j)) * fit.span_mm[j];
      const double half = tol.half_width(i);
      const bool significant =
          effect >= kSignificantFractionOfTolerance * half &&
          std::abs(fit.slope(i, j)) >= kSignificantSigmas * fit.slope_standard_error(i, j);
      if (!significant) continue;
      Evidence& e = i == j ? d.nonlinearity : d.misalignment;
      e.significant = true;
      e.ratio = std::max(e.ratio, effect / half);
      e.terms.push_back(std::string("d") + kAxisLower[i] + "/d" + kAxisUpper[j] + " = " +
                        format_number(fit.slope(i, j) * 1e6) + (i == j ? " ppm" : " urad") +
                        " moves d" + kAxisLower[i] + " by " + format_number(effect) +
                        " mm over the " + format_number(fit.span_mm[j]) + " mm of " +
                        kAxisUpper[j] + " travel probed (" + (i == j ? "scale" : "misalignment") +
                        ")");
    }
  }
  text += "slopes " + (slopes.empty() ? std::string("none (no commanded axis varied)") : slopes);
  std::string residuals;
  for (int i = 0; i < 3; ++i) {
    residuals += (i ? ", d" : "; residual rms d") + std::string(kAxisLower[i]) + " " +
                 format_number(fit.residual_rms_mm[i]) + " mm";
    if (fit.systematic_axis[i] >= 0) {
      residuals += " (" + format_number(fit.systematic_residual_mm[i]) + " mm shared along " +
                   kAxisUpper[fit.systematic_axis[i]] + ", " +
                   format_number(100 * fit.systematic_fraction[i]) + " %)";
    }
    const double half = tol.half_width(i);
    if (fit.systematic_fraction[i] >= kSystematicFraction &&
        fit.systematic_residual_mm[i] >= kSignificantFractionOfTolerance * half) {
      d.nonlinearity.significant = true;
      d.nonlinearity.ratio = std::max(d.nonlinearity.ratio, fit.systematic_residual_mm[i] / half);
      d.nonlinearity.terms.push_back(
          std::string("a residual of ") + format_number(fit.systematic_residual_mm[i]) +
          " mm in d" + kAxisLower[i] + " follows the commanded " +
          kAxisUpper[fit.systematic_axis[i]] + " (curvature over travel)");
    }
  }
  text += residuals;
  std::string significant;
  for (const Evidence* e : {&d.misalignment, &d.nonlinearity}) {
    for (const auto& term : e->terms) significant += (significant.empty() ? "" : "; ") + term;
  }
  text += "; " + (significant.empty() ? std::string("no significant slope or systematic residual")
                                      : "significant: " + significant);
  d.text = text;
  return d;
}

// Misalignment first when its evidence is significant and at least as large, relative to the
// tolerance, as the nonlinearity's; nonlinearity first when significant; otherwise what is left
// is scattered per-pogo error: wear.
std::vector<std::string> postcalibration_causes(const Diagnosis& d) {
  const std::string mis(kCauseMisaligned), non(kCauseNonlinear), wear(kCauseWear);
  if (d.misalignment.significant &&
      (!d.nonlinearity.significant || d.misalignment.ratio >= d.nonlinearity.ratio)) {
    return {mis, non, wear};
  }
  if (d.nonlinearity.significant) return {non, mis, wear};
  return {wear, non, mis};
}

// The fit's values as metrics, for those the machine config has a tolerance of.
void add_configured_fit_metrics(const FixtureDeltaFit& fit, const MachineConfig& m,
                                std::vector<Metric>* metrics) {
  if (!fit.error.empty()) return;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (!fit.fitted[j]) continue;
      const std::string name = fit_metric_name(i, j);
      if (const Tolerance* band = detail::find_tolerance(m, name)) {
        metrics->push_back(
            detail::judged_metric(name, fit.slope(i, j) * 1e6, i == j ? "ppm" : "urad", *band));
      }
    }
  }
  if (const Tolerance* band = detail::find_tolerance(m, kSystematicResidual)) {
    metrics->push_back(detail::judged_metric(kSystematicResidual,
                                             fit.systematic_residual_mm.maxCoeff(), "mm", *band));
  }
  if (const Tolerance* band = detail::find_tolerance(m, kScatterRms)) {
    metrics->push_back(
        detail::judged_metric(kScatterRms, fit.residual_rms_mm.maxCoeff(), "mm", *band));
  }
}

// ---- The common front of both checks ------------------------------------------------------------

struct Measured {
  std::string error;
  AxisTolerances tolerances;
  Expected expected;
  std::vector<PogoDelta> deltas;
};

Measured measure(const MeasurementSet& set, const MachineConfig& machine, Stage stage) {
  Measured out;
  const CheckKind kind =
      stage == Stage::Pre ? CheckKind::FixturePreCalibration : CheckKind::FixturePostCalibration;
  if (auto why = detail::why_not_a_set_of(set, kind, check_name(stage))) {
    out.error = *why;
    return out;
  }
  if (auto why = why_fixture_unusable(machine, stage)) {
    out.error = *why;
    return out;
  }
  if (auto why = detail::why_probe_unusable(machine)) {
    out.error = *why;
    return out;
  }
  if (auto why = read_tolerances(machine, stage, &out.tolerances)) {
    out.error = *why;
    return out;
  }
  const FixtureConfig& f = *machine.fixture;
  Expected& expected = out.expected;
  expected.k = read_configuration(set, f, &out.error);
  if (!out.error.empty()) return out;
  if (stage == Stage::Pre) {
    if (!expected.k) {
      out.error = "MeasurementSet.parameters: no '" + std::string(kConfigurationParameter) +
                  "'; the fixture pre-calibration needs the configuration probed (0.." +
                  std::to_string(f.precalibration_configuration_count() - 1) + ")";
      return out;
    }
    expected.rows = precalibration_rows(f, *expected.k);
    expected.configurations.assign(static_cast<std::size_t>(*expected.k), {});
    expected.configurations.push_back(precalibration_configuration(f, *expected.k));
    expected.configuration_count = f.precalibration_configuration_count();
  } else {
    expected.rows = expected.k ? precalibration_rows(f, *expected.k) : RowSelection::All;
    expected.configurations = postcalibration_configurations(f, expected.rows);
    expected.configuration_count = f.postcalibration_configuration_count();
  }
  const Probed probed = read_touches(set, machine, expected, stage);
  if (!probed.error.empty()) {
    out.error = probed.error;
    return out;
  }
  out.deltas = pogo_deltas(probed, f, stage, &out.error);
  return out;
}

}  // namespace

// ---- The checks ---------------------------------------------------------------------------------

CheckResult check_fixture_precalibration(const MeasurementSet& set, const MachineConfig& machine) {
  CheckResult result = detail::result_for(set);

  // Steps 0 to 4: validated touches to deltas measured - commanded.
  const Measured measured = measure(set, machine, Stage::Pre);
  if (!measured.error.empty()) return detail::invalid(result, measured.error);

  // Step 5: judge every delta; PASS when all are within limits of zero.
  result.metrics = delta_metrics(measured.deltas, measured.tolerances, Stage::Pre);
  const std::string out_of_band = out_of_band_summary(result.metrics);
  if (out_of_band.empty()) {
    result.verdict = Verdict::Pass;
    return result;
  }
  // Otherwise the deltas become zero offsets in the fixture's control unit.
  const FixtureConfig& f = *machine.fixture;
  result.verdict = Verdict::Fail;
  result.correction = zero_offsets(measured.deltas, f);
  result.likely_causes = {std::string(kCauseZeroDrift)};
  result.reason = out_of_band + ". The deltas of the " + std::to_string(measured.deltas.size()) +
                  " pogos of configuration " + std::to_string(*measured.expected.k) +
                  " are issued as zero offsets to " + result.correction->target +
                  "; a post-calibration must confirm them";
  return result;
}

CheckResult check_fixture_postcalibration(const MeasurementSet& set, const MachineConfig& machine) {
  CheckResult result = detail::result_for(set);

  // Steps 0 to 4: validated touches to deltas measured - commanded, every configuration.
  const Measured measured = measure(set, machine, Stage::Post);
  if (!measured.error.empty()) return detail::invalid(result, measured.error);

  // Step 5: judge every delta of every configuration.
  result.metrics = delta_metrics(measured.deltas, measured.tolerances, Stage::Post);

  // Step 6: fit the deltas against the commanded positions.
  const FixtureDeltaFit fit = fit_fixture_deltas(measured.deltas);
  add_configured_fit_metrics(fit, machine, &result.metrics);

  const std::string out_of_band = out_of_band_summary(result.metrics);
  if (out_of_band.empty()) {
    result.verdict = Verdict::Pass;
    return result;
  }
  // The zero offsets do not hold across the working volume: a physical intervention, the
  // likely causes ordered by what the fit says.
  const Diagnosis diagnosis = diagnose(fit, measured.tolerances);
  result.verdict = Verdict::Fail;
  result.likely_causes = postcalibration_causes(diagnosis);
  result.reason = out_of_band + ". " + diagnosis.text;
  return result;
}

}  // namespace ncqual::solver
