// SPDX-License-Identifier: Apache-2.0
// A generated historian (history_gen.hpp).
#include "history_gen.hpp"

#include "ncqual/acquisition/instruments.hpp"
#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/clock.hpp"
#include "ncqual/solver/solve.hpp"
#include "ncqual/historian/trend_watch.hpp"

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <utility>

namespace ncqual::history {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::int64_t kSecond = 1'000'000'000;
constexpr std::int64_t kMinute = 60 * kSecond;
constexpr std::int64_t kHour = 60 * kMinute;
constexpr std::int64_t kDay = 24 * kHour;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// "20260105T050000Z", as the scheduler writes the time of issue into its request ids.
std::string compact_time(std::int64_t t_ns) {
  char buffer[32];
  const std::string_view iso = format_iso8601(t_ns, buffer);
  std::string out;
  for (char c : iso.substr(0, 19)) {
    if (c != '-' && c != ':') out += c;
  }
  return out + "Z";
}

// Monday 0 .. Sunday 6 (1970-01-01 was a Thursday).
int weekday(std::int64_t t_ns) {
  const std::int64_t days = t_ns >= 0 ? t_ns / kDay : (t_ns - kDay + 1) / kDay;
  return static_cast<int>(((days % 7) + 7 + 3) % 7);
}

int day_of_month(std::int64_t t_ns) {
  char buffer[32];
  const std::string_view iso = format_iso8601(t_ns, buffer);
  return std::stoi(std::string(iso.substr(8, 2)));
}

// A uniform draw in [lo, hi) from the generator's own arithmetic (the same on every platform).
double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

struct Drawn {
  std::uint64_t simulator_seed = 0;
  std::optional<sim::SimulatorDrift> drift;
};

// What machine `index` gets from the seed: its own stream, so machine k is the same whatever the
// number of machines.
Drawn draw(const GenerateOptions& options, int index, bool has_fixture) {
  std::mt19937_64 rng(options.seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(index));
  Drawn d;
  d.simulator_seed = rng();
  if (uniform(rng, 0, 1) >= options.drift_share) return d;
  sim::SimulatorDrift drift;
  drift.since_ns = options.start_ns;
  const double sign = uniform(rng, 0, 1) < 0.5 ? -1.0 : 1.0;
  const double which = uniform(rng, 0, 1);
  if (which < 0.4) {  // the machine creeping along Y (a scale's reading head slipping)
    drift.machine_shift_mm_per_day.y() = sign * uniform(rng, 0.15e-3, 1.0e-3);
  } else if (which < 0.7) {  // ... along X
    drift.machine_shift_mm_per_day.x() = sign * uniform(rng, 0.15e-3, 1.0e-3);
  } else {  // the probe's tool length growing (a loosening stylus, a warming spindle)
    drift.tool_length_error_mm_per_day = sign * uniform(rng, 0.1e-3, 0.6e-3);
  }
  if (has_fixture && uniform(rng, 0, 1) < 0.5) {  // the fixture's column zeros moving
    drift.fixture_column_x_offset_mm_per_day = uniform(rng, 0.5e-3, 2.0e-3);
  }
  d.drift = drift;
  return d;
}

// The truth of a drifting simulator as of `t_ns` folded into its base: the same truth from then
// on with the drift restarting at `t_ns`.
void fold_drift(sim::SimulatorConfig& s, std::int64_t t_ns) {
  if (!s.drift) return;
  sim::SimulatorDrift& d = *s.drift;
  const double days =
      t_ns > d.since_ns ? static_cast<double>(t_ns - d.since_ns) / static_cast<double>(kDay) : 0.0;
  s.errors.machine_shift_mm += d.machine_shift_mm_per_day * days;
  s.errors.monument_shift_mm += d.monument_shift_mm_per_day * days;
  s.errors.tool_length_error_mm += d.tool_length_error_mm_per_day * days;
  s.errors.c_angle_error_rad += d.c_angle_error_rad_per_day * days;
  s.errors.a_home_error_rad += d.a_home_error_rad_per_day * days;
  s.fixture.column_x.offset_mm += d.fixture_column_x_offset_mm_per_day * days;
  s.fixture.pogo_y.offset_mm += d.fixture_pogo_y_offset_mm_per_day * days;
  s.fixture.pogo_z.offset_mm += d.fixture_pogo_z_offset_mm_per_day * days;
  s.volumetric.rigid_body.ec0xy_rad += d.squareness_ec0xy_rad_per_day * days;
  d.since_ns = t_ns;
}

struct Hold {
  CheckKind kind = CheckKind::MonumentPositioning;
  std::string request_id;
};

struct Machine {
  MachineConfig config;          // the simulator section as of now (repairs change it)
  sim::SimulatorConfig nominal;  // the simulator section as generated
  std::unique_ptr<acquisition::SimulatedInstruments> instruments;
  std::vector<Correction> fixture_corrections;  // applied to the fixture since its last repair
  std::optional<Hold> hold;
  bool weekly_due = false, monthly_due = false;
  int sequence = 0;
  int rotation = 0;  // the fixture's next pre-calibration configuration
  int interventions = 0;
};

class Generator {
 public:
  Generator(storage::Database& db, const GenerateOptions& options)
      : db_(db), options_(options), faults_(options.seed ^ 0xFA017ULL) {}

  GenerateReport run();

 private:
  void rebuild_instruments(Machine& m) {
    m.instruments = std::make_unique<acquisition::SimulatedInstruments>(m.config);
    for (const Correction& c : m.fixture_corrections) m.instruments->apply(c);
  }
  template <typename Sample>
  void store(const Sample& sample) {
    const auto t0 = Clock::now();
    db_.store(sample);
    report_.store_seconds += seconds_since(t0);
    report_.first_ns =
        report_.first_ns ? std::min(report_.first_ns, sample.time_ns) : sample.time_ns;
    report_.last_ns = std::max(report_.last_ns, sample.time_ns);
  }
  void status(Machine& m, const std::string& request_id, MachineState state,
              std::optional<CheckKind> kind, std::optional<Verdict> verdict,
              const std::string& detail, std::int64_t t) {
    store(MachineStatus{m.config.machine_id, request_id, state, kind, verdict, detail, t});
    ++report_.statuses;
  }
  void watched(const std::vector<TrendWarning>& changes) {
    for (const auto& w : changes) (w.active ? report_.warnings_raised : report_.warnings_ended)++;
  }
  // Requests, measures, judges and stores one check from `t` on; `t` moves past its result.
  CheckResult check(Machine& m, CheckKind kind, std::int64_t& t, const std::string& requested_by,
                    std::vector<NamedValue> parameters = {}, std::string verifies = {});
  // The day's checks of one machine, from `t`.
  void day(Machine& m, std::int64_t t, bool monday, bool first_monday);
  // Interprets a result as the scheduler does: true when the checks go on.
  bool judged(Machine& m, const CheckResult& r, std::int64_t t);
  void intervene(Machine& m, std::int64_t t);

  storage::Database& db_;
  const GenerateOptions& options_;
  std::mt19937_64 faults_;
  historian::TrendWatch watch_;
  GenerateReport report_;
  std::vector<NamedValue> last_parameters_;  // of the newest request
};

CheckResult Generator::check(Machine& m, CheckKind kind, std::int64_t& t,
                             const std::string& requested_by, std::vector<NamedValue> parameters,
                             std::string verifies) {
  const bool tracker = is_tracker_check(kind);
  const std::int64_t duration =
      tracker ? 40 * kMinute : (is_fixture_check(kind) ? 20 * kMinute : 4 * kMinute);
  if (kind == CheckKind::FixturePreCalibration && m.config.fixture) {
    // The scheduler's rotation (Scheduler::add_fixture_configuration).
    const int count = std::max(1, m.config.fixture->precalibration_configuration_count());
    const int k = ((m.rotation % count) + count) % count;
    parameters.push_back({"fixture_configuration", static_cast<double>(k), ""});
    m.rotation = (k + 1) % count;
  }
  CheckRequest request{m.config.machine_id,
                       m.config.machine_id + "-" + std::string(to_string(kind)) + "-" +
                           compact_time(t) + "-" + std::to_string(++m.sequence),
                       kind,
                       requested_by,
                       t,
                       1,
                       std::move(parameters),
                       std::move(verifies)};
  last_parameters_ = request.parameters;
  store(request);
  status(m, request.request_id, MachineState::Checking, kind, std::nullopt,
         std::string(to_string(kind)) + " requested by " + requested_by, t);
  const auto t0 = Clock::now();
  std::optional<MeasurementSet> set = m.instruments->measure(request, t + duration);
  if (!set) throw std::logic_error("the simulated instruments did not measure at once");
  CheckResult result = solver::solve(*set, m.config, set->time_ns + 2 * kSecond);
  if (tracker) report_.monthly_seconds += seconds_since(t0);
  result.produced_by = "ncqual-generate-history";
  store(*set);
  store(result);
  ++report_.checks;
  if (tracker) ++report_.monthly_checks;
  switch (result.verdict) {
    case Verdict::Pass: ++report_.passed; break;
    case Verdict::Fail: ++report_.failed; break;
    case Verdict::Invalid: ++report_.invalid; break;
  }
  if (options_.watch) {
    const auto w0 = Clock::now();
    watched(watch_.after_result(db_, result));
    report_.watch_seconds += seconds_since(w0);
  }
  t = result.time_ns + 30 * kSecond;
  return result;
}

bool Generator::judged(Machine& m, const CheckResult& r, std::int64_t t) {
  if (r.verdict == Verdict::Pass) {
    status(m, r.request_id, MachineState::Qualified, r.kind, r.verdict,
           "every period's checks current", t);
    return true;
  }
  std::string detail = std::string(to_string(r.kind)) + " " + std::string(to_string(r.verdict));
  if (!r.likely_causes.empty()) detail += "; first likely cause: " + r.likely_causes.front();
  if (!r.reason.empty()) detail += "; " + r.reason;
  detail += "; next: investigate, then ncqual intervene --machine " + m.config.machine_id +
            " --check " + std::string(to_string(r.kind)) + " --note \"...\"";
  m.hold = Hold{r.kind, r.request_id};
  status(m, r.request_id, MachineState::NeedsIntervention, r.kind, r.verdict, detail, t);
  return false;
}

void Generator::intervene(Machine& m, std::int64_t t) {
  const Hold h = *m.hold;
  m.hold.reset();
  Intervention iv;
  iv.machine_id = m.config.machine_id;
  iv.intervention_id = m.config.machine_id + "-intervention-" + compact_time(t) + "-" +
                       std::to_string(++m.interventions);
  iv.kind = h.kind;
  iv.operator_name = "generator";
  iv.time_ns = t;
  // The repair: the fault found is removed, the drift behind it restarts from now. A fixture
  // check's repair resets the fixture (and drops its zero offsets); any other the machine.
  sim::SimulatorConfig& s = m.config.simulator;
  fold_drift(s, t);
  if (is_fixture_check(h.kind)) {
    s.fixture = m.nominal.fixture;
    m.fixture_corrections.clear();
    iv.note = "fixture re-zeroed and its actuators re-homed after " + h.request_id;
  } else {
    s.errors = m.nominal.errors;
    s.volumetric = m.nominal.volumetric;
    iv.note = "machine re-referenced and probe re-qualified after " + h.request_id;
  }
  rebuild_instruments(m);
  store(iv);
  ++report_.interventions;
  status(m, "", MachineState::Checking, h.kind, std::nullopt,
         "intervention " + iv.intervention_id + " re-arms " + std::string(to_string(h.kind)),
         t + kSecond);
  if (options_.watch) {
    const auto w0 = Clock::now();
    watched(watch_.after_intervention(db_, iv));
    report_.watch_seconds += seconds_since(w0);
  }
}

void Generator::day(Machine& m, std::int64_t t, bool monday, bool first_monday) {
  if (m.hold) intervene(m, t - 30 * kMinute);
  if (monday) m.weekly_due = true;
  if (first_monday && options_.monthly && m.config.global_check) m.monthly_due = true;
  // A sudden fault, found by the day's checks.
  if (options_.fault_per_day > 0 && uniform(faults_, 0, 1) < options_.fault_per_day) {
    const double dx = uniform(faults_, -0.06, 0.06), dy = uniform(faults_, -0.06, 0.06);
    m.config.simulator.errors.machine_shift_mm += Eigen::Vector3d(dx, dy, 0);
    rebuild_instruments(m);
    ++report_.faults;
  }
  const std::string by = "scheduler";
  if (m.monthly_due) {
    const CheckResult r = check(m, CheckKind::GlobalGrid, t, by);
    if (!judged(m, r, t)) return;
    m.monthly_due = false;
  }
  for (CheckKind k : {CheckKind::MonumentCAlignment, CheckKind::MonumentToolLength,
                      CheckKind::MonumentPositioning, CheckKind::MonumentCRotation}) {
    const CheckResult r = check(m, k, t, by);
    if (!judged(m, r, t)) return;
  }
  if (!m.weekly_due || !m.config.fixture) return;
  const CheckResult pre = check(m, CheckKind::FixturePreCalibration, t, by);
  if (pre.verdict == Verdict::Fail && pre.correction) {
    // The solver's Compensation for the fixture's control unit, applied by the acquisition.
    const Compensation c{m.config.machine_id, pre.request_id, *pre.correction, pre.time_ns};
    store(c);
    ++report_.compensations;
    if (m.instruments->apply(c.correction).empty()) m.fixture_corrections.push_back(c.correction);
    if (options_.watch) {
      const auto w0 = Clock::now();
      watched(watch_.after_compensation(db_, c));
      report_.watch_seconds += seconds_since(w0);
    }
    status(m, pre.request_id, MachineState::Checking, pre.kind, pre.verdict,
           pre.request_id + " issued zero offsets for " + c.correction.target + "; verifying them",
           t);
    // The post-calibration runs the configuration of the pre-calibration it verifies.
    std::vector<NamedValue> parameters = last_parameters_;
    const CheckResult post =
        check(m, CheckKind::FixturePostCalibration, t, by, std::move(parameters), pre.request_id);
    if (!judged(m, post, t)) return;
  } else if (!judged(m, pre, t)) {
    return;
  }
  m.weekly_due = false;
}

GenerateReport Generator::run() {
  const auto t0 = Clock::now();
  std::vector<Machine> machines;
  for (int i = 0; i < options_.machines; ++i) {
    Machine& m = machines.emplace_back();
    m.config = generated_machine(options_, i);
    m.nominal = m.config.simulator;
    if (m.config.simulator.drift) ++report_.drifting;
    rebuild_instruments(m);
    report_.machine_ids.push_back(m.config.machine_id);
  }
  for (int d = 0; d < options_.days; ++d) {
    const std::int64_t midnight = options_.start_ns + d * kDay;
    const int wd = weekday(midnight);
    if (wd < 5) {
      const bool monday = wd == 0;
      const bool first_monday = monday && day_of_month(midnight) <= 7;
      for (Machine& m : machines) day(m, midnight + 5 * kHour, monday, first_monday);
    }
    if (options_.progress) options_.progress(d);
  }
  report_.seconds = seconds_since(t0);
  return report_;
}

}  // namespace

std::string generated_machine_id(int index) {
  char buffer[16];
  std::snprintf(buffer, sizeof buffer, "pm%03d", index + 1);
  return buffer;
}

MachineConfig generated_machine(const GenerateOptions& options, int index) {
  MachineConfig m = load_machine_config(options.machine_file);
  m.machine_id = generated_machine_id(index);
  const Drawn d = draw(options, index, m.fixture.has_value());
  m.simulator.seed = d.simulator_seed;
  m.simulator.drift = d.drift;
  return m;
}

PlantConfig generated_plant(const GenerateOptions& options,
                            const std::vector<std::string>& machine_ids) {
  PlantConfig plant;
  plant.plant = "generated";
  plant.simulated_clock = true;
  plant.simulated_start_ns = options.start_ns;
  const MachineConfig base = load_machine_config(options.machine_file);
  for (const std::string& id : machine_ids) {
    MachineConfig m = base;
    m.machine_id = id;
    plant.machines.push_back(std::move(m));
  }
  return plant;
}

GenerateReport generate_history(storage::Database& db, const GenerateOptions& options) {
  if (options.machines < 1) throw std::invalid_argument("machines must be at least 1");
  if (options.days < 1) throw std::invalid_argument("days must be at least 1");
  if (options.machine_file.empty()) throw std::invalid_argument("no machine file given");
  Generator generator(db, options);
  return generator.run();
}

std::string option_value(int argc, char** argv, int& i) {
  if (i + 1 >= argc) throw std::invalid_argument(std::string(argv[i]) + " needs a value");
  return argv[++i];
}

bool read_generate_option(int argc, char** argv, int& i, GenerateOptions& options) {
  const std::string arg = argv[i];
  if (arg == "--machines") {
    options.machines = std::stoi(option_value(argc, argv, i));
  } else if (arg == "--days") {
    options.days = std::stoi(option_value(argc, argv, i));
  } else if (arg == "--seed") {
    options.seed = std::stoull(option_value(argc, argv, i));
  } else if (arg == "--watch") {
    options.watch = true;
  } else if (arg == "--monthly") {
    options.monthly = true;
  } else {
    return false;
  }
  return true;
}

}  // namespace ncqual::history
