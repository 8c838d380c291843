// `ncqual uncertainty`: gathers the machine's planned tracker setup and uncertainty sources from
// its config, hands them to solver::evaluate_verification_uncertainty (and, with --search, to
// solver::best_tracker_location), prints the report. See uncertainty_command.hpp.
#include "uncertainty_command.hpp"

#include "ncqual/args.hpp"
#include "ncqual/config.hpp"
#include "ncqual/solver/verification_uncertainty.hpp"
#include "ncqual/units.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <numeric>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace ncqual {

const char* const kUncertaintyUsage =
    "  uncertainty --machine M [--plant F] [--trials N] [--seed S] [--threads T] [--search]\n"
    "              [--json]\n"
    "      Monte Carlo uncertainty (GUM S1) of the machine's monthly tracker grid check as\n"
    "      configured in global_check.uncertainty (planned tracker, sources); --trials and\n"
    "      --seed override the config, --threads only the speed; --search: the best tracker\n"
    "      location in global_check.uncertainty.search beside the configured one\n";

namespace {

constexpr int kExitError = 1, kExitUsage = 2;
constexpr int kMaxTrials = 1000000;
constexpr int kMaxThreads = 64;
constexpr std::size_t kWorstPoints = 5;
constexpr int kReportedCandidates = 5;

using nlohmann::json;

double um(double mm) { return mm * 1e3; }
double deg(double rad) { return units::rad_to_deg(rad); }
double urad(double rad) { return rad * 1e6; }

json vec(const Eigen::Vector3d& v, double scale = 1) {
  return json::array({v.x() * scale, v.y() * scale, v.z() * scale});
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// "(a, b, c)" with `format` for each.
std::string triple(const char* format, const Eigen::Vector3d& v) {
  return "(" + fmt(format, v.x()) + ", " + fmt(format, v.y()) + ", " + fmt(format, v.z()) + ")";
}

// "a b c" with `format` for each.
std::string three(const char* format, const Eigen::Vector3d& v) {
  return fmt(format, v.x()) + " " + fmt(format, v.y()) + " " + fmt(format, v.z());
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
  solver::TrackerRegion region;
  solver::TrackerLocationSearch result;
};

solver::TrackerUncertaintyModel tracker_model(const PlannedTrackerConfig& t) {
  solver::TrackerUncertaintyModel m;
  m.position_mm = t.position_mm;
  m.ypr_rad = t.ypr_rad;
  m.angular_sigma_rad = t.angular_sigma_rad;
  m.radial_sigma_mm = t.radial_sigma_mm;
  m.radial_sigma_mm_per_m = t.radial_sigma_mm_per_m;
  m.samples_per_point = t.samples_per_point;
  m.position_sigma_mm = t.position_sigma_mm;
  m.orientation_sigma_rad = t.orientation_sigma_rad;
  return m;
}

// The machine verified as it is nominally: systematic errors zero (RigidBodyErrors{}).
solver::UncertaintySources sources_of(const UncertaintySourcesConfig& s) {
  solver::UncertaintySources out;
  out.repeatability_sigma_mm = s.repeatability_sigma_mm;
  out.expansion_per_K = s.expansion_per_K;
  out.expansion_sigma_per_K = s.expansion_sigma_per_K;
  out.temperature_deviation_K = s.temperature_deviation_K;
  out.temperature_sigma_K = s.temperature_sigma_K;
  return out;
}

solver::TrackerRegion region_of(const TrackerSearchConfig& s) {
  solver::TrackerRegion r;
  r.lo_mm = s.lo_mm;
  r.hi_mm = s.hi_mm;
  r.steps = s.steps;
  r.envelope_clearance_mm = s.envelope_clearance_mm;
  r.min_range_mm = s.min_range_mm;
  r.max_range_mm = s.max_range_mm;
  return r;
}

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

json summary_json(const solver::SampleSummary& s) {
  return {{"mean_um", um(s.mean)},
          {"sigma_um", um(s.sigma)},
          {"quantile95_um", um(s.quantile95)},
          {"max_um", um(s.max)}};
}

json point_json(const solver::PointUncertainty& p) {
  return {{"label", p.label},
          {"commanded_mm", vec(p.commanded_mm)},
          {"tool_offset_mm", vec(p.tool_offset_mm)},
          {"target_mm", vec(p.commanded_mm + p.tool_offset_mm)},
          {"mean_um", vec(p.mean_mm, 1e3)},
          {"sigma_um", vec(p.sigma_mm, 1e3)},
          {"rms_um", um(p.rms_mm)},
          {"bound95_um", um(p.bound95_mm)},
          {"tracker_u_p_um", um(p.tracker_u_mm)}};
}

json candidate_json(const solver::TrackerCandidate& c, const solver::VerificationDesign& d) {
  return {{"position_mm", vec(c.position_mm)},
          {"yaw_deg", deg(c.yaw_rad)},
          {"max_u_p_um", um(c.max_u_mm)},
          {"mean_u_p_um", um(c.mean_u_mm)},
          {"worst_point", d.points[static_cast<std::size_t>(c.worst_point)].label}};
}

json search_json(const Search& s, const Inputs& in, const solver::VerificationUncertainty& u) {
  const TrackerSearchConfig& c = *in.config->search;
  json candidates = json::array();
  for (const auto& cand : s.result.candidates) candidates.push_back(candidate_json(cand, in.design));
  const auto& best = s.result.candidates.front();
  return {{"x_mm", json::array({c.lo_mm.x(), c.hi_mm.x()})},
          {"y_mm", json::array({c.lo_mm.y(), c.hi_mm.y()})},
          {"z_mm", json::array({c.lo_mm.z(), c.hi_mm.z()})},
          {"step_mm", c.step_mm},
          {"steps", json::array({c.steps.x(), c.steps.y(), c.steps.z()})},
          {"envelope_clearance_mm", c.envelope_clearance_mm},
          {"min_range_mm", c.min_range_mm},
          {"max_range_mm", c.max_range_mm},
          {"tried", s.result.tried},
          {"excluded", s.result.excluded},
          {"best", candidate_json(best, in.design)},
          {"configured",
           {{"position_mm", vec(in.tracker.position_mm)},
            {"yaw_deg", deg(in.tracker.ypr_rad[0])},
            {"max_u_p_um", um(s.result.given_max_u_mm)},
            {"mean_u_p_um", um(u.tracker_mean_u_mm)}}},
          {"candidates", candidates}};
}

json to_json(const Inputs& in, const solver::VerificationUncertainty& u,
             const std::optional<Search>& search) {
  const GlobalCheckConfig& g = *in.global;
  json points = json::array();
  for (const auto& p : u.points) points.push_back(point_json(p));
  json worst = json::array();
  for (std::size_t i : worst_points(u, kWorstPoints)) worst.push_back(point_json(u.points[i]));
  const std::size_t tw = tracker_worst_point(u);
  const Eigen::Vector3d sigma_alpha = in.sources.expansion_sigma_per_K * 1e6;
  return {
      {"machine_id", in.machine->machine_id},
      {"config", in.machine->source_path},
      {"plant", in.plant_file},
      {"machine_errors", "zero"},
      {"method", u.method == solver::IdentificationMethod::Linearised ? "linearised" : "full"},
      {"trials", u.trials},
      {"seed", in.options.seed},
      {"design",
       {{"points", u.points.size()},
        {"grid", json::array({g.grid_x_mm.size(), g.grid_y_mm.size(), g.grid_z_mm.size()})},
        {"targets", g.targets.size()},
        {"observations", u.observations},
        {"candidate_parameters", u.candidate_parameters},
        {"mean_kept_parameters", u.mean_kept_parameters},
        {"unidentifiable", u.unidentifiable}}},
      {"tracker",
       {{"position_mm", vec(in.tracker.position_mm)},
        {"ypr_deg", vec(in.tracker.ypr_rad, units::rad_to_deg(1.0))},
        {"angular_sigma_urad", urad(in.tracker.angular_sigma_rad)},
        {"radial_sigma_um", um(in.tracker.radial_sigma_mm)},
        {"radial_sigma_um_per_m", um(in.tracker.radial_sigma_mm_per_m)},
        {"samples_per_point", in.tracker.samples_per_point},
        {"position_sigma_mm", in.tracker.position_sigma_mm},
        {"orientation_sigma_urad", urad(in.tracker.orientation_sigma_rad)}}},
      {"sources",
       {{"repeatability_sigma_um", vec(in.sources.repeatability_sigma_mm, 1e3)},
        {"expansion_um_per_m_K", vec(in.sources.expansion_per_K, 1e6)},
        {"expansion_sigma_um_per_m_K", vec(sigma_alpha)},
        {"temperature_deviation_K", vec(in.sources.temperature_deviation_K)},
        {"temperature_sigma_K", vec(in.sources.temperature_sigma_K)}}},
      {"trial_max_residual_um", summary_json(u.max_residual_mm)},
      {"trial_mean_residual_um", summary_json(u.mean_residual_mm)},
      {"max_bound95_um", um(max_bound95(u))},
      {"tracker_alone",
       {{"max_u_p_um", um(u.tracker_max_u_mm)},
        {"mean_u_p_um", um(u.tracker_mean_u_mm)},
        {"worst_point", u.points[tw].label},
        {"worst_target_mm", vec(u.points[tw].commanded_mm + u.points[tw].tool_offset_mm)}}},
      {"worst_points", worst},
      {"points", points},
      {"search", search ? search_json(*search, in, u) : json()},
  };
}

// ---- Text ---------------------------------------------------------------------------------------

void print_report(const Inputs& in, const solver::VerificationUncertainty& u,
                  const std::optional<Search>& search) {
  const GlobalCheckConfig& g = *in.global;
  const solver::TrackerUncertaintyModel& t = in.tracker;
  const solver::UncertaintySources& s = in.sources;
  std::printf("Verification uncertainty of %s (%s):\n  the monthly tracker grid check, Monte "
              "Carlo (GUM S1)\n",
              in.machine->machine_id.c_str(), in.machine->source_path.c_str());
  std::printf("  design: %zu points (%zu x %zu x %zu grid x %zu targets), %d observations;\n    "
              "%d candidate parameters, %.1f kept on average by the BIC\n",
              u.points.size(), g.grid_x_mm.size(), g.grid_y_mm.size(), g.grid_z_mm.size(),
              g.targets.size(), u.observations, u.candidate_parameters, u.mean_kept_parameters);
  if (!u.unidentifiable.empty()) {
    std::string names;
    for (const auto& n : u.unidentifiable) names += (names.empty() ? "" : ", ") + n;
    std::printf("  the design cannot determine: %s\n", names.c_str());
  }
  std::printf("  machine errors: zero (the machine verified as it is nominally: what is left is\n"
              "  what the tracker, the repeatability and the thermal correction leave)\n");
  std::printf("  %d trials, seed %llu, %s identification\n", u.trials,
              static_cast<unsigned long long>(in.options.seed),
              u.method == solver::IdentificationMethod::Linearised ? "linearised" : "full");
  std::printf("  tracker at %s mm, yaw %.2f pitch %.2f roll %.2f deg\n    noise %.1f urad per "
              "angle, range %.2f um + %.2f um/m, %d readings a point\n    placement %.2f mm, "
              "%.1f urad (1 sigma)\n",
              triple("%.0f", t.position_mm).c_str(), deg(t.ypr_rad[0]), deg(t.ypr_rad[1]),
              deg(t.ypr_rad[2]), urad(t.angular_sigma_rad), um(t.radial_sigma_mm),
              um(t.radial_sigma_mm_per_m), t.samples_per_point, t.position_sigma_mm,
              urad(t.orientation_sigma_rad));
  std::printf("  sources (X Y Z): repeatability %s um\n    expansion %s +- %s um/(m K)\n"
              "    temperature deviation %s +- %s K\n",
              three("%.2f", s.repeatability_sigma_mm * 1e3).c_str(),
              three("%.2f", s.expansion_per_K * 1e6).c_str(),
              three("%.2f", s.expansion_sigma_per_K * 1e6).c_str(),
              three("%.2f", s.temperature_deviation_K).c_str(),
              three("%.2f", s.temperature_sigma_K).c_str());

  std::printf("\nResidual error after the identification, |e| over the grid in each trial (um)\n");
  std::printf("  %-12s %8s %8s %8s %8s\n", "", "mean", "sigma", "95 %", "largest");
  const auto row = [](const char* name, const solver::SampleSummary& v) {
    std::printf("  %-12s %8.2f %8.2f %8.2f %8.2f\n", name, um(v.mean), um(v.sigma),
                um(v.quantile95), um(v.max));
  };
  row("max |e|", u.max_residual_mm);
  row("mean |e|", u.mean_residual_mm);

  std::printf("\nWorst points: 95 %% bound of |e| (um), target in mm\n");
  std::printf("  %-14s %-26s %8s %8s %-22s %8s\n", "point", "target", "bound95", "rms",
              "sigma x y z", "track.u");
  for (std::size_t i : worst_points(u, kWorstPoints)) {
    const auto& p = u.points[i];
    std::printf("  %-14s %-26s %8.2f %8.2f %-22s %8.2f\n", p.label.c_str(),
                triple("%.0f", p.commanded_mm + p.tool_offset_mm).c_str(), um(p.bound95_mm),
                um(p.rms_mm), three("%.2f", p.sigma_mm * 1e3).c_str(), um(p.tracker_u_mm));
  }

  const std::size_t tw = tracker_worst_point(u);
  std::printf("\nTracker alone (eq. 24, the configured pose): max u_p %.2f um at %s %s mm,\n"
              "  mean %.2f um\n",
              um(u.tracker_max_u_mm), u.points[tw].label.c_str(),
              triple("%.0f", u.points[tw].commanded_mm + u.points[tw].tool_offset_mm).c_str(),
              um(u.tracker_mean_u_mm));

  if (!search) return;
  const TrackerSearchConfig& c = *in.config->search;
  const auto& r = search->result;
  std::printf("\nTracker location (eq. 24 over the grid, facing the envelope's centre)\n");
  std::printf("  searched x %.0f..%.0f, y %.0f..%.0f, z %.0f..%.0f mm, %d x %d x %d positions:\n"
              "    %d tried, %d excluded (envelope + %.0f mm, range %.0f..%.0f mm)\n",
              c.lo_mm.x(), c.hi_mm.x(), c.lo_mm.y(), c.hi_mm.y(), c.lo_mm.z(), c.hi_mm.z(),
              c.steps.x(), c.steps.y(), c.steps.z(), r.tried, r.excluded,
              c.envelope_clearance_mm, c.min_range_mm, c.max_range_mm);
  std::printf("  best       %s mm, yaw %7.2f deg: max u_p %.2f um, mean %.2f um\n",
              triple("%.0f", r.best.position_mm).c_str(), deg(r.best.ypr_rad[0]), um(r.max_u_mm),
              um(r.mean_u_mm));
  std::printf("  configured %s mm, yaw %7.2f deg: max u_p %.2f um, mean %.2f um\n",
              triple("%.0f", t.position_mm).c_str(), deg(t.ypr_rad[0]), um(r.given_max_u_mm),
              um(u.tracker_mean_u_mm));
  if (r.given_max_u_mm > 0) {
    std::printf("  the best candidate changes the largest u_p by %+.1f %%\n",
                100 * (r.max_u_mm / r.given_max_u_mm - 1));
  }
}

// ---- Command ------------------------------------------------------------------------------------

int usage_error(const std::string& message) {
  std::cerr << "ncqual uncertainty: " << message << "\nusage:\n" << kUncertaintyUsage;
  return kExitUsage;
}

int default_threads() {
  const unsigned n = std::thread::hardware_concurrency();
  return static_cast<int>(std::clamp(n, 1u, static_cast<unsigned>(kMaxThreads)));
}

int run(const Args& args) {
  if (!args.positional().empty()) {
    throw ArgError("unexpected argument '" + args.positional().front() + "'");
  }
  Inputs in;
  in.plant_file = plant_config_path(args.get_or("plant", ""));
  if (in.plant_file.empty()) throw ArgError("pass --plant FILE (or set NCQUAL_PLANT)");
  const std::string machine_id = args.require("machine");
  const int trials = args.get_int("trials", 0);  // 0: the config's
  if (args.has("trials") && (trials < 1 || trials > kMaxTrials)) {
    throw ArgError("--trials " + std::to_string(trials) + ": expected 1 to " +
                   std::to_string(kMaxTrials));
  }
  const std::int64_t seed = args.get_int64("seed", 0);
  if (seed < 0) throw ArgError("--seed " + std::to_string(seed) + ": expected >= 0");
  const int threads = args.get_int("threads", default_threads());
  if (threads < 1 || threads > kMaxThreads) {
    throw ArgError("--threads " + std::to_string(threads) + ": expected 1 to " +
                   std::to_string(kMaxThreads));
  }

  const PlantConfig plant = load_plant_config(in.plant_file);
  in.machine = plant.find_machine(machine_id);
  if (!in.machine) {
    std::cerr << "ncqual uncertainty: machine '" << machine_id << "' is not configured in "
              << plant.source_path << "\n";
    return kExitError;
  }
  if (!in.machine->global_check) {
    std::cerr << "ncqual uncertainty: machine '" << machine_id << "' (" << in.machine->source_path
              << ") has no global_check: section: it has no tracker verification to assess\n";
    return kExitError;
  }
  in.global = &*in.machine->global_check;
  if (!in.global->uncertainty) {
    std::cerr << "ncqual uncertainty: machine '" << machine_id << "' (" << in.machine->source_path
              << ") has no global_check.uncertainty: mapping (the planned tracker and the "
                 "uncertainty sources; see ncqual/global_check.hpp)\n";
    return kExitError;
  }
  in.config = &*in.global->uncertainty;
  if (args.has("search") && !in.config->search) {
    std::cerr << "ncqual uncertainty: --search: machine '" << machine_id << "' ("
              << in.machine->source_path
              << ") has no global_check.uncertainty.search: mapping (where the tracker may "
                 "stand)\n";
    return kExitError;
  }

  in.design = solver::grid_verification_design(*in.global);
  in.tracker = tracker_model(in.config->tracker);
  in.sources = sources_of(in.config->sources);
  in.options.trials = args.has("trials") ? trials : in.config->trials;
  in.options.seed = args.has("seed") ? static_cast<std::uint64_t>(seed) : in.config->seed;
  in.options.threads = threads;
  in.options.method = solver::IdentificationMethod::Linearised;

  const solver::VerificationUncertainty u =
      solver::evaluate_verification_uncertainty(in.design, in.tracker, in.sources, in.options);
  std::optional<Search> search;
  if (args.has("search")) {
    Search s;
    s.region = region_of(*in.config->search);
    solver::LocationSearchOptions options;
    options.report = kReportedCandidates;
    s.result = solver::best_tracker_location(in.design, in.tracker, s.region, options);
    search = std::move(s);
  }

  if (args.has("json")) {
    std::cout << to_json(in, u, search).dump(2) << "\n";
  } else {
    print_report(in, u, search);
  }
  return 0;
}

}  // namespace

int run_uncertainty(const std::vector<std::string>& args) {
  if (std::find(args.begin(), args.end(), "--help") != args.end()) {
    std::cout << "usage:\n" << kUncertaintyUsage;
    return 0;
  }
  try {
    const Args parsed(args, {"machine", "plant", "trials", "seed", "threads"}, {"search", "json"});
    return run(parsed);
  } catch (const ArgError& e) {
    return usage_error(e.what());
  } catch (const ConfigError& e) {
    std::cerr << "ncqual uncertainty: " << e.what() << "\n";
    return kExitError;
  } catch (const std::invalid_argument& e) {
    std::cerr << "ncqual uncertainty: " << e.what() << "\n";
    return kExitError;
  }
}

}  // namespace ncqual
