// `ncqual uncertainty`: the uncertainty of a machine's monthly laser-tracker verification (the
// grid check and its identification of the 21 rigid-body errors), by Monte Carlo (GUM S1).
//
//   ncqual uncertainty --machine M [--plant F] [--trials N] [--seed S] [--threads T] [--search]
//                      [--json]
//
// Reads the machine's `global_check:` section from the plant config (--plant or NCQUAL_PLANT)
// and its `uncertainty:` mapping (ncqual/global_check.hpp: the planned tracker, the uncertainty
// sources, trials, seed, the search region), builds the grid design of the GlobalGrid program
// (solver::grid_verification_design) and runs solver::evaluate_verification_uncertainty on it
// with the machine's systematic errors zero: the machine verified as it is nominally, so what is
// left after the identification is what the tracker's noise and placement, the repeatability and
// the thermal correction leave (the figures do not depend on the errors as long as the model
// represents them). --trials and --seed override the config; --threads (default: the hardware's
// cores, at most 64) only changes the speed, never a figure. With --search it also runs
// solver::best_tracker_location over the configured search region (eq. 24, no Monte Carlo) and
// compares the best candidate with the configured position. This command only gathers and
// prints; the math is the solver's (ncqual/solver/verification_uncertainty.hpp).
//
// --json prints one document; its names are a public interface (append, never rename):
//   {"machine_id", "config" (machine file), "plant" (plant file),
//    "machine_errors": "zero", "method": "linearised", "trials", "seed",
//    "design": {"points", "grid": [nx, ny, nz], "targets", "observations",
//        "candidate_parameters", "mean_kept_parameters", "unidentifiable": [function names]},
//    "tracker": {"position_mm": [x, y, z], "ypr_deg": [yaw, pitch, roll], "angular_sigma_urad",
//        "radial_sigma_um", "radial_sigma_um_per_m", "samples_per_point", "position_sigma_mm",
//        "orientation_sigma_urad"},
//    "sources": {"repeatability_sigma_um": [3], "expansion_um_per_m_K": [3],
//        "expansion_sigma_um_per_m_K": [3], "temperature_deviation_K": [3],
//        "temperature_sigma_K": [3]},
//    "trial_max_residual_um", "trial_mean_residual_um": the distribution over the trials of the
//        largest and of the mean |e| over the grid (e: the residual error the identified model
//        leaves at a target, solver header), each {"mean_um", "sigma_um", "quantile95_um",
//        "max_um"},
//    "max_bound95_um": the largest per-point 95 % bound,
//    "tracker_alone": {"max_u_p_um", "mean_u_p_um", "worst_point", "worst_target_mm": [3]}:
//        eq. 24 over the grid, tracker at its configured pose,
//    "worst_points": [the 5 largest bound95_um first: point],
//    "points": [every grid point in program order: point],
//        point = {"label", "commanded_mm": [3], "tool_offset_mm": [3], "target_mm": [3],
//                 "mean_um": [3], "sigma_um": [3], "rms_um", "bound95_um", "tracker_u_p_um"},
//    "search": null without --search, else {"x_mm": [min, max], "y_mm", "z_mm", "step_mm",
//        "steps": [3], "envelope_clearance_mm", "min_range_mm", "max_range_mm", "tried",
//        "excluded",
//        "best": {"position_mm": [3], "yaw_deg", "max_u_p_um", "mean_u_p_um", "worst_point"},
//        "configured": {"position_mm": [3], "yaw_deg", "max_u_p_um", "mean_u_p_um"},
//        "candidates": [best first, at most 5: {"position_mm", "yaw_deg", "max_u_p_um",
//            "mean_u_p_um", "worst_point"}]}}
//
// Returns 0 when it printed, 1 on an error it reported (unknown machine, no global_check or no
// global_check.uncertainty, --search without global_check.uncertainty.search, a bad config, a
// design or setup the solver refuses), 2 on bad usage (the usage on stderr).
#pragma once

#include <string>
#include <vector>

namespace ncqual {

extern const char* const kUncertaintyUsage;

// `args`: what follows `ncqual uncertainty` on the command line.
int run_uncertainty(const std::vector<std::string>& args);

}  // namespace ncqual
