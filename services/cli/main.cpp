// ncqual: the operator's command-line tool.
//
//   ncqual history [--plant F | --db F] [--machine M] [--kind K] [--limit N] [--since-ns T]
//                  [--json]
//   ncqual check   --machine M --kind K [--plant F] [--domain N] [--wait SECONDS] [--json]
//   ncqual wait    [--plant F | --db F] (--request ID | --count N [--machine M] |
//                  --settled --machine M [--since-ns T]) [--timeout S]
//   ncqual count   [--plant F | --db F] [--machine M]
//   ncqual budget  --machine M [--plant F] [--db F] [--last N] [--json]   (budget_command.hpp)
//   ncqual analyze iso230-2 FILE [--json]                                 (analyze_command.hpp)
//   ncqual analyze circle FILE [--plane XY|YZ|XZ] [--nominal-radius-mm R] [--centre-mm U,V]
//                  [--json]
//   ncqual analyze grid --x-run F --y-run F --grid F [--json]
//   ncqual import  iso230-2|circle FILE | grid --x-run F --y-run F --grid F  --machine M
//                                                                          (import_command.hpp)
//   ncqual status  [--plant F] [--db F] [--machine M] [--json]             (status_command.hpp)
//   ncqual intervene --machine M --check KIND --note TEXT [--operator NAME]  (status_command.hpp)
//   ncqual trend   --machine M [--kind K] [--every day|week|month] [--metrics N]
//   ncqual uncertainty --machine M [--plant F] [--trials N] [--seed S] [--threads T] [--search]
//                  [--json]
//                                                                          (uncertainty_command.hpp)
//
// Exit codes: 0 success (for `check --wait`: PASS), 1 error, 2 usage, 3 FAIL, 4 INVALID,
// 5 timed out.
#include "analyze_command.hpp"
#include "budget_command.hpp"
#include "import_command.hpp"
#include "plant_args.hpp"
#include "status_command.hpp"
#include "uncertainty_command.hpp"
#include "ncqual/args.hpp"
#include "ncqual/clock.hpp"
#include "ncqual/config.hpp"
#include "ncqual/dds/dispatcher.hpp"
#include "ncqual/dds/topics.hpp"
#include "ncqual/storage.hpp"
#include "ncqual/storage_json.hpp"

#include <spdlog/spdlog.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <thread>

namespace {
using namespace ncqual;

constexpr int kExitError = 1, kExitUsage = 2, kExitFail = 3, kExitInvalid = 4, kExitTimeout = 5;

const char* kUsage =
    "usage: ncqual <command> [options]\n"
    "  history [--plant F | --db F] [--machine M] [--kind K] [--limit N] [--since-ns T] [--json]\n"
    "      stored checks, newest first\n"
    "  check --machine M --kind K [--plant F] [--domain N] [--wait SECONDS] [--json]\n"
    "      ask the scheduler to run a check now; with --wait, print its result\n"
    "  wait [--plant F | --db F] (--request ID | --count N [--machine M] |\n"
    "       --settled --machine M [--since-ns T]) [--timeout S]\n"
    "      wait until the historian has stored that whole check (or N results)\n"
    "  count [--plant F | --db F] [--machine M]\n"
    "      number of stored results\n"
    "  budget --machine M [--plant F] [--db F] [--last N] [--json]\n"
    "      the error budget: capability, allowance and today's share of every error source,\n"
    "      derived tolerances of the check metrics, RSS and Monte Carlo totals\n"
    "  analyze iso230-2 FILE [--json]\n"
    "  analyze circle FILE [--plane XY|YZ|XZ] [--nominal-radius-mm R] [--centre-mm U,V] [--json]\n"
    "  analyze grid --x-run F --y-run F --grid F [--json]\n"
    "      evaluate an instrument export (ISO 230-2 positioning run, ISO 230-4 circular test,\n"
    "      tracker grid) on its own, without services; `ncqual analyze --help` for the formats\n"
    "  import iso230-2|circle FILE --machine M | import grid --x-run F --y-run F --grid F\n"
    "         --machine M\n"
    "      publish an instrument export as a MeasurementSet of the machine: the solver judges\n"
    "      it, the historian stores it; prints its request id\n"
    "  status [--plant F] [--db F] [--machine M] [--json]\n"
    "      every machine's state, and per period its last pass and when it falls due next\n"
    "  intervene --machine M --check KIND --note TEXT [--operator NAME]\n"
    "      record a physical intervention: re-arms the machine's held check\n"
    "  trend --machine M [--kind K] [--every day|week|month] [--metrics N]\n"
    "      per period: checks passed/failed and the values nearest their tolerances\n"
    "  uncertainty --machine M [--plant F] [--trials N] [--seed S] [--threads T] [--search]\n"
    "              [--json]\n"
    "      Monte Carlo uncertainty of the machine's monthly tracker verification (GUM S1)\n"
    "      and, with --search, the tracker location that minimises it\n"
    "The plant config comes from --plant or NCQUAL_PLANT; the domain from --domain,\n"
    "NCQUAL_DOMAIN or the plant config.\n"
    "Exit codes: 0 ok/PASS, 1 error, 2 usage, 3 FAIL, 4 INVALID, 5 timed out.\n";

// --db, else the plant config's historian, else the demo's var/historian.db ($NCQUAL_VAR).
std::string database_path(const Args& args) {
  if (auto db = args.get("db")) return *db;
  const std::string plant = plant_config_path(args.get_or("plant", ""));
  if (!plant.empty()) return load_plant_config(plant).historian_database;
  const char* var = std::getenv("NCQUAL_VAR");
  const std::string fallback = std::string(var && *var ? var : "var") + "/historian.db";
  if (std::filesystem::exists(fallback)) return fallback;
  throw ArgError("pass --db FILE or --plant FILE (or set NCQUAL_PLANT); no " + fallback + " here");
}

std::string format_value(double v) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(4) << v;
  return s.str();
}

// At most kShownMetrics per row: all of them when few, else the worst-case summaries ("max")
// and the ones out of tolerance first (--json has every metric).
constexpr std::size_t kShownMetrics = 6;
std::string format_metrics(const std::vector<Metric>& metrics) {
  std::vector<const Metric*> shown;
  if (metrics.size() <= kShownMetrics) {
    for (const auto& m : metrics) shown.push_back(&m);
  } else {
    for (const auto& m : metrics) {
      if (m.name.find("max") != std::string::npos) shown.push_back(&m);
    }
    for (const auto& m : metrics) {
      if (!m.pass && m.name.find("max") == std::string::npos) shown.push_back(&m);
    }
    if (shown.size() > kShownMetrics) shown.resize(kShownMetrics);
  }
  std::string out;
  for (const Metric* m : shown) {
    if (!out.empty()) out += "  ";
    out += m->name + "=" + format_value(m->value) + (m->pass ? "" : "(!)");
  }
  if (shown.size() < metrics.size()) {
    out += "  (+" + std::to_string(metrics.size() - shown.size()) + " more; --json for all)";
  }
  return out;
}

void print_table(const std::vector<storage::CheckRecord>& records) {
  std::printf("%-24s %-10s %-22s %-8s %s\n", "time (UTC)", "machine", "check", "verdict",
              "metrics ((!) = out of tolerance)");
  for (const auto& r : records) {
    char buf[32];
    const std::int64_t t = r.result ? r.result->time_ns : (r.request ? r.request->time_ns : 0);
    const std::string verdict = r.result ? std::string(to_string(r.result->verdict)) : "pending";
    const std::string kind =
        r.result ? std::string(to_string(r.result->kind))
                 : (r.request ? std::string(to_string(r.request->kind)) : std::string("?"));
    std::printf("%-24s %-10s %-22s %-8s %s\n", std::string(format_iso8601(t, buf)).c_str(),
                r.machine_id.c_str(), kind.c_str(), verdict.c_str(),
                r.result ? format_metrics(r.result->metrics).c_str() : "");
    if (r.result && r.result->verdict != Verdict::Pass) {
      if (!r.result->reason.empty()) {
        // The table shows the start of a long reason; `history --json` has all of it.
        constexpr std::size_t kShownReason = 300;
        std::string reason = r.result->reason;
        if (reason.size() > kShownReason) reason = reason.substr(0, kShownReason) + " ...";
        std::printf("%59s reason: %s\n", "", reason.c_str());
      }
      if (!r.result->likely_causes.empty()) {
        std::printf("%59s first likely cause: %s\n", "", r.result->likely_causes.front().c_str());
      }
    }
  }
}

int cmd_history(const Args& args) {
  auto db = storage::Database::open_readonly(database_path(args));
  storage::HistoryQuery q;
  if (auto m = args.get("machine")) q.machine_id = *m;
  if (auto k = args.get("kind")) {
    q.kind = parse_check_kind(*k);
    if (!q.kind) throw ArgError("--kind '" + *k + "' is not a check kind");
  }
  q.limit = args.get_int("limit", 100);
  q.since_ns = args.get_int64("since-ns", q.since_ns);
  const auto records = db.history(q);
  if (args.has("json")) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& r : records) out.push_back(storage::to_json(r));
    std::cout << out.dump(2) << "\n";
  } else {
    print_table(records);
  }
  return 0;
}

int exit_code_of(Verdict v) {
  switch (v) {
    case Verdict::Pass: return 0;
    case Verdict::Fail: return kExitFail;
    default: return kExitInvalid;
  }
}

int cmd_check(const Args& args) {
  const PlantConfig plant = plant_from_args(args);
  const std::string machine = configured_machine(plant, args.require("machine")).machine_id;
  const std::string kind_name = args.require("kind");
  const auto kind = parse_check_kind(kind_name);
  if (!kind) throw ArgError("--kind '" + kind_name + "' is not a check kind");
  const double wait_s = args.get_double("wait", 0);

  const WallClock clock;
  char host[128] = {};
  gethostname(host, sizeof host - 1);
  const CheckCommand cmd{machine,
                         "op-" + machine + "-" + std::to_string(clock.now_ns()) + "-" +
                             std::to_string(getpid()),
                         *kind, std::string("operator:") + (getenv("USER") ? getenv("USER") : host),
                         clock.now_ns(), {}};

  const int domain = ncqual::dds::resolve_domain_id(args.get_int("domain", -1), plant.domain_id);
  ncqual::dds::Participant participant({domain, plant.qos_profiles_file, "ncqual-cli"});
  ncqual::dds::Writer<ncqual::dds::CheckCommandTopic> commands(participant);
  std::optional<ncqual::dds::Reader<ncqual::dds::CheckResultTopic>> results;
  if (wait_s > 0) results.emplace(participant, machine);

  if (!commands.wait_for_readers(1, std::chrono::seconds(10))) {
    std::cerr << "ncqual check: no scheduler is listening on domain " << domain << "\n";
    return kExitError;
  }
  if (!commands.write(cmd) || !commands.wait_for_acknowledgments(std::chrono::seconds(10))) {
    std::cerr << "ncqual check: the scheduler did not acknowledge the order\n";
    return kExitError;
  }
  std::cerr << "requested " << kind_name << " on " << machine << " (" << cmd.request_id << ")\n";
  if (!results) {
    std::cout << cmd.request_id << "\n";
    return 0;
  }
  std::optional<CheckResult> got;
  ncqual::dds::Dispatcher dispatcher;
  dispatcher.on(*results, [&](ncqual::dds::Received<CheckResult> in) {
    if (in.value.request_id == cmd.request_id) got = in.value;
  });
  dispatcher.run_until([&] { return got.has_value(); },
                       std::chrono::milliseconds(static_cast<long long>(wait_s * 1000)));
  if (!got) {
    std::cerr << "ncqual check: no result for " << cmd.request_id << " within " << wait_s << " s\n";
    return kExitTimeout;
  }
  storage::CheckRecord rec;
  rec.machine_id = got->machine_id;
  rec.request_id = got->request_id;
  rec.kind = got->kind;
  rec.result = *got;
  if (args.has("json")) {
    std::cout << storage::to_json(rec).dump(2) << "\n";
  } else {
    print_table({rec});
  }
  return exit_code_of(got->verdict);
}

// Waits on the database itself: the historian's commit is the event we wait for. The database
// is re-read every 100 ms until the condition holds or the deadline passes.
int cmd_wait(const Args& args) {
  const std::string path = database_path(args);
  const double timeout_s = args.get_double("timeout", 60);
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::milliseconds(static_cast<long long>(timeout_s * 1000));
  const auto request = args.get("request");
  const int count = args.get_int("count", -1);
  const bool settled = args.has("settled");
  if (!request && count < 0 && !settled) {
    throw ArgError("pass --request ID, --count N or --settled --machine M");
  }
  std::optional<std::string> machine = args.get("machine");
  if (settled && !machine) throw ArgError("--settled needs --machine M");
  const std::int64_t since_ns = args.get_int64("since-ns", 0);
  // The whole check: request, measurement set and result (topics arrive independently).
  auto complete = [](const std::optional<storage::CheckRecord>& rec) {
    return rec && rec->request && rec->measurement && rec->result;
  };
  while (true) {
    if (std::filesystem::exists(path)) {
      try {
        auto db = storage::Database::open_readonly(path);
        if (request) {
          auto rec = db.find_check(*request);
          if (complete(rec)) {
            std::cout << to_string(rec->result->verdict) << "\n";
            return 0;
          }
        } else if (settled) {
          // The machine's cycle is over when its newest status says QUALIFIED, OVERDUE or
          // NEEDS_INTERVENTION and the check that decided it is stored whole.
          const auto status = db.latest_status(*machine);
          if (status && status->time_ns >= since_ns &&
              (status->state == MachineState::Qualified ||
               status->state == MachineState::Overdue ||
               status->state == MachineState::NeedsIntervention) &&
              (status->request_id.empty() || complete(db.find_check(status->request_id)))) {
            std::cout << to_string(status->state) << "\n";
            return 0;
          }
        } else if (db.count_results(machine) >= count) {
          return 0;
        }
      } catch (const storage::StorageError&) {
        // The historian is creating the schema right now: look again.
      }
    }
    if (std::chrono::steady_clock::now() >= deadline) {
      std::cerr << "ncqual wait: timed out after " << timeout_s << " s\n";
      return kExitTimeout;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

int cmd_count(const Args& args) {
  const std::string path = database_path(args);
  if (!std::filesystem::exists(path)) {
    std::cout << 0 << "\n";
    return 0;
  }
  auto db = storage::Database::open_readonly(path);
  std::cout << db.count_results(args.get("machine")) << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "help") {
    std::cout << kUsage;
    return argc < 2 ? kExitUsage : 0;
  }
  const std::string command = argv[1];
  const std::vector<std::string> rest(argv + 2, argv + argc);
  spdlog::set_level(spdlog::level::warn);
  try {
    if (command == "history") {
      return cmd_history(
          Args(rest, {"plant", "db", "machine", "kind", "limit", "since-ns"}, {"json"}));
    }
    if (command == "check") {
      return cmd_check(Args(rest, {"plant", "machine", "kind", "domain", "wait"}, {"json"}));
    }
    if (command == "count") {
      return cmd_count(Args(rest, {"plant", "db", "machine"}, {}));
    }
    if (command == "analyze") {
      return run_analyze(rest);
    }
    if (command == "import") {
      return run_import(rest);
    }
    if (command == "status") {
      return run_status(rest);
    }
    if (command == "intervene") {
      return run_intervene(rest);
    }
    if (command == "trend") {
      return run_trend(rest);
    }
    if (command == "uncertainty") {
      return run_uncertainty(rest);
    }
    if (command == "budget") {
      return run_budget_command(Args(rest, kBudgetFlagsWithValue, kBudgetSwitches));
    }
    if (command == "wait") {
      return cmd_wait(Args(rest, {"plant", "db", "request", "count", "machine", "timeout",
                                  "since-ns"},
                           {"settled"}));
    }
    std::cerr << "ncqual: unknown command '" << command << "'\n" << kUsage;
    return kExitUsage;
  } catch (const ArgError& e) {
    std::cerr << "ncqual " << command << ": " << e.what() << "\n";
    return kExitUsage;
  } catch (const std::exception& e) {
    std::cerr << "ncqual " << command << ": " << e.what() << "\n";
    return kExitError;
  }
}
