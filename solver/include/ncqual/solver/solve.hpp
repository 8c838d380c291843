// SPDX-License-Identifier: Apache-2.0
// The solver's entry point: a measurement set in, a check result out.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/model.hpp"

#include <cstdint>

namespace ncqual::solver {

// Dispatches by set.kind to the check that implements it. The result always carries the set's
// machine_id, request_id, kind and origin (measured or simulated), and `time_ns` (the caller's
// clock, read outside the library).
// Verdict INVALID, never a throw, for: a machine not configured in the plant, an instrument
// error in the set, a kind this solver version does not implement, and any bad data the check
// itself rejects.
CheckResult solve(const MeasurementSet& set, const PlantConfig& plant, std::int64_t time_ns);

// As above with the machine's config given directly; INVALID when set.machine_id differs from
// machine.machine_id.
CheckResult solve(const MeasurementSet& set, const MachineConfig& machine, std::int64_t time_ns);

// True for the check kinds this solver version can judge.
bool is_implemented(CheckKind kind);

}  // namespace ncqual::solver
