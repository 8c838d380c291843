// SPDX-License-Identifier: Apache-2.0
// The monthly tracker checks: sort the labelled points of a set, evaluate them with the pure
// evaluations, judge the figures against the machine's tolerances, rank the likely causes.
#include "ncqual/solver/global_checks.hpp"

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/global_check.hpp"
#include "ncqual/common/kinematics.hpp"
#include "ncqual/solver/circle_fit.hpp"
#include "ncqual/solver/circular_test.hpp"
#include "ncqual/solver/global_grid.hpp"
#include "ncqual/solver/iso230_2.hpp"
#include "ncqual/solver/master_frame.hpp"
#include "ncqual/solver/rotary_axes.hpp"
#include "ncqual/solver/volumetric_identification.hpp"
#include "ncqual/common/text.hpp"
#include "ncqual/common/units.hpp"
#include "result_building.hpp"
#include "touch_input.hpp"

#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ncqual::solver {
namespace {

using detail::format_number;
using detail::machine_where;

// The identification weighs every tracker point alike; the figure only scales the reported
// chi-square, not the estimates.
constexpr double kAssumedPointSigmaMm = 0.01;

// A tracker point with its label taken apart: "<group>:<index>[:t<k>]", or for the linear run
// "run:<cycle>:<up|down>:<index>".
struct LabelledPoint {
  std::string group;  // x_run, y_run, grid, c, a, w, ccw, cw, run
  int index = 0;
  int target = 0;
  int cycle = 0;   // run only
  bool up = true;  // run only
  const TrackerPoint* point = nullptr;
  std::size_t position = 0;  // in set.tracker_points
};

std::string point_field(std::size_t i, const std::string& field) {
  return "MeasurementSet.tracker_points[" + std::to_string(i) + "]." + field;
}

bool parse_int(const std::string& text, int* out) {
  if (text.empty() || text.size() > 6) return false;
  for (char ch : text) {
    if (ch < '0' || ch > '9') return false;
  }
  *out = std::stoi(text);
  return true;
}

// Every point labelled as the programs label them, finite, with a configured target; else why not.
std::optional<std::string> sort_points(const MeasurementSet& set, const GlobalCheckConfig& gc,
                                       std::vector<LabelledPoint>* out) {
  std::map<std::string, std::size_t> seen;
  for (std::size_t i = 0; i < set.tracker_points.size(); ++i) {
    const TrackerPoint& p = set.tracker_points[i];
    const AxisPosition& c = p.commanded;
    for (double v : {c.x_mm, c.y_mm, c.z_mm, c.w_mm, c.a_rad, c.c_rad}) {
      if (!std::isfinite(v)) {
        return point_field(i, "commanded") + " has a non-finite axis (" + format_number(v) + ")";
      }
    }
    if (!p.measured_mm.allFinite()) {
      return point_field(i, "measured_mm") + " = " + detail::format_vector(p.measured_mm) +
             " is not finite";
    }
    if (auto [it, fresh] = seen.emplace(p.label, i); !fresh) {
      return point_field(i, "label") + " = '" + p.label + "' repeats tracker_points[" +
             std::to_string(it->second) + "]";
    }
    const std::vector<std::string> parts = split_at(p.label, ':');
    LabelledPoint lp;
    lp.group = parts[0];
    lp.point = &p;
    lp.position = i;
    bool ok = false;
    if (lp.group == "run") {
      ok = parts.size() == 4 && parse_int(parts[1], &lp.cycle) && lp.cycle >= 1 &&
           (parts[2] == "up" || parts[2] == "down") && parse_int(parts[3], &lp.index);
      lp.up = ok && parts[2] == "up";
    } else if (lp.group == "x_run" || lp.group == "y_run" || lp.group == "grid" ||
               lp.group == "c" || lp.group == "a" || lp.group == "w" || lp.group == "ccw" ||
               lp.group == "cw") {
      ok = (parts.size() == 2 || parts.size() == 3) && parse_int(parts[1], &lp.index);
      if (ok && parts.size() == 3) {
        ok = parts[2].size() > 1 && parts[2][0] == 't' && parse_int(parts[2].substr(1), &lp.target);
      }
    }
    if (!ok) {
      return point_field(i, "label") + " = '" + p.label +
             "' is not a label of the monthly programs (x_run:<i>, y_run:<i>, grid:<i>:t<k>, "
             "c:<i>, a:<i>, w:<i>, ccw:<i>, cw:<i>, run:<cycle>:<up|down>:<i>)";
    }
    if (lp.target >= static_cast<int>(gc.targets.size())) {
      return point_field(i, "label") + " = '" + p.label + "' names target " +
             std::to_string(lp.target) + " but global_check.targets has " +
             std::to_string(gc.targets.size());
    }
    out->push_back(lp);
  }
  return std::nullopt;
}

Eigen::Vector3d commanded_target(const LabelledPoint& p, const GlobalCheckConfig& gc) {
  return stylus_ball_centre(p.point->commanded, gc.targets[static_cast<std::size_t>(p.target)]);
}

FramePoint frame_point(const LabelledPoint& p, const GlobalCheckConfig& gc) {
  return {p.point->label, commanded_target(p, gc), p.point->measured_mm};
}

std::vector<FramePoint> group(const std::vector<LabelledPoint>& points, const std::string& name,
                              const GlobalCheckConfig& gc, int target = 0) {
  std::vector<FramePoint> out;
  for (const auto& p : points) {
    if (p.group == name && p.target == target) out.push_back(frame_point(p, gc));
  }
  return out;
}

// Step 0 of every tracker check: a set of this kind from the tracker, a machine with a
// global_check section and the tolerances, points sorted. Returns the reason when unusable.
std::optional<std::string> prepare(const MeasurementSet& set, const MachineConfig& machine,
                                   const std::vector<std::string_view>& metrics,
                                   std::string_view check, std::vector<LabelledPoint>* points) {
  if (auto why = detail::why_not_a_set_of(set, set.kind, check)) return why;
  if (!machine.global_check) {
    return machine_where(machine) +
           " has no global_check: section: the targets of its tracker "
           "check " +
           std::string(to_string(set.kind)) + " are unknown";
  }
  if (auto why = detail::why_tolerances_missing(machine, metrics, check)) return why;
  if (set.tracker_points.empty()) {
    return "MeasurementSet.tracker_points is empty: " + std::string(check) +
           " needs the tracker's readings";
  }
  return sort_points(set, *machine.global_check, points);
}

void add(CheckResult& r, const MachineConfig& m, const std::string& name, double value,
         const std::string& unit) {
  r.metrics.push_back(detail::judged_metric(name, value, unit, *detail::find_tolerance(m, name)));
}

bool failed(const CheckResult& r, const std::string& name) {
  const Metric* m = find_metric(r, name);
  return m && !m->pass;
}

// The master frame of the set's own runs; std::nullopt and `why` when they cannot make one.
std::optional<MasterFrame> master_frame_of(const std::vector<LabelledPoint>& points,
                                           const GlobalCheckConfig& gc, std::string* why) {
  try {
    return fit_master_frame(group(points, "x_run", gc), group(points, "y_run", gc));
  } catch (const std::invalid_argument& e) {
    *why = std::string("master frame: ") + e.what();
    return std::nullopt;
  }
}

// The grid of the main target in the master frame of the set's own runs; else why not.
std::optional<std::string> grid_of(const std::vector<LabelledPoint>& points,
                                   const GlobalCheckConfig& gc, GlobalGridEvaluation* out) {
  std::string why;
  const auto frame = master_frame_of(points, gc, &why);
  if (!frame) return why;
  try {
    out->grid = analyze_grid(*frame, group(points, "grid", gc, 0));
  } catch (const std::invalid_argument& e) {
    return std::string("grid: ") + e.what();
  }
  out->frame = *frame;
  return std::nullopt;
}

Plane plane_of(CheckKind kind) {
  return kind == CheckKind::CircleXY   ? Plane::XY
         : kind == CheckKind::CircleYZ ? Plane::YZ
                                       : Plane::XZ;
}

// The circular test of a circle set, evaluated; else why not (`check` names it).
std::optional<std::string> circle_of(const MeasurementSet& set,
                                     const std::vector<LabelledPoint>& points,
                                     const GlobalCheckConfig& gc, const std::string& check,
                                     CircleEvaluation* out) {
  const Plane plane = plane_of(set.kind);
  const int u = plane == Plane::YZ ? 1 : 0;
  const int v = plane == Plane::XY ? 1 : 2;
  // An imported export (`ncqual import circle`) is already in the machine's axes and carries its
  // own reference; a tracker measurement is put in the master frame of its runs.
  const bool imported = find_value(set.parameters, "imported") != nullptr;
  Eigen::Isometry3d to_master = Eigen::Isometry3d::Identity();
  if (!imported) {
    std::string why;
    const auto frame = master_frame_of(points, gc, &why);
    if (!frame) return why;
    to_master = frame->instrument_to_master;
  }
  CircularTestInput& input = out->input;
  input.plane = plane;
  for (const auto& lp : points) {
    if (lp.group != "ccw" && lp.group != "cw") continue;
    const Eigen::Vector3d m = to_master * lp.point->measured_mm;
    input.points.push_back(
        {Eigen::Vector2d(m[u], m[v]), lp.group == "ccw" ? PathDirection::Ccw : PathDirection::Cw});
  }
  AxisPosition centre;
  centre.x_mm = gc.circle.centre_mm.x();
  centre.y_mm = gc.circle.centre_mm.y();
  centre.z_mm = gc.circle.centre_mm.z();
  const Eigen::Vector3d c = stylus_ball_centre(centre, gc.targets.front());
  if (!imported) {
    input.nominal_centre_mm = Eigen::Vector2d(c[u], c[v]);
    input.nominal_radius_mm = gc.circle.radius_mm;
  } else {
    const NamedValue* r0 = find_value(set.parameters, "nominal_radius_mm");
    const NamedValue* cu = find_value(set.parameters, "centre_u_mm");
    const NamedValue* cv = find_value(set.parameters, "centre_v_mm");
    if (r0) input.nominal_radius_mm = r0->value;
    if (cu && cv) input.nominal_centre_mm = Eigen::Vector2d(c[u] + cu->value, c[v] + cv->value);
  }
  try {
    out->result = evaluate_circular_test(input);
  } catch (const std::invalid_argument& e) {
    return check + ": " + e.what();
  }
  return std::nullopt;
}

// The ISO 230-2 evaluation of a linear axis run; else why not.
std::optional<std::string> linear_run_of(const MeasurementSet& set,
                                         const std::vector<LabelledPoint>& points,
                                         const GlobalCheckConfig& gc, LinearRunEvaluation* out) {
  // The run's axis: the configured one, or the request's parameter `axis` (0, 1, 2) of an import.
  int axis = gc.linear_run.axis;
  if (const NamedValue* a = find_value(set.parameters, "axis")) {
    if (!(a->value == 0 || a->value == 1 || a->value == 2)) {
      return "MeasurementSet.parameters axis = " + format_number(a->value) +
             ": expected 0, 1 or 2 (X, Y, Z)";
    }
    axis = static_cast<int>(a->value);
  }
  out->axis = axis;
  // The position along the axis: the measured points projected on the run's best-fit line,
  // oriented and zeroed like the commanded coordinate (ISO 230-2 figures are differences, so the
  // zero does not matter; the orientation does).
  std::vector<const LabelledPoint*> run_points;
  for (const auto& p : points) {
    if (p.group == "run") run_points.push_back(&p);
  }
  if (run_points.size() < 4) {
    return "the linear axis run has " + std::to_string(run_points.size()) +
           " run:<cycle>:<up|down>:<i> points; it needs at least 2 targets x 2 cycles";
  }
  std::vector<Eigen::Vector3d> measured;
  double commanded_mean = 0;
  for (const auto* p : run_points) {
    measured.push_back(p->point->measured_mm);
    commanded_mean += commanded_target(*p, gc)[axis];
  }
  commanded_mean /= static_cast<double>(run_points.size());
  const PrincipalAxes line = principal_axes(measured);
  const Eigen::Vector3d& centroid = line.centroid;
  Eigen::Vector3d oriented = Eigen::Vector3d::Zero();
  for (const auto* p : run_points) {
    oriented +=
        (p->point->measured_mm - centroid) * (commanded_target(*p, gc)[axis] - commanded_mean);
  }
  Eigen::Vector3d direction = line.vectors.col(2);
  if (direction.dot(oriented) < 0) direction = -direction;
  std::vector<PositioningReading>& readings = out->readings;
  for (const auto* p : run_points) {
    PositioningReading r;
    r.target_mm = commanded_target(*p, gc)[axis];
    r.cycle = p->cycle;
    r.direction = p->up ? Approach::Up : Approach::Down;
    r.measured_mm = commanded_mean + direction.dot(p->point->measured_mm - centroid);
    readings.push_back(r);
  }
  try {
    out->result = evaluate_iso230_2(readings);
  } catch (const std::invalid_argument& e) {
    return std::string("linear axis run: ") + e.what();
  }
  return std::nullopt;
}

}  // namespace

CheckResult check_global_master_frame(const MeasurementSet& set, const MachineConfig& machine) {
  CheckResult result = detail::result_for(set);
  std::vector<LabelledPoint> points;
  if (auto why = prepare(
          set, machine,
          {"master_orthogonality_urad", "master_x_straightness_mm", "master_y_straightness_mm"},
          "the master frame check", &points)) {
    return detail::invalid(result, *why);
  }
  std::string why;
  const auto frame = master_frame_of(points, *machine.global_check, &why);
  if (!frame) return detail::invalid(result, why);
  add(result, machine, "master_orthogonality_urad", frame->orthogonality_urad, "urad");
  add(result, machine, "master_x_straightness_mm", frame->x_run.straightness_mm.maxCoeff(), "mm");
  add(result, machine, "master_y_straightness_mm", frame->y_run.straightness_mm.maxCoeff(), "mm");
  std::vector<std::string> causes;
  if (failed(result, "master_orthogonality_urad")) {
    causes.push_back("X and Y ways out of square (column or slide alignment)");
  }
  if (failed(result, "master_x_straightness_mm") || failed(result, "master_y_straightness_mm")) {
    causes.push_back("ways not straight (foundation settled, worn or damaged ways)");
    causes.push_back("tracker or target disturbed during the run (air turbulence, loose target)");
  }
  detail::decide_verdict(result, causes);
  return result;
}

CheckResult check_global_grid(const MeasurementSet& set, const MachineConfig& machine) {
  CheckResult result = detail::result_for(set);
  std::vector<LabelledPoint> points;
  if (auto why =
          prepare(set, machine,
                  {"grid_max_deviation_mm", "grid_rms_deviation_mm", "grid_squareness_xy_urad",
                   "grid_squareness_yz_urad", "grid_squareness_zx_urad", "grid_scale_x_um_per_m",
                   "grid_scale_y_um_per_m", "grid_scale_z_um_per_m"},
                  "the grid check", &points)) {
    return detail::invalid(result, *why);
  }
  const GlobalCheckConfig& gc = *machine.global_check;
  GlobalGridEvaluation evaluation;
  if (auto why = grid_of(points, gc, &evaluation)) return detail::invalid(result, *why);
  const MasterFrame* frame = &evaluation.frame;
  const GridAnalysis& grid = evaluation.grid;
  add(result, machine, "grid_max_deviation_mm", grid.max_deviation_mm, "mm");
  add(result, machine, "grid_rms_deviation_mm", grid.rms_deviation_mm, "mm");
  add(result, machine, "grid_squareness_xy_urad", grid.affine.squareness_xy_urad, "urad");
  add(result, machine, "grid_squareness_yz_urad", grid.affine.squareness_yz_urad, "urad");
  add(result, machine, "grid_squareness_zx_urad", grid.affine.squareness_zx_urad, "urad");
  add(result, machine, "grid_scale_x_um_per_m", grid.affine.scale_x_um_per_m, "um/m");
  add(result, machine, "grid_scale_y_um_per_m", grid.affine.scale_y_um_per_m, "um/m");
  add(result, machine, "grid_scale_z_um_per_m", grid.affine.scale_z_um_per_m, "um/m");

  // The 21 rigid-body errors from every target's grid (their lever arms separate the angular
  // errors), when the machine asks for the residual after a modelled compensation.
  std::optional<IdentifiedErrors> identified;
  if (detail::find_tolerance(machine, "volumetric_residual_after_mm")) {
    std::vector<VolumetricPoint> volumetric;
    for (const auto& p : points) {
      if (p.group != "grid") continue;
      const AxisPosition& c = p.point->commanded;
      volumetric.push_back({p.point->label, Eigen::Vector3d(c.x_mm, c.y_mm, c.z_mm),
                            commanded_target(p, gc) - Eigen::Vector3d(c.x_mm, c.y_mm, c.z_mm),
                            p.point->measured_mm, kAssumedPointSigmaMm});
    }
    try {
      IdentificationOptions options;
      options.initial_instrument_from_machine = frame->instrument_to_master.inverse();
      identified = identify_rigid_body_errors(volumetric, options);
    } catch (const std::invalid_argument& e) {
      return detail::invalid(result, std::string("volumetric identification: ") + e.what());
    }
    add(result, machine, "volumetric_residual_after_mm", identified->max_after_mm, "mm");
  }

  std::vector<std::string> causes;
  for (const char* axes : {"xy", "yz", "zx"}) {
    if (failed(result, std::string("grid_squareness_") + axes + "_urad")) {
      causes.push_back(std::string("axes ") + axes[0] + " and " + axes[1] +
                       " out of square (way alignment)");
    }
  }
  bool scale_failed = false;
  for (const char* axis : {"x", "y", "z"}) {
    scale_failed |= failed(result, std::string("grid_scale_") + axis + "_um_per_m");
  }
  if (scale_failed) {
    causes.push_back(
        "axis scale: machine temperature away from 20 C or the scale (pitch) "
        "compensation out of date");
  }
  if (failed(result, "volumetric_residual_after_mm")) {
    causes.push_back(
        "errors a rigid-body model cannot hold: non-repeatable positioning, loose "
        "gibs or a deforming structure (or the tracker disturbed)");
  }
  if (failed(result, "grid_max_deviation_mm") || failed(result, "grid_rms_deviation_mm")) {
    causes.push_back(
        "straightness or angular errors of an axis (worn or damaged ways, settled "
        "foundation): see where the worst points are");
  }
  detail::decide_verdict(result, causes);
  if (result.verdict == Verdict::Pass && identified) {
    // The identified error functions are the volumetric compensation a control can load: the
    // Legendre coefficients of each function (mm or rad) and the squareness errors.
    Correction c;
    c.target = std::string(kVolumetricTargetPrefix) + machine.machine_id;
    for (const auto& p : identified->parameters) {
      if (p.frame >= 0) continue;  // the tracker's placement is not the machine's
      c.offsets.push_back({p.name, p.value,
                           p.function >= 0 && volumetric::is_angular(p.function) ? "rad"
                           : p.squareness >= 0                                   ? "rad"
                                                                                 : "mm"});
    }
    result.correction = std::move(c);
  }
  if (result.verdict == Verdict::Fail && !grid.worst_points.empty()) {
    // Where it is worst: the patent's charts in a sentence.
    std::string worst = "worst points:";
    for (std::size_t k = 0; k < grid.worst_points.size() && k < 3; ++k) {
      const GridPointResult& p = grid.points[grid.worst_points[k]];
      worst += " " + p.label + " at " + detail::format_vector(p.commanded_mm) + " off by " +
               detail::format_vector(p.deviation_mm) + " mm;";
    }
    result.reason += ". " + worst;
  }
  return result;
}

CheckResult check_rotary_axis(const MeasurementSet& set, const MachineConfig& machine) {
  CheckResult result = detail::result_for(set);
  const RotaryAxis axis = set.kind == CheckKind::RotaryW   ? RotaryAxis::W
                          : set.kind == CheckKind::RotaryA ? RotaryAxis::A
                                                           : RotaryAxis::C;
  const std::string a = axis == RotaryAxis::A ? "a" : "c";
  const std::vector<std::string> names =
      axis == RotaryAxis::W
          ? std::vector<std::string>{"w_scale_um_per_m", "w_misalignment_urad", "w_straightness_mm"}
          : std::vector<std::string>{a + "_dA_mean_arcsec", a + "_dA_range_arcsec",
                                     a + "_dR_max_mm", a + "_axis_tilt_urad"};
  std::vector<LabelledPoint> points;
  const std::string check = "the " + std::string(rotary_axis_name(axis)) + " axis check";
  if (auto why = prepare(set, machine, {names.begin(), names.end()}, check, &points)) {
    return detail::invalid(result, *why);
  }
  const GlobalCheckConfig& gc = *machine.global_check;
  std::string why;
  const auto frame = master_frame_of(points, gc, &why);
  if (!frame) return detail::invalid(result, why);
  const std::string group_name = axis == RotaryAxis::W ? "w" : a;
  std::vector<RotaryPoint> rotary;
  for (const auto& p : points) {
    if (p.group != group_name) continue;
    rotary.push_back(
        {p.point->label, p.point->commanded, frame->instrument_to_master * p.point->measured_mm});
  }
  RotaryAxisResult r;
  try {
    r = analyze_rotary_axis(axis, rotary, gc.targets.front());
  } catch (const std::invalid_argument& e) {
    return detail::invalid(result, check + ": " + e.what());
  }
  std::vector<std::string> causes;
  if (r.w) {
    add(result, machine, names[0], r.w->w_scale_um_per_m, "um/m");
    add(result, machine, names[1], r.w->tilt_urad.norm(), "urad");
    add(result, machine, names[2], r.w->straightness_mm, "mm");
    if (failed(result, names[1]) || failed(result, names[2])) {
      causes.push_back("W travel not along the tool axis (quill or ram guide misaligned or worn)");
    }
    if (failed(result, names[0])) {
      causes.push_back("W scale: W servo or scale compensation, spindle housing warm");
    }
  } else {
    const RotaryCircleResult& c = *r.circle;
    add(result, machine, names[0], c.dA_mean_arcsec, "arcsec");
    add(result, machine, names[1], c.dA_range_arcsec, "arcsec");
    add(result, machine, names[2], c.dR_max_abs_mm, "mm");
    add(result, machine, names[3], c.tilt_urad.norm(), "urad");
    const std::string A = axis == RotaryAxis::A ? "A" : "C";
    if (failed(result, names[0])) {
      causes.push_back(A + " axis zero (reference mark or encoder offset) shifted");
    }
    if (failed(result, names[1])) {
      causes.push_back(A +
                       " axis angular positioning error (encoder, drive gear or its "
                       "compensation table)");
    }
    if (failed(result, names[3])) {
      causes.push_back(A +
                       (axis == RotaryAxis::A ? " axis not parallel to the head's X axis"
                                              : " axis not parallel to machine Z") +
                       " (head mounting, bearing)");
    }
    if (failed(result, names[2])) {
      causes.push_back(A +
                       " axis centre of rotation off the pivot, or the target holder length "
                       "wrong (fitted centre off by " +
                       detail::format_vector(c.centre_offset_mm) + " mm, radius by " +
                       format_number(c.radius_error_mm) + " mm)");
    }
  }
  detail::decide_verdict(result, causes);
  return result;
}

CheckResult check_circle(const MeasurementSet& set, const MachineConfig& machine) {
  CheckResult result = detail::result_for(set);
  const Plane plane = plane_of(set.kind);
  std::string p = std::string(to_string(plane));
  for (char& ch : p) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  const std::string g_name = "circle_" + p + "_G_mm", h_name = "circle_" + p + "_H_mm";
  std::vector<LabelledPoint> points;
  const std::string check = "the " + std::string(to_string(plane)) + " circle";
  if (auto why = prepare(set, machine, {}, check, &points)) return detail::invalid(result, *why);
  CircleEvaluation evaluation;
  if (auto why = circle_of(set, points, *machine.global_check, check, &evaluation)) {
    return detail::invalid(result, *why);
  }
  const CircularTestResult& r = evaluation.result;
  const bool both = r.G_b_mm.has_value();
  if (auto why = detail::why_tolerances_missing(machine,
                                                both ? std::vector<std::string_view>{g_name, h_name}
                                                     : std::vector<std::string_view>{g_name},
                                                check)) {
    return detail::invalid(result, *why);
  }
  add(result, machine, g_name, both ? *r.G_b_mm : r.G_mm, "mm");
  if (both) add(result, machine, h_name, *r.H_mm, "mm");
  std::vector<std::string> causes;
  if (failed(result, g_name)) {
    // The shape says which: an ellipse at 45 degrees is squareness, along the axes scale mismatch.
    // A short arc does not resolve the shape: both, in the usual order.
    const std::string axes = p.substr(0, 1) + " and " + p.substr(1);
    if (r.squareness_urad && r.scale_mismatch_um_per_m) {
      const bool square_first = std::abs(*r.squareness_urad) > std::abs(*r.scale_mismatch_um_per_m);
      const std::string square = "axes " + axes + " out of square (" +
                                 format_number(*r.squareness_urad) + " urad from the shape)";
      const std::string scale =
          "scale mismatch of " + axes + " (" + format_number(*r.scale_mismatch_um_per_m) + " um/m)";
      causes.push_back(square_first ? square : scale);
      causes.push_back(square_first ? scale : square);
    } else {
      causes.push_back("axes " + axes + " out of square (the arc of " +
                       format_number(std::round(r.arc.span_rad * 180 / units::kPi)) +
                       " deg does not resolve the shape)");
      causes.push_back("scale mismatch of " + axes);
    }
    causes.push_back("servo mismatch or straightness of the axes in the plane");
  }
  if (both && failed(result, h_name)) {
    causes.insert(causes.begin(),
                  "reversal: backlash of the axes (hysteresis of the two directions)");
  }
  detail::decide_verdict(result, causes);
  return result;
}

CheckResult check_linear_axis_run(const MeasurementSet& set, const MachineConfig& machine) {
  CheckResult result = detail::result_for(set);
  std::vector<LabelledPoint> points;
  if (auto why = prepare(set, machine, {"linear_A_mm", "linear_E_mm", "linear_R_mm", "linear_B_mm"},
                         "the linear axis run", &points)) {
    return detail::invalid(result, *why);
  }
  LinearRunEvaluation evaluation;
  if (auto why = linear_run_of(set, points, *machine.global_check, &evaluation)) {
    return detail::invalid(result, *why);
  }
  const std::vector<PositioningReading>& readings = evaluation.readings;
  const Iso230_2Result& iso = evaluation.result;
  if (!iso.has_up || !iso.has_down) {
    // ISO 230-2's A and B (what the tolerances judge) are bidirectional figures.
    return detail::invalid(
        result, "the linear axis run went " + std::string(iso.has_up ? "up (+)" : "down (-)") +
                    " only (" + std::to_string(readings.size()) +
                    " readings): its bidirectional accuracy A and reversal B need both "
                    "directions; measure the run both ways (`ncqual analyze iso230-2` reports "
                    "the unidirectional figures of this one)");
  }
  const double nan = std::nan("");
  add(result, machine, "linear_A_mm", iso.A_mm.value_or(nan), "mm");
  add(result, machine, "linear_E_mm", iso.E_mm.value_or(nan), "mm");
  add(result, machine, "linear_R_mm", iso.R_mm.value_or(nan), "mm");
  add(result, machine, "linear_B_mm", iso.B_mm.value_or(nan), "mm");
  std::vector<std::string> causes;
  if (failed(result, "linear_B_mm")) {
    causes.push_back("reversal: backlash of the ball screw or nut, or the backlash compensation");
  }
  if (failed(result, "linear_R_mm")) {
    causes.push_back("repeatability: friction or stick-slip of the ways, servo tuning");
  }
  if (failed(result, "linear_E_mm") || failed(result, "linear_A_mm")) {
    causes.push_back(
        "systematic positioning error: pitch error compensation out of date or the "
        "axis warmer than 20 C");
  }
  detail::decide_verdict(result, causes);
  return result;
}

namespace {

// The points of a set for an evaluation without judging (no tolerances needed); throws why not.
std::vector<LabelledPoint> points_for_evaluation(const MeasurementSet& set,
                                                 const MachineConfig& machine,
                                                 std::string_view check) {
  std::vector<LabelledPoint> points;
  if (auto why = prepare(set, machine, {}, check, &points)) throw std::invalid_argument(*why);
  return points;
}

}  // namespace

GlobalGridEvaluation evaluate_global_grid(const MeasurementSet& set, const MachineConfig& machine) {
  const auto points = points_for_evaluation(set, machine, "the grid check");
  GlobalGridEvaluation out;
  if (auto why = grid_of(points, *machine.global_check, &out)) throw std::invalid_argument(*why);
  return out;
}

CircleEvaluation evaluate_circle(const MeasurementSet& set, const MachineConfig& machine) {
  const std::string check = "the " + std::string(to_string(plane_of(set.kind))) + " circle";
  const auto points = points_for_evaluation(set, machine, check);
  CircleEvaluation out;
  if (auto why = circle_of(set, points, *machine.global_check, check, &out)) {
    throw std::invalid_argument(*why);
  }
  return out;
}

LinearRunEvaluation evaluate_linear_axis_run(const MeasurementSet& set,
                                             const MachineConfig& machine) {
  const auto points = points_for_evaluation(set, machine, "the linear axis run");
  LinearRunEvaluation out;
  if (auto why = linear_run_of(set, points, *machine.global_check, &out)) {
    throw std::invalid_argument(*why);
  }
  return out;
}

}  // namespace ncqual::solver
