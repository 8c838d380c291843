// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/solve.hpp"

#include "ncqual/solver/fixture_checks.hpp"
#include "ncqual/solver/global_checks.hpp"
#include "ncqual/solver/monument_positioning.hpp"
#include "ncqual/solver/monument_probe_checks.hpp"
#include "ncqual/solver/part_setpoints.hpp"
#include "result_building.hpp"

#include <cmath>
#include <exception>
#include <string>

namespace ncqual::solver {
namespace {

CheckResult stamped(CheckResult result, const MeasurementSet& set, std::int64_t time_ns) {
  result.machine_id = set.machine_id;
  result.request_id = set.request_id;
  result.kind = set.kind;
  result.time_ns = time_ns;
  return result;
}

// One solver check per row of the check-kind table (ncqual/common/check_kinds.hpp). No `default:`,
// so that the compiler (-Wswitch) names a kind added to the table without its check here.
CheckResult dispatch(const MeasurementSet& set, const MachineConfig& machine) {
  switch (set.kind) {
    case CheckKind::MonumentCAlignment: return check_c_axis_alignment(set, machine);
    case CheckKind::MonumentToolLength: return check_composite_tool_length(set, machine);
    case CheckKind::MonumentPositioning: return check_repeatable_positioning(set, machine);
    case CheckKind::MonumentCRotation: return check_c_rotation(set, machine);
    case CheckKind::FixturePreCalibration: return check_fixture_precalibration(set, machine);
    case CheckKind::FixturePostCalibration: return check_fixture_postcalibration(set, machine);
    case CheckKind::PartSetPoints: return check_part_setpoints(set, machine);
    case CheckKind::GlobalMasterFrame: return check_global_master_frame(set, machine);
    case CheckKind::GlobalGrid: return check_global_grid(set, machine);
    case CheckKind::RotaryW:
    case CheckKind::RotaryA:
    case CheckKind::RotaryC: return check_rotary_axis(set, machine);
    case CheckKind::CircleXY:
    case CheckKind::CircleYZ:
    case CheckKind::CircleXZ: return check_circle(set, machine);
    case CheckKind::LinearAxisRun: return check_linear_axis_run(set, machine);
  }
  return detail::invalid(detail::result_for(set),
                         "check kind '" + std::string(to_string(set.kind)) +
                             "' is not implemented by this solver version");
}

}  // namespace

bool is_implemented(CheckKind kind) {
  // dispatch() judges every kind of the process; anything else is a value off the enum.
  const int k = static_cast<int>(kind);
  return k >= 0 && k < kCheckKindCount;
}

CheckResult solve(const MeasurementSet& set, const PlantConfig& plant, std::int64_t time_ns) {
  const MachineConfig* machine = plant.find_machine(set.machine_id);
  if (!machine) {
    return stamped(detail::invalid(detail::result_for(set), "machine_id '" + set.machine_id +
                                                                "' is not configured in plant '" +
                                                                plant.plant + "'"),
                   set, time_ns);
  }
  return solve(set, *machine, time_ns);
}

CheckResult solve(const MeasurementSet& set, const MachineConfig& machine, std::int64_t time_ns) {
  CheckResult result = detail::result_for(set);
  try {
    if (set.machine_id != machine.machine_id) {
      result = detail::invalid(result, "machine_id '" + set.machine_id +
                                           "' does not match the machine config '" +
                                           machine.machine_id + "'");
    } else if (!set.error.empty()) {
      // The instrument could not perform the request: nothing to judge.
      result = detail::invalid(result, "MeasurementSet.error: " + set.error);
    } else {
      result = dispatch(set, machine);
      // The last line against a figure no check could evaluate: a NaN or infinite metric cannot
      // be judged, so neither can the check.
      std::string unevaluated;
      for (const Metric& m : result.metrics) {
        if (!std::isfinite(m.value)) unevaluated += (unevaluated.empty() ? "" : ", ") + m.name;
      }
      if (!unevaluated.empty()) {
        result = detail::invalid(result, "could not be evaluated: " + unevaluated);
      }
    }
  } catch (const std::exception& e) {
    // Checks do not throw on bad data; this is the last line against a verdict-less result.
    result = detail::invalid(result, std::string("solver error: ") + e.what());
  }
  return stamped(std::move(result), set, time_ns);
}

}  // namespace ncqual::solver
