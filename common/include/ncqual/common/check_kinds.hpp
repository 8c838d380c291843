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

// What a Compensation corrects, read from its target's prefix (the solver writes them):
//   WorkOffset   "work_offset:<machine>"  a part's set points: the work offset of that one part
//   ZeroOffsets  "fixture:<fixture>"      a fixture pre-calibration's zero offsets of its pogos
//   Volumetric   "volumetric:<machine>"   the monthly grid's error functions (scale, straightness,
//                                         angular, squareness of X, Y, Z) for the control
//   Other        any other target: nobody knows what it touched
enum class CompensationKind { WorkOffset, ZeroOffsets, Volumetric, Other };
inline constexpr std::string_view kWorkOffsetTargetPrefix = "work_offset:";
inline constexpr std::string_view kZeroOffsetsTargetPrefix = "fixture:";
inline constexpr std::string_view kVolumetricTargetPrefix = "volumetric:";
CompensationKind compensation_kind(std::string_view target);
// "work offset", "fixture zero offsets", "volumetric compensation", "compensation"
std::string_view to_string(CompensationKind kind);

// The restart rule (docs/trends.md, "What restarts a series"): one row per kind of compensation
// and one for interventions, saying which series (check kind, and metrics of it) it restarts: the
// series whose cause it corrects, and only those, so that a warning is ended only by what could
// have removed its cause. The trend watch, `ncqual trend`, the report's and the dashboard's
// charts read it through restarts_series; nothing else decides what restarts a series.
struct RestartRow {
  std::optional<CompensationKind> compensation;  // none: an intervention
  bool everything = false;                       // every series of the machine
  std::vector<CheckKind> kinds;                  // every metric of these kinds' checks
  // Besides `kinds`: these metrics of `metric_kind`'s checks only.
  std::optional<CheckKind> metric_kind;
  std::vector<std::string_view> metrics;
  std::string_view why;  // for people (and the docs' table)
};
const std::vector<RestartRow>& restart_rule();

// Whether a restart restarts the series of `metric` reported by checks of `series`: an
// intervention (compensation none) or a compensation of that kind.
bool restarts_series(std::optional<CompensationKind> compensation, CheckKind series,
                     std::string_view metric);

// True when some kind's check reads tolerance key `key`.
bool is_tolerance_key(std::string_view key);

}  // namespace ncqual
