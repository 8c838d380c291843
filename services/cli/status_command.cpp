#include "status_command.hpp"

#include "plant_args.hpp"

#include "ncqual/args.hpp"
#include "ncqual/calendar.hpp"
#include "ncqual/clock.hpp"
#include "ncqual/config.hpp"
#include "ncqual/dds/endpoint.hpp"
#include "ncqual/dds/participant.hpp"
#include "ncqual/dds/topics.hpp"
#include "ncqual/storage.hpp"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <algorithm>
#include <cmath>

namespace ncqual {

namespace {

constexpr int kExitError = 1;

nlohmann::json time_or_null(std::optional<std::int64_t> t) {
  return t ? nlohmann::json(*t) : nlohmann::json(nullptr);
}

}  // namespace

int run_status(const std::vector<std::string>& words) {
  const Args args(words, {"plant", "db", "machine"}, {"json"});
  const PlantConfig plant = plant_from_args(args);
  const std::string db_path = args.get_or("db", plant.historian_database);
  if (!std::filesystem::exists(db_path)) {
    std::cerr << "ncqual status: no historian database at " << db_path << "\n";
    return kExitError;
  }
  auto db = storage::Database::open_readonly(db_path);
  const Calendar calendar(plant.calendar.value_or(default_calendar_config()));
  const auto machine_filter = args.get("machine");
  if (machine_filter) (void)configured_machine(plant, *machine_filter);
  nlohmann::json out{{"plant", plant.plant}, {"machines", nlohmann::json::array()}};
  std::int64_t plant_now = WallClock().now_ns();
  for (const auto& m : plant.machines) {
    if (machine_filter && m.machine_id != *machine_filter) continue;
    const auto status = db.latest_status(m.machine_id);
    // On a simulated clock "now" is the scheduler's newest word on the machine (heartbeats carry
    // wall time, so the machine's last-seen time would not do).
    const std::int64_t now =
        plant.simulated_clock ? (status ? status->time_ns : plant.simulated_start_ns) : plant_now;
    nlohmann::json jm{{"machine_id", m.machine_id}};
    jm["state"] = status ? std::string(to_string(status->state)) : std::string(to_string(MachineState::Unknown));
    jm["detail"] = status ? status->detail : "no status stored yet";
    jm["status_time_ns"] = status ? nlohmann::json(status->time_ns) : nlohmann::json(nullptr);
    jm["periods"] = nlohmann::json::array();
    for (const auto& period : calendar.config().periods) {
      nlohmann::json jp{{"name", period.name}, {"every", std::string(to_string(period.unit))},
                        {"checks", nlohmann::json::array()}};
      std::optional<std::int64_t> oldest;
      bool all = true, any = false;
      for (CheckKind k : period.checks) {
        if (!has_sections_for(m, k)) continue;
        any = true;
        std::optional<std::int64_t> last = db.last_pass_ns(m.machine_id, k);
        if (k == CheckKind::FixturePreCalibration) {
          // A fixture loop that ended in a passed post-calibration completes the week too.
          const auto post = db.last_pass_ns(m.machine_id, CheckKind::FixturePostCalibration);
          if (post && (!last || *post > *last)) last = post;
        }
        jp["checks"].push_back({{"kind", std::string(to_string(k))}, {"last_pass_ns", time_or_null(last)}});
        if (!last) {
          all = false;
        } else if (!oldest || *last < *oldest) {
          oldest = last;
        }
      }
      if (!any) continue;
      const std::optional<std::int64_t> period_last = all ? oldest : std::nullopt;
      jp["last_pass_ns"] = time_or_null(period_last);
      jp["due"] = calendar.due(period, period_last, now);
      jp["overdue"] = calendar.overdue(period, period_last, now);
      jp["next_due_ns"] = calendar.next_due(period, period_last, now);
      jm["periods"].push_back(jp);
    }
    out["machines"].push_back(jm);
    out["now_ns"] = now;
  }
  if (args.has("json")) {
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  const auto when = [&](const nlohmann::json& t) {
    return t.is_null() ? std::string("never") : calendar.local_text(t.get<std::int64_t>());
  };
  std::cout << "plant " << plant.plant << " (" << calendar.config().time_zone
            << (plant.simulated_clock ? ", simulated clock" : "") << ")\n";
  for (const auto& jm : out["machines"]) {
    std::cout << "\n" << jm["machine_id"].get<std::string>() << "  " << jm["state"].get<std::string>()
              << "  (" << when(jm["status_time_ns"]) << ")\n  " << jm["detail"].get<std::string>() << "\n";
    std::cout << "  " << std::left << std::setw(10) << "period" << std::setw(8) << "every"
              << std::setw(24) << "last passed" << std::setw(24) << "next due" << "\n";
    for (const auto& jp : jm["periods"]) {
      const std::string flag = jp["overdue"].get<bool>() ? "OVERDUE" : jp["due"].get<bool>() ? "due" : "";
      std::cout << "  " << std::setw(10) << jp["name"].get<std::string>() << std::setw(8)
                << jp["every"].get<std::string>() << std::setw(24) << when(jp["last_pass_ns"])
                << std::setw(24) << (jp["due"].get<bool>() ? std::string("now") : when(jp["next_due_ns"]))
                << flag << "\n";
    }
  }
  return 0;
}

int run_intervene(const std::vector<std::string>& words) {
  const Args args(words, {"plant", "machine", "check", "note", "operator", "domain"}, {});
  const PlantConfig plant = plant_from_args(args);
  const std::string machine = configured_machine(plant, args.require("machine")).machine_id;
  const std::string kind_name = args.require("check");
  const auto kind = parse_check_kind(kind_name);
  if (!kind) throw ArgError("--check '" + kind_name + "' is not a check kind");
  const std::string note = args.require("note");
  if (note.find_first_not_of(" \t") == std::string::npos) {
    throw ArgError("--note is empty: say what was done (e.g. \"stylus replaced\")");
  }
  char host[128] = {};
  gethostname(host, sizeof host - 1);
  const std::string who = args.get_or("operator", getenv("USER") ? getenv("USER") : host);
  const WallClock clock;
  const Intervention iv{machine,
                        "iv-" + machine + "-" + std::to_string(clock.now_ns()) + "-" + std::to_string(getpid()),
                        *kind, note, who, clock.now_ns()};
  const int domain = ncqual::dds::resolve_domain_id(args.get_int("domain", -1), plant.domain_id);
  ncqual::dds::Participant participant({domain, plant.qos_profiles_file, "ncqual-cli"});
  ncqual::dds::Writer<ncqual::dds::InterventionTopic> writer(participant);
  // The scheduler (to re-arm) and the historian (to record): both must hear it.
  if (!writer.wait_for_readers(2, std::chrono::seconds(10))) {
    std::cerr << "ncqual intervene: the scheduler and the historian must both be running on domain "
              << domain << " (fewer than 2 readers of ncqual/Intervention)\n";
    return kExitError;
  }
  if (!writer.write(iv) || !writer.wait_for_acknowledgments(std::chrono::seconds(10))) {
    std::cerr << "ncqual intervene: the intervention was not acknowledged\n";
    return kExitError;
  }
  std::cerr << "recorded intervention on " << machine << " for " << kind_name << " by " << who << "\n";
  std::cout << iv.intervention_id << "\n";
  return 0;
}

namespace {

// How much of its tolerance band a value uses: |v - centre| / half-width (> 1: out of tolerance).
double band_use(const Metric& m) {
  const double half = 0.5 * (m.upper - m.lower);
  if (!(half > 0)) return 0;
  return std::abs(m.value - 0.5 * (m.upper + m.lower)) / half;
}

struct Bucket {
  int pass = 0, fail = 0, invalid = 0;
  std::map<std::string, Metric> worst;  // per metric: the value using most of its band
};

}  // namespace

int run_trend(const std::vector<std::string>& words) {
  const Args args(words, {"plant", "db", "machine", "kind", "every", "metrics"}, {});
  const PlantConfig plant = plant_from_args(args);
  const std::string machine = configured_machine(plant, args.require("machine")).machine_id;
  std::optional<CheckKind> only;
  if (auto k = args.get("kind")) {
    only = parse_check_kind(*k);
    if (!only) throw ArgError("--kind '" + *k + "' is not a check kind");
  }
  const std::string every = args.get_or("every", "week");
  PeriodConfig bucket_period;
  if (every == "day") {
    bucket_period.unit = PeriodUnit::Day;
  } else if (every == "week") {
    bucket_period.unit = PeriodUnit::Week;
  } else if (every == "month") {
    bucket_period.unit = PeriodUnit::Month;
  } else {
    throw ArgError("--every '" + every + "': expected day, week or month");
  }
  const int shown = args.get_int("metrics", 3);
  if (shown < 0 || shown > 20) throw ArgError("--metrics: expected 0 to 20");
  const std::string db_path = args.get_or("db", plant.historian_database);
  if (!std::filesystem::exists(db_path)) {
    std::cerr << "ncqual trend: no historian database at " << db_path << "\n";
    return kExitError;
  }
  auto db = storage::Database::open_readonly(db_path);
  const Calendar calendar(plant.calendar.value_or(default_calendar_config()));
  storage::HistoryQuery q;
  q.machine_id = machine;
  q.kind = only;
  q.limit = 0;
  // kind -> bucket start -> counts and worst values; per kind the metrics nearest their limits.
  std::map<CheckKind, std::map<std::int64_t, Bucket>> table;
  std::map<CheckKind, std::map<std::string, double>> peak_use;
  for (const auto& rec : db.history(q)) {
    if (!rec.result) continue;
    const CheckResult& r = *rec.result;
    Bucket& b = table[r.kind][calendar.period_start(bucket_period, r.time_ns)];
    (r.verdict == Verdict::Pass ? b.pass : r.verdict == Verdict::Fail ? b.fail : b.invalid)++;
    for (const auto& m : r.metrics) {
      auto it = b.worst.find(m.name);
      if (it == b.worst.end() || band_use(m) > band_use(it->second)) b.worst[m.name] = m;
      double& peak = peak_use[r.kind][m.name];
      peak = std::max(peak, band_use(m));
    }
  }
  if (table.empty()) {
    std::cout << "no stored results for " << machine << (only ? " of " + std::string(to_string(*only)) : "") << "\n";
    return 0;
  }
  for (const auto& [kind, buckets] : table) {
    // The metrics that came nearest their tolerance over the whole history.
    std::vector<std::pair<double, std::string>> ranked;
    for (const auto& [name, use] : peak_use[kind]) ranked.emplace_back(-use, name);
    std::sort(ranked.begin(), ranked.end());
    if (static_cast<int>(ranked.size()) > shown) ranked.resize(static_cast<std::size_t>(shown));
    std::cout << "\n" << to_string(kind) << "  (per " << every << ": runs, and the value nearest its "
              << "tolerance; (!) out of tolerance)\n";
    std::cout << "  " << std::left << std::setw(18) << (every + " from") << std::setw(14) << "pass/fail/inv";
    for (const auto& [use, name] : ranked) std::cout << std::setw(26) << name;
    std::cout << "\n";
    for (const auto& [start, b] : buckets) {
      const std::string when = calendar.local_text(start).substr(0, 10);
      std::cout << "  " << std::setw(18) << when << std::setw(14)
                << (std::to_string(b.pass) + "/" + std::to_string(b.fail) + "/" + std::to_string(b.invalid));
      for (const auto& [use, name] : ranked) {
        auto it = b.worst.find(name);
        std::ostringstream cell;
        if (it != b.worst.end()) {
          cell << std::setprecision(4) << it->second.value << " " << it->second.unit
               << (band_use(it->second) > 1 ? " (!)" : "");
        }
        std::cout << std::setw(26) << cell.str();
      }
      std::cout << "\n";
    }
  }
  return 0;
}

}  // namespace ncqual
