// SPDX-License-Identifier: Apache-2.0
// The table of check kinds: one row per kind with everything the parts of ncqual need to know
// about it besides its math. The scheduler, `ncqual status`, the acquisition, the solver's
// dispatch, the configuration layer (which tolerance keys exist) and the CLI read it; nothing else
// lists kinds. docs/architecture.md says how to add a kind.
//
// The order of the rows is the CheckKind enum's (the wire contract's values); the default
// calendar runs the kinds of a cadence in row order.
#pragma once

#include "ncqual/common/model.hpp"

#include <array>
#include <optional>
#include <string_view>
#include <vector>

namespace ncqual {

// Where the default calendar puts a kind; PerPart and AfterCorrection are not periods.
enum class Cadence { Monthly, Weekly, Daily, PerPart, AfterCorrection };

// What measures it: the touch probe in the spindle against the monument or the part, the touch
// probe against the holding fixture's pogos, or the laser tracker with a reflector in the spindle.
enum class Instrument { TouchProbe, FixtureProbe, LaserTracker };

// The machine config section a kind needs besides probe and monument; a machine without it is
// never planned or shown that kind.
enum class Needs { Monument, SetPoints, Fixture, GlobalCheck };

// "monthly", "weekly", "daily", "per part", "after correction"; "touch probe", "fixture probe",
// "laser tracker"; "monument", "set points", "fixture", "global check".
std::string_view to_string(Cadence cadence);
std::string_view to_string(Instrument instrument);
std::string_view to_string(Needs needs);

struct CheckKindInfo {
  CheckKind kind;
  std::string_view name;   // the stable name: config, command line, logs, JSON, historian
  std::string_view title;  // for people: "daily 1: probe alignment with the C axis"
  Cadence cadence;
  Instrument instrument;
  Needs needs;
  // How long the instruments take for one check, in minutes: on a simulated clock the
  // measurement is stamped this long after its request.
  double duration_min;
  // A PASS of this kind is also a pass of `satisfies` (the post-calibration that verifies zero
  // offsets completes the week's pre-calibration); none: only of itself.
  std::optional<CheckKind> satisfies;
  // What an intervention on a machine held by this kind re-runs, and which kind the intervention
  // may name besides this one: the post-calibration's loop starts again at the pre-calibration.
  std::optional<CheckKind> rerun_after_intervention;
  // The tolerance keys (tolerances: in the machine config) its solver check reads; a machine's
  // tolerances must be keys of some kind's list. Which are required is the check's business
  // (it is INVALID, naming the key, without them).
  std::vector<std::string_view> tolerances;
};

// The table, in CheckKind order.
const std::array<CheckKindInfo, kCheckKindCount>& check_kinds();
const CheckKindInfo& check_kind_info(CheckKind kind);

// The kinds whose PASS counts as a pass of `kind`: itself, and those that satisfy it.
std::vector<CheckKind> kinds_passing(CheckKind kind);
// What an intervention on a machine held by `held` re-runs (itself unless its row says another).
CheckKind rerun_after_intervention(CheckKind held);
// The kind that verifies a software correction issued by a failed `kind` (the post-calibration
// after the pre-calibration's zero offsets): the row that satisfies `kind` and runs after a
// correction. None: a failure of `kind` holds the machine.
std::optional<CheckKind> verified_by(CheckKind kind);
// Whether an intervention that names `named` may re-arm a machine held by `held`.
bool intervention_matches(CheckKind named, CheckKind held);

bool is_tracker_check(CheckKind kind);  // instrument LaserTracker
bool is_fixture_check(CheckKind kind);  // instrument FixtureProbe

// Whether a compensation issued by a check of `issued_by` restarts the trend series of the
// metrics of `series` (docs/trends.md, "The series and its segment"): a tracker check's
// (volumetric) compensation moves the machine everywhere and restarts every series; any other
// the series of its own kind and of the kinds it is verified by or satisfies (a fixture's zero
// offsets restart the fixture checks' series, not the monument's).
bool compensation_restarts(CheckKind issued_by, CheckKind series);

// True when some kind's check reads tolerance key `key`.
bool is_tolerance_key(std::string_view key);

}  // namespace ncqual
