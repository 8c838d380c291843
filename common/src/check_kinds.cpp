// SPDX-License-Identifier: Apache-2.0
#include "ncqual/common/check_kinds.hpp"

#include "ncqual/common/enum_names.hpp"

#include <algorithm>

namespace ncqual {
namespace {

using K = CheckKind;
using C = Cadence;
using I = Instrument;
using N = Needs;

// One row per kind, in CheckKind order (check_kinds() verifies the order once).
std::array<CheckKindInfo, kCheckKindCount> make_table() {
  // One row per kind reads as a table: clang-format keeps its hands off.
  // clang-format off
  return {{
      {K::MonumentCAlignment, "monument_c_alignment", "daily 1: probe alignment with the C axis",
       C::Daily, I::TouchProbe, N::Monument, 8, std::nullopt, std::nullopt,
       {"c_align_dx_mm", "c_align_dy_mm", "probe_c_offset_mm", "c_align_consistency_mm"}},
      {K::MonumentToolLength, "monument_tool_length", "daily 2: composite tool length",
       C::Daily, I::TouchProbe, N::Monument, 4, std::nullopt, std::nullopt,
       {"tool_length_error_mm", "tool_length_mm"}},
      {K::MonumentPositioning, "monument_positioning",
       "daily 3: repeatable X, Y, Z positioning against the monument", C::Daily, I::TouchProbe,
       N::Monument, 6, std::nullopt, std::nullopt,
       {"center_dx_mm", "center_dy_mm", "face_dz_mm", "hole_diameter_error_mm"}},
      {K::MonumentCRotation, "monument_c_rotation", "daily 4: C-axis rotational accuracy",
       C::Daily, I::TouchProbe, N::Monument, 8, std::nullopt, std::nullopt,
       {"c_angle_error_arcsec"}},
      {K::FixturePreCalibration, "fixture_precal", "weekly: fixture pre-calibration",
       C::Weekly, I::FixtureProbe, N::Fixture, 25, std::nullopt, std::nullopt,
       {"fixture_dx_mm", "fixture_dy_mm", "fixture_dz_mm", "fixture_delta_mm"}},
      {K::FixturePostCalibration, "fixture_postcal",
       "weekly: fixture post-calibration of the zero offsets", C::AfterCorrection,
       I::FixtureProbe, N::Fixture, 60, K::FixturePreCalibration, K::FixturePreCalibration,
       {"fixture_dx_mm", "fixture_dy_mm", "fixture_dz_mm", "fixture_delta_mm",
        "fixture_fit_dx_per_x_ppm", "fixture_fit_dx_per_y_urad", "fixture_fit_dx_per_z_urad",
        "fixture_fit_dy_per_x_urad", "fixture_fit_dy_per_y_ppm", "fixture_fit_dy_per_z_urad",
        "fixture_fit_dz_per_x_urad", "fixture_fit_dz_per_y_urad", "fixture_fit_dz_per_z_ppm",
        "fixture_fit_systematic_residual_mm", "fixture_fit_scatter_rms_mm"}},
      {K::PartSetPoints, "part_setpoints", "per part: primary and secondary set points",
       C::PerPart, I::TouchProbe, N::SetPoints, 5, std::nullopt, std::nullopt,
       {"setpoint_max_dev_mm"}},
      {K::GlobalMasterFrame, "global_master_frame", "monthly: master frame from the X and Y runs",
       C::Monthly, I::LaserTracker, N::GlobalCheck, 20, std::nullopt, std::nullopt,
       {"master_orthogonality_urad", "master_x_straightness_mm", "master_y_straightness_mm"}},
      {K::GlobalGrid, "global_grid", "monthly: positioning over the working envelope (grid)",
       C::Monthly, I::LaserTracker, N::GlobalCheck, 90, std::nullopt, std::nullopt,
       {"grid_max_deviation_mm", "grid_rms_deviation_mm", "grid_squareness_xy_urad",
        "grid_squareness_yz_urad", "grid_squareness_zx_urad", "grid_scale_x_um_per_m",
        "grid_scale_y_um_per_m", "grid_scale_z_um_per_m", "volumetric_residual_after_mm"}},
      {K::RotaryW, "rotary_w", "monthly: W axis with X, Y, Z held", C::Monthly, I::LaserTracker,
       N::GlobalCheck, 20, std::nullopt, std::nullopt,
       {"w_scale_um_per_m", "w_misalignment_urad", "w_straightness_mm"}},
      {K::RotaryA, "rotary_a", "monthly: A axis with X, Y, Z held", C::Monthly, I::LaserTracker,
       N::GlobalCheck, 20, std::nullopt, std::nullopt,
       {"a_dA_mean_arcsec", "a_dA_range_arcsec", "a_dR_max_mm", "a_axis_tilt_urad"}},
      {K::RotaryC, "rotary_c", "monthly: C axis with X, Y, Z held", C::Monthly, I::LaserTracker,
       N::GlobalCheck, 20, std::nullopt, std::nullopt,
       {"c_dA_mean_arcsec", "c_dA_range_arcsec", "c_dR_max_mm", "c_axis_tilt_urad"}},
      {K::CircleXY, "circle_xy", "monthly: circular test in XY (ISO 230-4)", C::Monthly,
       I::LaserTracker, N::GlobalCheck, 15, std::nullopt, std::nullopt,
       {"circle_xy_G_mm", "circle_xy_H_mm"}},
      {K::CircleYZ, "circle_yz", "monthly: circular test in YZ (ISO 230-4)", C::Monthly,
       I::LaserTracker, N::GlobalCheck, 15, std::nullopt, std::nullopt,
       {"circle_yz_G_mm", "circle_yz_H_mm"}},
      {K::CircleXZ, "circle_xz", "monthly: circular test in XZ (ISO 230-4)", C::Monthly,
       I::LaserTracker, N::GlobalCheck, 15, std::nullopt, std::nullopt,
       {"circle_xz_G_mm", "circle_xz_H_mm"}},
      {K::LinearAxisRun, "linear_axis_run", "monthly: linear positioning along X (ISO 230-2)",
       C::Monthly, I::LaserTracker, N::GlobalCheck, 45, std::nullopt, std::nullopt,
       {"linear_A_mm", "linear_E_mm", "linear_R_mm", "linear_B_mm"}},
  }};
  // clang-format on
}

const std::array<CheckKindInfo, kCheckKindCount>& table() {
  static const std::array<CheckKindInfo, kCheckKindCount> rows = [] {
    auto t = make_table();
    for (int i = 0; i < kCheckKindCount; ++i) {
      if (static_cast<int>(t[static_cast<std::size_t>(i)].kind) != i) std::terminate();
    }
    return t;
  }();
  return rows;
}

}  // namespace

std::string_view to_string(Cadence cadence) {
  constexpr std::array<std::string_view, 5> kNames = {"monthly", "weekly", "daily", "per part",
                                                      "after correction"};
  return name_of(kNames, cadence);
}

std::string_view to_string(Instrument instrument) {
  constexpr std::array<std::string_view, 3> kNames = {"touch probe", "fixture probe",
                                                      "laser tracker"};
  return name_of(kNames, instrument);
}

std::string_view to_string(Needs needs) {
  constexpr std::array<std::string_view, 4> kNames = {"monument", "set points", "fixture",
                                                      "global check"};
  return name_of(kNames, needs);
}

const std::array<CheckKindInfo, kCheckKindCount>& check_kinds() { return table(); }

const CheckKindInfo& check_kind_info(CheckKind kind) {
  return table().at(static_cast<std::size_t>(kind));
}

std::vector<CheckKind> kinds_passing(CheckKind kind) {
  std::vector<CheckKind> out{kind};
  for (const auto& row : table()) {
    if (row.satisfies == kind) out.push_back(row.kind);
  }
  return out;
}

std::optional<CheckKind> verified_by(CheckKind kind) {
  for (const auto& row : table()) {
    if (row.satisfies == kind && row.cadence == Cadence::AfterCorrection) return row.kind;
  }
  return std::nullopt;
}

CheckKind rerun_after_intervention(CheckKind held) {
  return check_kind_info(held).rerun_after_intervention.value_or(held);
}

bool intervention_matches(CheckKind named, CheckKind held) {
  return named == held || named == rerun_after_intervention(held);
}

bool is_tracker_check(CheckKind kind) {
  return check_kind_info(kind).instrument == Instrument::LaserTracker;
}

bool is_fixture_check(CheckKind kind) {
  return check_kind_info(kind).instrument == Instrument::FixtureProbe;
}

CompensationKind compensation_kind(std::string_view target) {
  const auto starts = [&](std::string_view prefix) {
    return target.substr(0, prefix.size()) == prefix;
  };
  if (starts(kWorkOffsetTargetPrefix)) return CompensationKind::WorkOffset;
  if (starts(kZeroOffsetsTargetPrefix)) return CompensationKind::ZeroOffsets;
  if (starts(kVolumetricTargetPrefix)) return CompensationKind::Volumetric;
  return CompensationKind::Other;
}

std::string_view to_string(CompensationKind kind) {
  constexpr std::array<std::string_view, 4> kNames = {"work offset", "fixture zero offsets",
                                                      "volumetric compensation", "compensation"};
  return name_of(kNames, kind);
}

const std::vector<RestartRow>& restart_rule() {
  using CK = CompensationKind;
  // clang-format off
  static const std::vector<RestartRow> rows = {
      {std::nullopt, true, {}, std::nullopt, {},
       "an intervention records the held check it answers and a note, not what was touched: it "
       "restarts every series of its machine"},
      {CK::WorkOffset, false, {}, std::nullopt, {},
       "the work offset of the part just measured: the next part's set points are measured from "
       "nominal again, so it restarts no series"},
      {CK::ZeroOffsets, false, {K::FixturePreCalibration, K::FixturePostCalibration},
       std::nullopt, {},
       "moves where the fixture's control puts its pogos: the fixture checks' series, not the "
       "monument's, the tracker's or the part's"},
      {CK::Volumetric, false,
       {K::GlobalMasterFrame, K::GlobalGrid, K::CircleXY, K::CircleYZ, K::CircleXZ,
        K::LinearAxisRun},
       K::FixturePostCalibration,
       {"fixture_fit_dx_per_x_ppm", "fixture_fit_dx_per_y_urad", "fixture_fit_dx_per_z_urad",
        "fixture_fit_dy_per_x_urad", "fixture_fit_dy_per_y_ppm", "fixture_fit_dy_per_z_urad",
        "fixture_fit_dz_per_x_urad", "fixture_fit_dz_per_y_urad", "fixture_fit_dz_per_z_ppm",
        "fixture_fit_systematic_residual_mm"},
       "corrects the shape of X, Y and Z over the volume (scale, straightness, angular and "
       "squareness errors; the tracker's placement, a rigid shift, is fitted out of it): the "
       "series of the checks that move X, Y, Z over the volume and the fixture fit's scale, "
       "angle and systematic terms; not the monument checks (a drift of the machine against "
       "its monument, the probe, the tool length, the C axis), the rotary checks with X, Y, Z "
       "held, the pogo deltas, the fit's scatter or the part's set points"},
      {CK::Other, true, {}, std::nullopt, {},
       "a target ncqual does not know: nobody can say what it touched, so every series"},
  };
  // clang-format on
  return rows;
}

bool restarts_series(std::optional<CompensationKind> compensation, CheckKind series,
                     std::string_view metric) {
  for (const RestartRow& row : restart_rule()) {
    if (row.compensation != compensation) continue;
    return row.everything ||
           std::find(row.kinds.begin(), row.kinds.end(), series) != row.kinds.end() ||
           (row.metric_kind == series &&
            std::find(row.metrics.begin(), row.metrics.end(), metric) != row.metrics.end());
  }
  return true;  // not reached: every kind has its row
}

bool is_tolerance_key(std::string_view key) {
  return std::any_of(table().begin(), table().end(), [&](const CheckKindInfo& row) {
    return std::find(row.tolerances.begin(), row.tolerances.end(), key) != row.tolerances.end();
  });
}

}  // namespace ncqual
