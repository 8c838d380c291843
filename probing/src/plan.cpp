// SPDX-License-Identifier: Apache-2.0
#include "ncqual/probing/plan.hpp"

#include "ncqual/common/kinematics.hpp"
#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/units.hpp"

#include <cmath>
#include <cstdio>

namespace ncqual::probing {

AxisPosition axes_placing_ball_at(const Eigen::Vector3d& ball_centre, double a_rad, double c_rad,
                                  double w_mm, const ProbeGeometry& nominal_probe) {
  const Eigen::Vector3d in_body(nominal_probe.stylus_offset_mm.x(),
                                nominal_probe.stylus_offset_mm.y(),
                                -(nominal_probe.tool_length_mm + w_mm));
  const Eigen::Vector3d pivot = ball_centre - wrist_rotation(a_rad, c_rad) * in_body;
  AxisPosition axes;
  axes.x_mm = pivot.x();
  axes.y_mm = pivot.y();
  axes.z_mm = pivot.z();
  axes.w_mm = w_mm;
  axes.a_rad = a_rad;
  axes.c_rad = c_rad;
  return axes;
}

namespace {

// Radial touches of the hole edge with the head at C = c (A = 0): from the hole centre
// outward; the ball meets the wall after R_hole - r_ball, the search goes the overtravel beyond.
void add_hole_edge_touches(const MachineConfig& machine, double c_rad,
                           std::vector<ProbingMove>* program) {
  const MonumentConfig& taught = machine.monument;
  const ProbeGeometry& probe = machine.probe;
  const Eigen::Vector3d inside_hole(taught.hole_center_mm.x(), taught.hole_center_mm.y(),
                                    taught.face_z_mm - taught.probe_depth_mm);
  const AxisPosition edge_start = axes_placing_ball_at(inside_hole, 0, c_rad, 0, probe);
  const double edge_travel =
      taught.hole_diameter_mm / 2 - probe.ball_radius_mm + machine.probing.overtravel_mm;
  const int n = taught.hole_touches;
  for (int k = 0; k < n; ++k) {
    const double theta = 2 * units::kPi * k / n;
    program->push_back({"hole_edge", edge_start,
                        Eigen::Vector3d(std::cos(theta), std::sin(theta), 0), edge_travel});
  }
}

// One touch of a vertical gauge edge: the ball starts clearance + r outside the edge plane
// at `on_edge` (a point of the edge plane), head at (a, c), and moves along `direction`.
ProbingMove gauge_edge_touch(const MachineConfig& machine, const char* feature,
                             const Eigen::Vector3d& on_edge, const Eigen::Vector3d& direction,
                             double a_rad, double c_rad) {
  const ProbingConfig& p = machine.probing;
  const double gap = machine.probe.ball_radius_mm + p.clearance_mm;
  const Eigen::Vector3d start = on_edge - gap * direction;
  return {feature, axes_placing_ball_at(start, a_rad, c_rad, 0, machine.probe), direction,
          p.clearance_mm + p.overtravel_mm};
}

Eigen::Vector3d gauge_point(const MonumentConfig& taught, double dx, double dy) {
  return {taught.hole_center_mm.x() + dx, taught.hole_center_mm.y() + dy,
          taught.face_z_mm - taught.probe_depth_mm};
}

}  // namespace

std::vector<ProbingMove> monument_c_alignment_program(const MachineConfig& machine) {
  std::vector<ProbingMove> program;
  add_hole_edge_touches(machine, 0, &program);
  add_hole_edge_touches(machine, units::kPi, &program);
  return program;
}

std::vector<ProbingMove> monument_tool_length_program(const MachineConfig& machine) {
  const MonumentConfig& taught = machine.monument;
  const double half = taught.gauge_width_mm / 2;
  const double c = units::kPi / 2;
  return {gauge_edge_touch(machine, "gauge_edge_+x", gauge_point(taught, half, 0),
                           -Eigen::Vector3d::UnitX(), units::kPi / 2, c),
          gauge_edge_touch(machine, "gauge_edge_-x", gauge_point(taught, -half, 0),
                           Eigen::Vector3d::UnitX(), -units::kPi / 2, c)};
}

std::vector<ProbingMove> monument_c_rotation_program(const MachineConfig& machine) {
  const MonumentConfig& taught = machine.monument;
  const Eigen::Vector3d upper_edge = gauge_point(taught, 0, taught.gauge_width_mm / 2);
  const double c = units::kPi / 2;
  return {gauge_edge_touch(machine, "gauge_edge_+y", upper_edge, -Eigen::Vector3d::UnitY(),
                           units::kPi / 2, c),
          gauge_edge_touch(machine, "gauge_edge_+y", upper_edge, -Eigen::Vector3d::UnitY(),
                           -units::kPi / 2, c)};
}

std::vector<ProbingMove> part_setpoints_program(const MachineConfig& machine) {
  const PartSetPointsConfig& sp = machine.setpoints;
  const double gap = machine.probe.ball_radius_mm + machine.probing.clearance_mm;
  const double travel = machine.probing.clearance_mm + machine.probing.overtravel_mm;
  std::vector<ProbingMove> program;
  for (const SetPointConfig& point : sp.points) {
    const Eigen::Vector3d& c = point.intended_mm;
    const std::string prefix = "setpoint:" + point.name + ":";
    const struct {
      const char* axis;
      Eigen::Vector3d ball_start;
      Eigen::Vector3d direction;
    } touches[] = {
        {"z", {c.x() + sp.inset_mm, c.y() + sp.inset_mm, c.z() + gap}, -Eigen::Vector3d::UnitZ()},
        {"x",
         {c.x() - gap, c.y() + sp.inset_mm, c.z() - sp.probe_depth_mm},
         Eigen::Vector3d::UnitX()},
        {"y",
         {c.x() + sp.inset_mm, c.y() - gap, c.z() - sp.probe_depth_mm},
         Eigen::Vector3d::UnitY()},
    };
    for (const auto& t : touches) {
      program.push_back({prefix + t.axis,
                         axes_placing_ball_at(t.ball_start, 0, 0, 0, machine.probe), t.direction,
                         travel});
    }
  }
  return program;
}

std::vector<ProbingMove> monument_positioning_program(const MachineConfig& machine) {
  const MonumentConfig& taught = machine.monument;
  const ProbeGeometry& probe = machine.probe;
  const double ball_r = probe.ball_radius_mm;
  std::vector<ProbingMove> program;
  add_hole_edge_touches(machine, 0, &program);

  // Face touch: down along -Z onto the face beside the hole.
  const Eigen::Vector3d above_face(taught.hole_center_mm.x() + taught.face_offset_mm,
                                   taught.hole_center_mm.y(),
                                   taught.face_z_mm + ball_r + machine.probing.clearance_mm);
  program.push_back({"face", axes_placing_ball_at(above_face, 0, 0, 0, probe),
                     -Eigen::Vector3d::UnitZ(),
                     machine.probing.clearance_mm + machine.probing.overtravel_mm});
  return program;
}

namespace {

constexpr std::string_view kConfigurationParameter = "fixture_configuration";

std::string format_number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

// The five touches of one pogo, against its commanded position q = origin + c in the machine
// frame, with the nominal probe.
void add_pogo_moves(const FixtureConfig& f, const ProbeGeometry& nominal_probe,
                    const ProbingConfig& probing, const PogoPlacement& placement, int configuration,
                    std::size_t index, std::vector<FixtureMove>* moves) {
  const Eigen::Vector3d q = f.to_machine(placement.commanded_mm);
  const double r = nominal_probe.ball_radius_mm;
  const double h = f.block_half_size_mm();
  for (PogoFace face : kPogoFaces) {
    const Eigen::Vector3d n = outward_normal(face);
    Eigen::Vector3d start;
    if (face == PogoFace::Top) {
      start = q + (r + probing.clearance_mm) * n;
    } else {
      start = q + (h + r + probing.clearance_mm) * n;
      start.z() -= f.probe_depth_mm;
    }
    FixtureMove m;
    m.move.feature = pogo_touch_feature(placement.pogo, configuration, face);
    m.move.start = axes_placing_ball_at(start, 0, 0, 0, nominal_probe);
    m.move.direction = approach_direction(face);
    m.move.travel_mm = probing.clearance_mm + probing.overtravel_mm;
    m.placement = index;
    m.face = face;
    moves->push_back(std::move(m));
  }
}

// "fixture_configuration" of the request: an integer in 0 .. count - 1.
std::optional<int> configuration_parameter(const CheckRequest& request, int count,
                                           std::string* error) {
  const NamedValue* value = find_value(request.parameters, kConfigurationParameter);
  if (!value) return std::nullopt;
  const double k = value->value;
  if (!std::isfinite(k) || k != std::floor(k) || k < 0 || k > count - 1) {
    *error = "the request's parameter " + std::string(kConfigurationParameter) + " = " +
             format_number(k) + " is not an integer in 0.." + std::to_string(count - 1);
    return std::nullopt;
  }
  return static_cast<int>(k);
}

}  // namespace

FixturePlan fixture_plan(const FixtureConfig& f, const ProbeGeometry& nominal_probe,
                         const ProbingConfig& probing, const CheckRequest& request) {
  FixturePlan plan;
  const int pre_count = f.precalibration_configuration_count();
  const auto k = configuration_parameter(request, pre_count, &plan.error);
  if (!plan.error.empty()) return plan;
  std::vector<std::vector<PogoPlacement>> configurations;
  if (request.kind == CheckKind::FixturePreCalibration) {
    if (!k) {
      plan.error = "a fixture pre-calibration request needs the parameter " +
                   std::string(kConfigurationParameter) + " (0.." + std::to_string(pre_count - 1) +
                   ")";
      return plan;
    }
    // The pre-calibration probes one configuration; its index in the features is k itself.
    configurations.assign(static_cast<std::size_t>(*k), {});
    configurations.push_back(precalibration_configuration(f, *k));
  } else if (request.kind == CheckKind::FixturePostCalibration) {
    configurations =
        postcalibration_configurations(f, k ? precalibration_rows(f, *k) : RowSelection::All);
  } else {
    plan.error = "a fixture plan is for '" +
                 std::string(to_string(CheckKind::FixturePreCalibration)) + "' and '" +
                 std::string(to_string(CheckKind::FixturePostCalibration)) + "', not '" +
                 std::string(to_string(request.kind)) + "'";
    return plan;
  }
  for (std::size_t j = 0; j < configurations.size(); ++j) {
    for (const PogoPlacement& placement : configurations[j]) {
      plan.placements.push_back(placement);
      add_pogo_moves(f, nominal_probe, probing, placement, static_cast<int>(j),
                     plan.placements.size() - 1, &plan.moves);
    }
  }
  return plan;
}

TouchPlan touch_plan(const CheckRequest& request, const MachineConfig& machine) {
  TouchPlan plan;
  const std::string kind(to_string(request.kind));
  switch (request.kind) {
    case CheckKind::MonumentCAlignment: plan.moves = monument_c_alignment_program(machine); break;
    case CheckKind::MonumentToolLength: plan.moves = monument_tool_length_program(machine); break;
    case CheckKind::MonumentPositioning: plan.moves = monument_positioning_program(machine); break;
    case CheckKind::MonumentCRotation: plan.moves = monument_c_rotation_program(machine); break;
    case CheckKind::PartSetPoints:
      if (machine.setpoints.points.empty()) {
        plan.error = "machine '" + machine.machine_id + "' has no setpoints: section (" +
                     machine.source_path + "): nothing to probe for '" + kind + "'";
        break;
      }
      plan.moves = part_setpoints_program(machine);
      break;
    case CheckKind::FixturePreCalibration:
    case CheckKind::FixturePostCalibration: {
      if (!machine.fixture) {
        plan.error = "machine '" + machine.machine_id + "' has no fixture: section (" +
                     machine.source_path + "): nothing to probe for '" + kind + "'";
        break;
      }
      FixturePlan fixture = fixture_plan(*machine.fixture, machine.probe, machine.probing, request);
      plan.error = fixture.error;
      for (auto& m : fixture.moves) plan.moves.push_back(std::move(m.move));
      break;
    }
    default:
      plan.error = "'" + kind + "' is measured by the " +
                   std::string(to_string(check_kind_info(request.kind).instrument)) +
                   ", not by probing moves";
  }
  return plan;
}

}  // namespace ncqual::probing
