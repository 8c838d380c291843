// SPDX-License-Identifier: Apache-2.0
// The holding fixture simulator: a pogo fixture (Universal Holding Fixture) whose true pogo
// positions differ from the commanded ones by known errors, its control unit with the zero
// offsets the weekly pre-calibration issues, and the probing program of the weekly fixture checks
// run with the (erroneous) machine and probe of a MachineSimulator. It returns raw touches, never
// the answer; the errors are ground truth for tests.
//
// The true fixture (FixtureErrors, simulator.fixture in the machine config). The control unit
// holds a zero offset o per pogo and axis (not per actuator: the deltas the solver measures are per
// pogo, and the control unit trims each pogo's own commanded position; it is assumed to be able to
// trim the X of each pogo on its column). For a pogo commanded to c (fixture frame) it drives the
// actuators to
//   a = c - o
// and the top-face centre of the pogo's reference block truly is, in the machine frame,
//   p = origin + sum over the axes j of (a_j + e_j(a_j)) d_j + pogo_offset + wear
// with e_j and d_j the error and the direction of fixture axis j (column_x, pogo_y, pogo_z; see
// FixtureAxisErrors), pogo_offset the pogo's own offset and wear a fresh N(0, wear_sigma^2) draw
// per axis for every placement. A pure offset error (offsets of the axes and of the pogos) is a
// constant per pogo: once o equals it the pogo is where commanded in every configuration, while
// scale, misalignment and nonlinearity depend on a and remain. The reference block is an
// axis-aligned box of the configured size and height under p (its tilt by a misalignment of
// micro-radians is not modelled); the other pogos are not modelled (the probing moves are assumed
// clear of them).
//
// The probing program (the machine's part program, against the commanded positions, head at home:
// A = C = 0, W = 0), for every probed pogo of every configuration, with q = origin + c:
//   top: ball centre from q + (0, 0, r + 5) along -Z, 10 mm of travel;
//   x-:  from q + (-(h + r + 5), 0, -d) along +X;  x+: from q + (h + r + 5, 0, -d) along -X;
//   y-:  from q + (0, -(h + r + 5), -d) along +Y;  y+: from q + (0, h + r + 5, -d) along -Y;
//   (h = block half size, d = probe depth, r = nominal ball radius, 5 mm clearance, 5 mm over-
//   travel). Both sides in X and in Y, so the pogo's centre, the mean of the two side contacts,
//   does not depend on the ball radius. Features: "pogo:<label>:cfg<index>:<face>"
//   (ncqual/common/fixture.hpp).
// Configurations: pre-calibration (kind FixturePreCalibration) probes configuration k of the
// request's parameter "fixture_configuration" (required, an integer in 0 .. 2n-1); post-calibration
// (FixturePostCalibration) probes every post-calibration configuration j in order, with the rows of
// the pre-calibration configuration given by "fixture_configuration" when present (the rows whose
// zero offsets the post-calibration verifies), else every row.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/fixture.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/sim/machine_simulator.hpp"
#include "ncqual/sim/simulator_config.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <map>
#include <optional>
#include <string>

namespace ncqual::sim {

class FixtureSimulator {
 public:
  // `errors` are the base truth; with `drift` they drift as fixture_errors_at(errors, drift, t).
  FixtureSimulator(FixtureConfig fixture, FixtureErrors errors,
                   std::optional<SimulatorDrift> drift = std::nullopt);
  // The machine's `fixture:` section with the simulator's fixture errors and drift; throws
  // ConfigError naming the machine when it has no fixture.
  static FixtureSimulator for_machine(const MachineConfig& machine, const SimulatorConfig& config);

  const FixtureConfig& fixture() const { return fixture_; }
  // The base errors: the truth without drift, or at and before drift.since.
  const FixtureErrors& ground_truth() const { return errors_; }
  // The errors at `now_ns` (ns since the Unix epoch, UTC): fixture_errors_at(errors, drift, now).
  FixtureErrors ground_truth_at(std::int64_t now_ns) const {
    return fixture_errors_at(errors_, drift_, now_ns);
  }
  const std::optional<SimulatorDrift>& drift() const { return drift_; }
  // The fixture frozen at `now_ns`: its errors at that time, drift cleared, the zero offsets held
  // by the control unit kept. Without drift, an identical copy.
  FixtureSimulator at(std::int64_t now_ns) const;

  // ---- The control unit's zero offsets ----
  // Adds the offsets of a Correction issued by the fixture pre-calibration (target
  // "fixture:<fixture_id>", offsets "<pogo>.d<x|y|z>" in "mm", value = measured - commanded) to
  // the ones held: the deltas were measured with the held offsets in force. All or nothing:
  // throws std::invalid_argument naming the target or the offset (index, name, value, unit) when
  // any is not for this fixture.
  void apply_zero_offsets(const Correction& correction);
  void clear_zero_offsets();
  // The offset held for a pogo (zero when none).
  Eigen::Vector3d zero_offset_mm(const std::string& pogo) const;
  const std::map<std::string, Eigen::Vector3d>& zero_offsets() const { return zero_offsets_; }

  // Actuator commands for a placement: a = c - o (fixture frame).
  Eigen::Vector3d actuator_command_mm(const PogoPlacement& placement) const;
  // True top-face centre of the pogo's reference block in the machine frame, without the wear
  // scatter: origin + sum_j (a_j + e_j(a_j)) d_j + pogo_offset, with the base errors (for the
  // truth at a time ask at(now_ns)).
  Eigen::Vector3d true_reference_point_mm(const PogoPlacement& placement) const;
  // What a perfect probe would measure against the command: true point - (origin + c).
  Eigen::Vector3d true_delta_mm(const PogoPlacement& placement) const;

 private:
  FixtureConfig fixture_;
  FixtureErrors errors_;
  std::optional<SimulatorDrift> drift_;
  std::map<std::string, Eigen::Vector3d> zero_offsets_;
};

// Performs the fixture check `request` asks for (kinds FixturePreCalibration and
// FixturePostCalibration), measured at `time_ns` (ns since the Unix epoch, UTC), on the fixture's
// current state (its zero offsets) with the true machine and probe of `machine`, both with their
// truth at that time (machine.at(time_ns), fixture.at(time_ns)), returning the touches as
// MachineSimulator::perform does for the monument: latched axis readouts, approach unit vectors,
// trigger noise N(0, sigma^2) along the approach from NormalSource(request_seed(seed,
// request_id)) (one deviate per move, drawn whether or not it triggers), the request's parameters
// echoed, instrument "touch_probe", frame "machine". The wear scatter comes from a second
// generator, request_seed(seed, request_id + "/fixture_wear"), three deviates per placement. A move
// that meets nothing is left out and named in `error` ("probe alarm: move <i> ('<feature>'): ...");
// a bad request yields no touches and an `error` saying why.
MeasurementSet perform_fixture_check(const MachineSimulator& machine,
                                     const FixtureSimulator& fixture, const CheckRequest& request,
                                     std::int64_t time_ns);

}  // namespace ncqual::sim
