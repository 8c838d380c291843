// SPDX-License-Identifier: Apache-2.0
// `ncqual uncertainty`: the uncertainty of a machine's monthly laser-tracker verification (the
// grid check and its identification of the 21 rigid-body errors), by Monte Carlo (GUM S1).
//
//   ncqual uncertainty --machine M [--plant F] [--trials N] [--seed S] [--threads T] [--search]
//                      [--json]
//
// Reads the machine's `global_check:` section from the plant config (--plant or NCQUAL_PLANT)
// and its `uncertainty:` mapping (ncqual/common/global_check.hpp: the planned tracker, the
// uncertainty sources, trials, seed, the search region), builds the grid design of the GlobalGrid
// program (solver::grid_verification_design) and runs solver::evaluate_verification_uncertainty on
// it with the machine's systematic errors zero: the machine verified as it is nominally, so what is
// left after the identification is what the tracker's noise and placement, the repeatability and
// the thermal correction leave (the figures do not depend on the errors as long as the model
// represents them). --trials and --seed override the config; --threads (default: the hardware's
// cores, at most 64) only changes the speed, never a figure. With --search it also runs
// solver::best_tracker_location over the configured search region (eq. 24, no Monte Carlo) and
// compares the best candidate with the configured position. This command only gathers and
// prints; the math is the solver's (ncqual/solver/verification_uncertainty.hpp).
//
// --json prints one document (UncertaintyDocument below); its names are a public interface
// (append, never rename):
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
// Returns 0 when it printed, 1 on an error it reported (no global_check or no
// global_check.uncertainty, --search without global_check.uncertainty.search, a bad config, a
// design or setup the solver refuses), 2 on bad usage (the message and the usage on stderr; and a
// machine the plant does not configure).
#include "commands.hpp"

#include "ncqual/common/config.hpp"
#include "ncqual/common/json.hpp"
#include "ncqual/solver/verification_uncertainty.hpp"
#include "ncqual/common/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <iostream>
#include <numeric>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace ncqual::cli {
namespace {

constexpr int kMaxTrials = 1000000;
constexpr int kMaxThreads = 64;
constexpr std::size_t kWorstPoints = 5;
constexpr int kReportedCandidates = 5;

double um(double mm) { return mm * 1e3; }
double deg(double rad) { return units::rad_to_deg(rad); }
double urad(double rad) { return rad * 1e6; }

// "(a, b, c)" with `decimals` each.
std::string triple(int decimals, const Eigen::Vector3d& v) {
  return fmt::format("({:.{}f}, {:.{}f}, {:.{}f})", v.x(), decimals, v.y(), decimals, v.z(),
                     decimals);
}

// "a b c" with two decimals each.
std::string three(const Eigen::Vector3d& v) {
  return fmt::format("{:.2f} {:.2f} {:.2f}", v.x(), v.y(), v.z());
}

// Everything one run gathers and computes.
struct Inputs {
  std::string plant_file;
  const MachineConfig* machine = nullptr;
  const GlobalCheckConfig* global = nullptr;
  const VerificationUncertaintyConfig* config = nullptr;
  solver::VerificationDesign design;
  solver::TrackerUncertaintyModel tracker;
  solver::UncertaintySources sources;
  solver::MonteCarloOptions options;
};

struct Search {
  solver::TrackerLocationSearch result;
};

// Design indices, the largest 95 % bound first (design order among equals), at most `n`.
std::vector<std::size_t> worst_points(const solver::VerificationUncertainty& u, std::size_t n) {
  std::vector<std::size_t> order(u.points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return u.points[a].bound95_mm > u.points[b].bound95_mm;
  });
  order.resize(std::min(n, order.size()));
  return order;
}

// The design index of the largest tracker-alone u_p (the first of equals).
std::size_t tracker_worst_point(const solver::VerificationUncertainty& u) {
  std::size_t worst = 0;
  for (std::size_t i = 1; i < u.points.size(); ++i) {
    if (u.points[i].tracker_u_mm > u.points[worst].tracker_u_mm) worst = i;
  }
  return worst;
}

double max_bound95(const solver::VerificationUncertainty& u) {
  double m = 0;
  for (const auto& p : u.points) m = std::max(m, p.bound95_mm);
  return m;
}

// ---- JSON ---------------------------------------------------------------------------------------

// The --json document (names: the file comment above).
struct SummaryDocument {
  double mean_um = 0, sigma_um = 0, quantile95_um = 0, max_um = 0;
};
struct PointDocument {
  std::string label;
  Eigen::Vector3d commanded_mm, tool_offset_mm, target_mm, mean_um, sigma_um;
  double rms_um = 0, bound95_um = 0, tracker_u_p_um = 0;
};
struct DesignDocument {
  std::size_t points = 0;
  std::array<std::size_t, 3> grid{};
  std::size_t targets = 0;
  int observations = 0, candidate_parameters = 0;
  double mean_kept_parameters = 0;
  std::vector<std::string> unidentifiable;
};
struct TrackerDocument {
  Eigen::Vector3d position_mm, ypr_deg;
  double angular_sigma_urad = 0, radial_sigma_um = 0, radial_sigma_um_per_m = 0;
  int samples_per_point = 0;
  double position_sigma_mm = 0, orientation_sigma_urad = 0;
};
struct SourcesDocument {
  Eigen::Vector3d repeatability_sigma_um, expansion_um_per_m_K, expansion_sigma_um_per_m_K,
      temperature_deviation_K, temperature_sigma_K;
};
struct TrackerAloneDocument {
  double max_u_p_um = 0, mean_u_p_um = 0;
  std::string worst_point;
  Eigen::Vector3d worst_target_mm;
};
struct CandidateDocument {
  Eigen::Vector3d position_mm;
  double yaw_deg = 0, max_u_p_um = 0, mean_u_p_um = 0;
  std::string worst_point;
};
struct ConfiguredDocument {
  Eigen::Vector3d position_mm;
  double yaw_deg = 0, max_u_p_um = 0, mean_u_p_um = 0;
};
struct SearchDocument {
  Eigen::Vector2d x_mm, y_mm, z_mm;  // [min, max]
  double step_mm = 0;
  std::array<int, 3> steps{};
  double envelope_clearance_mm = 0, min_range_mm = 0, max_range_mm = 0;
  int tried = 0, excluded = 0;
  CandidateDocument best;
  ConfiguredDocument configured;
  std::vector<CandidateDocument> candidates;
};
struct UncertaintyDocument {
  std::string machine_id, config, plant;
  std::string machine_errors = "zero";
  std::string method;
  int trials = 0;
  std::uint64_t seed = 0;
  DesignDocument design;
  TrackerDocument tracker;
  SourcesDocument sources;
  SummaryDocument trial_max_residual_um, trial_mean_residual_um;
  double max_bound95_um = 0;
  TrackerAloneDocument tracker_alone;
  std::vector<PointDocument> worst_points, points;
  std::optional<SearchDocument> search;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(SummaryDocument, mean_um, sigma_um, quantile95_um, max_um)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(PointDocument, label, commanded_mm, tool_offset_mm, target_mm,
                                   mean_um, sigma_um, rms_um, bound95_um, tracker_u_p_um)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(DesignDocument, points, grid, targets, observations,
                                   candidate_parameters, mean_kept_parameters, unidentifiable)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TrackerDocument, position_mm, ypr_deg, angular_sigma_urad,
                                   radial_sigma_um, radial_sigma_um_per_m, samples_per_point,
                                   position_sigma_mm, orientation_sigma_urad)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(SourcesDocument, repeatability_sigma_um, expansion_um_per_m_K,
                                   expansion_sigma_um_per_m_K, temperature_deviation_K,
                                   temperature_sigma_K)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TrackerAloneDocument, max_u_p_um, mean_u_p_um, worst_point,
                                   worst_target_mm)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CandidateDocument, position_mm, yaw_deg, max_u_p_um, mean_u_p_um,
                                   worst_point)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ConfiguredDocument, position_mm, yaw_deg, max_u_p_um,
                                   mean_u_p_um)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(SearchDocument, x_mm, y_mm, z_mm, step_mm, steps,
                                   envelope_clearance_mm, min_range_mm, max_range_mm, tried,
                                   excluded, best, configured, candidates)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(UncertaintyDocument, machine_id, config, plant, machine_errors,
                                   method, trials, seed, design, tracker, sources,
                                   trial_max_residual_um, trial_mean_residual_um, max_bound95_um,
                                   tracker_alone, worst_points, points, search)

SummaryDocument summary_document(const solver::SampleSummary& s) {
  return {um(s.mean), um(s.sigma), um(s.quantile95), um(s.max)};
}

PointDocument point_document(const solver::PointUncertainty& p) {
  return {p.label,           p.commanded_mm,   p.tool_offset_mm, p.commanded_mm + p.tool_offset_mm,
          p.mean_mm * 1e3,   p.sigma_mm * 1e3, um(p.rms_mm),     um(p.bound95_mm),
          um(p.tracker_u_mm)};
}

CandidateDocument candidate_document(const solver::TrackerCandidate& c,
                                     const solver::VerificationDesign& d) {
  return {c.position_mm, deg(c.yaw_rad), um(c.max_u_mm), um(c.mean_u_mm),
          d.points[static_cast<std::size_t>(c.worst_point)].label};
}

SearchDocument search_document(const Search& s, const Inputs& in,
                               const solver::VerificationUncertainty& u) {
  const TrackerSearchConfig& c = *in.config->search;
  SearchDocument d;
  d.x_mm = {c.lo_mm.x(), c.hi_mm.x()};
  d.y_mm = {c.lo_mm.y(), c.hi_mm.y()};
  d.z_mm = {c.lo_mm.z(), c.hi_mm.z()};
  d.step_mm = c.step_mm;
  d.steps = {c.steps.x(), c.steps.y(), c.steps.z()};
  d.envelope_clearance_mm = c.envelope_clearance_mm;
  d.min_range_mm = c.min_range_mm;
  d.max_range_mm = c.max_range_mm;
  d.tried = s.result.tried;
  d.excluded = s.result.excluded;
  d.best = candidate_document(s.result.candidates.front(), in.design);
  d.configured = {in.tracker.position_mm, deg(in.tracker.ypr_rad[0]), um(s.result.given_max_u_mm),
                  um(u.tracker_mean_u_mm)};
  for (const auto& cand : s.result.candidates) {
    d.candidates.push_back(candidate_document(cand, in.design));
  }
  return d;
}

UncertaintyDocument document_of(const Inputs& in, const solver::VerificationUncertainty& u,
                                const std::optional<Search>& search) {
  const GlobalCheckConfig& g = *in.global;
  UncertaintyDocument d;
  d.machine_id = in.machine->machine_id;
  d.config = in.machine->source_path;
  d.plant = in.plant_file;
  d.method = u.method == solver::IdentificationMethod::Linearised ? "linearised" : "full";
  d.trials = u.trials;
  d.seed = in.options.seed;
  d.design = {u.points.size(),        {g.grid_x_mm.size(), g.grid_y_mm.size(), g.grid_z_mm.size()},
              g.targets.size(),       u.observations,
              u.candidate_parameters, u.mean_kept_parameters,
              u.unidentifiable};
  const auto& t = in.tracker;
  d.tracker = {t.position_mm,         t.ypr_rad * units::rad_to_deg(1.0), urad(t.angular_sigma_rad),
               um(t.radial_sigma_mm), um(t.radial_sigma_mm_per_m),        t.samples_per_point,
               t.position_sigma_mm,   urad(t.orientation_sigma_rad)};
  d.sources = {in.sources.repeatability_sigma_mm * 1e3, in.sources.expansion_per_K * 1e6,
               in.sources.expansion_sigma_per_K * 1e6, in.sources.temperature_deviation_K,
               in.sources.temperature_sigma_K};
  d.trial_max_residual_um = summary_document(u.max_residual_mm);
  d.trial_mean_residual_um = summary_document(u.mean_residual_mm);
  d.max_bound95_um = um(max_bound95(u));
  const std::size_t tw = tracker_worst_point(u);
  d.tracker_alone = {um(u.tracker_max_u_mm), um(u.tracker_mean_u_mm), u.points[tw].label,
                     u.points[tw].commanded_mm + u.points[tw].tool_offset_mm};
  for (std::size_t i : worst_points(u, kWorstPoints)) {
    d.worst_points.push_back(point_document(u.points[i]));
  }
  for (const auto& p : u.points) d.points.push_back(point_document(p));
  if (search) d.search = search_document(*search, in, u);
  return d;
}

// ---- Text ---------------------------------------------------------------------------------------

void print_report(const Inputs& in, const solver::VerificationUncertainty& u,
                  const std::optional<Search>& search) {
  const GlobalCheckConfig& g = *in.global;
  const solver::TrackerUncertaintyModel& t = in.tracker;
  const solver::UncertaintySources& s = in.sources;
  fmt::print(
      "Verification uncertainty of {} ({}):\n  the monthly tracker grid check, Monte "
      "Carlo (GUM S1)\n",
      in.machine->machine_id, in.machine->source_path);
  fmt::print(
      "  design: {} points ({} x {} x {} grid x {} targets), {} observations;\n    "
      "{} candidate parameters, {:.1f} kept on average by the BIC\n",
      u.points.size(), g.grid_x_mm.size(), g.grid_y_mm.size(), g.grid_z_mm.size(), g.targets.size(),
      u.observations, u.candidate_parameters, u.mean_kept_parameters);
  if (!u.unidentifiable.empty()) {
    fmt::print("  the design cannot determine: {}\n", fmt::join(u.unidentifiable, ", "));
  }
  fmt::print(
      "  machine errors: zero (the machine verified as it is nominally: what is left is\n"
      "  what the tracker, the repeatability and the thermal correction leave)\n");
  fmt::print("  {} trials, seed {}, {} identification\n", u.trials, in.options.seed,
             u.method == solver::IdentificationMethod::Linearised ? "linearised" : "full");
  fmt::print(
      "  tracker at {} mm, yaw {:.2f} pitch {:.2f} roll {:.2f} deg\n    noise {:.1f} urad per "
      "angle, range {:.2f} um + {:.2f} um/m, {} readings a point\n    placement {:.2f} mm, "
      "{:.1f} urad (1 sigma)\n",
      triple(0, t.position_mm), deg(t.ypr_rad[0]), deg(t.ypr_rad[1]), deg(t.ypr_rad[2]),
      urad(t.angular_sigma_rad), um(t.radial_sigma_mm), um(t.radial_sigma_mm_per_m),
      t.samples_per_point, t.position_sigma_mm, urad(t.orientation_sigma_rad));
  fmt::print(
      "  sources (X Y Z): repeatability {} um\n    expansion {} +- {} um/(m K)\n"
      "    temperature deviation {} +- {} K\n",
      three(s.repeatability_sigma_mm * 1e3), three(s.expansion_per_K * 1e6),
      three(s.expansion_sigma_per_K * 1e6), three(s.temperature_deviation_K),
      three(s.temperature_sigma_K));

  fmt::print("\nResidual error after the identification, |e| over the grid in each trial (um)\n");
  fmt::print("  {:<12} {:>8} {:>8} {:>8} {:>8}\n", "", "mean", "sigma", "95 %", "largest");
  const auto row = [](const char* name, const solver::SampleSummary& v) {
    fmt::print("  {:<12} {:8.2f} {:8.2f} {:8.2f} {:8.2f}\n", name, um(v.mean), um(v.sigma),
               um(v.quantile95), um(v.max));
  };
  row("max |e|", u.max_residual_mm);
  row("mean |e|", u.mean_residual_mm);

  fmt::print("\nWorst points: 95 % bound of |e| (um), target in mm\n");
  fmt::print("  {:<14} {:<26} {:>8} {:>8} {:<22} {:>8}\n", "point", "target", "bound95", "rms",
             "sigma x y z", "track.u");
  for (std::size_t i : worst_points(u, kWorstPoints)) {
    const auto& p = u.points[i];
    fmt::print("  {:<14} {:<26} {:8.2f} {:8.2f} {:<22} {:8.2f}\n", p.label,
               triple(0, p.commanded_mm + p.tool_offset_mm), um(p.bound95_mm), um(p.rms_mm),
               three(p.sigma_mm * 1e3), um(p.tracker_u_mm));
  }

  const std::size_t tw = tracker_worst_point(u);
  fmt::print(
      "\nTracker alone (eq. 24, the configured pose): max u_p {:.2f} um at {} {} mm,\n"
      "  mean {:.2f} um\n",
      um(u.tracker_max_u_mm), u.points[tw].label,
      triple(0, u.points[tw].commanded_mm + u.points[tw].tool_offset_mm), um(u.tracker_mean_u_mm));

  if (!search) return;
  const TrackerSearchConfig& c = *in.config->search;
  const auto& r = search->result;
  fmt::print("\nTracker location (eq. 24 over the grid, facing the envelope's centre)\n");
  fmt::print(
      "  searched x {:.0f}..{:.0f}, y {:.0f}..{:.0f}, z {:.0f}..{:.0f} mm, {} x {} x {} "
      "positions:\n    {} tried, {} excluded (envelope + {:.0f} mm, range {:.0f}..{:.0f} "
      "mm)\n",
      c.lo_mm.x(), c.hi_mm.x(), c.lo_mm.y(), c.hi_mm.y(), c.lo_mm.z(), c.hi_mm.z(), c.steps.x(),
      c.steps.y(), c.steps.z(), r.tried, r.excluded, c.envelope_clearance_mm, c.min_range_mm,
      c.max_range_mm);
  fmt::print("  best       {} mm, yaw {:7.2f} deg: max u_p {:.2f} um, mean {:.2f} um\n",
             triple(0, r.best.position_mm), deg(r.best.ypr_rad[0]), um(r.max_u_mm),
             um(r.mean_u_mm));
  fmt::print("  configured {} mm, yaw {:7.2f} deg: max u_p {:.2f} um, mean {:.2f} um\n",
             triple(0, t.position_mm), deg(t.ypr_rad[0]), um(r.given_max_u_mm),
             um(u.tracker_mean_u_mm));
  if (r.given_max_u_mm > 0) {
    fmt::print("  the best candidate changes the largest u_p by {:+.1f} %\n",
               100 * (r.max_u_mm / r.given_max_u_mm - 1));
  }
}

// ---- Command ------------------------------------------------------------------------------------

int default_threads() {
  const unsigned n = std::thread::hardware_concurrency();
  return static_cast<int>(std::clamp(n, 1u, static_cast<unsigned>(kMaxThreads)));
}

struct Options {
  std::string plant, machine;
  std::optional<int> trials;
  std::optional<std::int64_t> seed;
  int threads = default_threads();
  bool search = false, json = false;
};

int run(const Options& o) {
  Inputs in;
  in.plant_file = plant_config_path(o.plant);
  if (in.plant_file.empty()) throw UsageError("pass --plant FILE (or set NCQUAL_PLANT)");
  const std::string& machine_id = o.machine;

  const PlantConfig plant = load_plant_config(in.plant_file);
  in.machine = &configured_machine(plant, machine_id);
  if (!in.machine->global_check) {
    std::cerr << "ncqual uncertainty: machine '" << machine_id << "' (" << in.machine->source_path
              << ") has no global_check: section: it has no tracker verification to assess\n";
    return kExitError;
  }
  in.global = &*in.machine->global_check;
  if (!in.global->uncertainty) {
    std::cerr << "ncqual uncertainty: machine '" << machine_id << "' (" << in.machine->source_path
              << ") has no global_check.uncertainty: mapping (the planned tracker and the "
                 "uncertainty sources; see ncqual/common/global_check.hpp)\n";
    return kExitError;
  }
  in.config = &*in.global->uncertainty;
  if (o.search && !in.config->search) {
    std::cerr << "ncqual uncertainty: --search: machine '" << machine_id << "' ("
              << in.machine->source_path
              << ") has no global_check.uncertainty.search: mapping (where the tracker may "
                 "stand)\n";
    return kExitError;
  }

  in.design = solver::grid_verification_design(*in.global);
  in.tracker = in.config->tracker;
  // The machine verified as it is nominally: systematic errors zero (RigidBodyErrors{}).
  in.sources = {in.config->sources, volumetric::RigidBodyErrors{}};
  in.options.trials = o.trials.value_or(in.config->trials);
  in.options.seed = o.seed ? static_cast<std::uint64_t>(*o.seed) : in.config->seed;
  in.options.threads = o.threads;
  in.options.method = solver::IdentificationMethod::Linearised;

  const solver::VerificationUncertainty u =
      solver::evaluate_verification_uncertainty(in.design, in.tracker, in.sources, in.options);
  std::optional<Search> search;
  if (o.search) {
    Search s;
    solver::LocationSearchOptions options;
    options.report = kReportedCandidates;
    s.result = solver::best_tracker_location(in.design, in.tracker, *in.config->search, options);
    search = std::move(s);
  }

  if (o.json) {
    std::cout << nlohmann::json(document_of(in, u, search)).dump(2) << "\n";
  } else {
    print_report(in, u, search);
  }
  return kExitOk;
}

}  // namespace

void add_uncertainty(CLI::App& app, Commands& commands) {
  const auto [cmd, o] = add_command(
      app, commands, "uncertainty",
      "Monte Carlo uncertainty (GUM S1) of the machine's monthly tracker grid check as\n"
      "configured in global_check.uncertainty (planned tracker, sources), and with --search\n"
      "the tracker location in global_check.uncertainty.search beside the configured one",
      run);
  add_machine_option(cmd, o->machine, "the machine whose global_check: section to assess");
  add_plant_option(cmd, o->plant);
  cmd->add_option(
         "--trials", o->trials,
         "Monte Carlo trials, 1 to " + std::to_string(kMaxTrials) + " (default: the config's)")
      ->type_name("N")
      ->check(CLI::Range(1, kMaxTrials).description(""));
  cmd->add_option("--seed", o->seed, "the random seed, >= 0 (default: the config's)")
      ->type_name("S")
      ->check(CLI::NonNegativeNumber.description(""));
  cmd->add_option("--threads", o->threads,
                  "threads, 1 to " + std::to_string(kMaxThreads) +
                      "; they change only the speed, never a figure")
      ->type_name("T")
      ->capture_default_str()
      ->check(CLI::Range(1, kMaxThreads).description(""));
  cmd->add_flag("--search", o->search, "also the best tracker location of the search region");
  add_json_flag(cmd, o->json);
}

}  // namespace ncqual::cli
