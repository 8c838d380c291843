// SPDX-License-Identifier: Apache-2.0
// The laser tracker simulator of the monthly global check: the machine runs the program of a
// tracker check (ncqual/common/global_check.hpp) and a tracker standing beside it measures the
// reflector in the spindle. The machine is the true one of SimulatorConfig (21 rigid-body errors,
// thermal expansion, reversal, repeatability, wrist errors), the tracker has its own frame and
// noise in its spherical coordinates. Readings come out in the tracker frame, never corrected; the
// truth is exposed for tests.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/global_check.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/sim/simulator_config.hpp"

#include <cstdint>

namespace ncqual::sim {

class TrackerSimulator {
 public:
  // Throws std::invalid_argument when the machine has no `global_check:` section.
  TrackerSimulator(MachineConfig machine, SimulatorConfig config);

  // Runs the program of `request.kind` and returns the tracker's readings (frame "tracker"),
  // measured at `time_ns` (ns since the Unix epoch, UTC) on the truth of that time (at(time_ns)).
  // Reproducible: the noise comes from (config seed, request_id). A kind that is not a tracker
  // check yields an empty set with `error` saying so.
  MeasurementSet perform(const CheckRequest& request, std::int64_t time_ns) const;

  // The simulator frozen at `now_ns`: the truth of that time (config_at(config(), now_ns), drift
  // cleared), same tracker, seed and noise. Without drift, an identical copy.
  TrackerSimulator at(std::int64_t now_ns) const;

  // ---- The true world (for tests) ----
  // With the base truth of config(); for the truth at a time ask at(now_ns).
  // Where the target really is (machine frame) for readouts `axes`, reflector `target`, with the
  // linear axes arriving from `direction` (+1/-1 per axis, for the reversal) and no random error.
  Eigen::Vector3d true_target(const AxisPosition& axes, const ProbeGeometry& target,
                              const Eigen::Vector3i& direction = Eigen::Vector3i::Ones()) const;
  // Tracker frame -> machine frame: machine = R * tracker + position.
  Eigen::Matrix3d tracker_rotation() const { return config_.tracker.rotation(); }
  const Eigen::Vector3d& tracker_position() const { return config_.tracker.position_mm; }
  const SimulatorConfig& config() const { return config_; }
  const GlobalCheckConfig& global_check() const { return *machine_.global_check; }

 private:
  MachineConfig machine_;
  SimulatorConfig config_;
};

}  // namespace ncqual::sim
