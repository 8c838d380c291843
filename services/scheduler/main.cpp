// ncqual-scheduler: runs the qualification process (scheduler.hpp) for every machine of the
// plant. Reads CheckResults, CheckCommands and Interventions; writes CheckRequests and
// MachineStatus. Its durable state is the plant's scheduler.state_database.
//
// Wall clock: decisions are taken as results arrive and once a second (shift starts, timeouts).
// Simulated clock (plant clock.mode: simulated): the clock starts at clock.start (or where the
// state file left it) and, whenever no check is waiting for a result, jumps to the next thing
// due; --days N (or --until T) ends the run once nothing is due before that time. A check that
// gets no answer for --stall-s of wall time lets the clock run on to its timeout (so a dead
// acquisition is retried and reported as it would be in a plant).
#include "scheduler.hpp"

#include "ncqual/command_line.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/log.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <set>

namespace {

using namespace ncqual;

std::vector<CheckKind> parse_cycle(const std::string& text) {
  std::vector<CheckKind> cycle;
  std::size_t start = 0;
  while (start < text.size()) {
    const auto comma = text.find(',', start);
    const std::string name =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const auto kind = parse_check_kind(name);
    if (!kind) throw std::invalid_argument("--cycle: '" + name + "' is not a check kind");
    cycle.push_back(*kind);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return cycle;
}

constexpr std::int64_t kNsPerDay = 86'400'000'000'000LL;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Runs the qualification process of every machine of the plant (or of --machine).",
               "ncqual-scheduler");
  command_line::configure(app);
  command_line::ServiceOptions options;
  command_line::add_service_options(app, options);
  std::optional<std::string> machine_list, cycle_text, state_flag, until_text;
  std::optional<double> days;
  double stall_s = 30;
  app.add_option("--machine", machine_list,
                 "serve only these machines (one scheduler per machine or group; default: all)")
      ->type_name("ID[,ID...]");
  app.add_option("--cycle", cycle_text,
                 "checks to run once at start, in order (default without a calendar: the "
                 "plant's scheduler.startup_checks; '' for none)")
      ->type_name("KIND,KIND,...");
  app.add_option("--state", state_flag,
                 "the durable state file (default: the plant's scheduler.state_database; with "
                 "--machine, scheduler-<ids>.db beside it)")
      ->type_name("FILE");
  app.add_option("--days", days, "simulated clock only: stop once nothing is due before that time")
      ->type_name("N");
  app.add_option("--until", until_text, "simulated clock only: as --days, to an ISO 8601 UTC time")
      ->type_name("ISO-TIME");
  app.add_option("--stall-s", stall_s,
                 "simulated clock: wall seconds without an answer before the clock runs on to "
                 "the check's timeout")
      ->type_name("S")
      ->capture_default_str();
  if (const auto code = command_line::parse(app, argc, argv)) return *code;
  try {
    init_logging("scheduler", options.log_level);
    PlantConfig loaded = load_plant_config(ncqual::dds::plant_file_from(options.plant));
    // --machine: this scheduler serves only those machines (one scheduler per machine, or per
    // group); the others' commands and interventions are another scheduler's, not errors. Its
    // default state file is its own, so two schedulers never share one.
    std::set<std::string> others;
    if (const auto& list = machine_list) {
      std::vector<MachineConfig> served = loaded.machines_named(*list, "--machine");
      for (const auto& m : loaded.machines) others.insert(m.machine_id);
      for (const auto& m : served) others.erase(m.machine_id);
      loaded.machines = std::move(served);
      std::string ids = *list;
      std::replace(ids.begin(), ids.end(), ',', '+');
      loaded.scheduler_state_database =
          (std::filesystem::path(loaded.scheduler_state_database).parent_path() /
           ("scheduler-" + ids + ".db")).string();
    }
    const PlantConfig plant = std::move(loaded);
    std::vector<CheckKind> cycle = plant.calendar ? std::vector<CheckKind>{} : plant.startup_checks;
    if (cycle_text) cycle = parse_cycle(*cycle_text);

    storage::StateFile state = storage::StateFile::open(state_flag.value_or(plant.scheduler_state_database));
    SimulatedClock simulated(plant.simulated_start_ns);
    WallClock wall;
    std::optional<std::int64_t> until;
    if (plant.simulated_clock) {
      if (const auto saved = scheduler::saved_clock_ns(state)) simulated.set_ns(*saved);
      if (until_text) {
        until = parse_iso8601(*until_text);
        if (!until) throw std::invalid_argument("--until: '" + *until_text + "' is not an ISO 8601 UTC time");
      } else if (days) {
        if (!(*days > 0)) throw std::invalid_argument("--days: must be > 0");
        until = plant.simulated_start_ns + static_cast<std::int64_t>(*days * kNsPerDay);
      }
    } else if (days || until_text) {
      throw std::invalid_argument("--days/--until need the plant's clock.mode: simulated");
    }
    const Clock& clock = plant.simulated_clock ? static_cast<const Clock&>(simulated) : wall;
    if (!(stall_s > 0)) throw std::invalid_argument("--stall-s: must be > 0");

    ncqual::dds::Service service({"scheduler", "",
                                  ncqual::dds::resolve_domain_id(options.domain, plant.domain_id),
                                  plant.qos_profiles_file});
    auto& p = service.participant();
    ncqual::dds::Writer<ncqual::dds::CheckRequestTopic> requests(p);
    ncqual::dds::Writer<ncqual::dds::MachineStatusTopic> statuses(p);
    ncqual::dds::Reader<ncqual::dds::CheckResultTopic> results(p);
    ncqual::dds::Reader<ncqual::dds::CheckCommandTopic> commands(p);
    ncqual::dds::Reader<ncqual::dds::InterventionTopic> interventions(p);

    scheduler::Scheduler sched(plant, clock,
                               {[&](const CheckRequest& r) {
                                  if (!requests.write(r)) spdlog::error("{}: request not queued", r.request_id);
                                },
                                [&](const MachineStatus& s) { statuses.write(s); }},
                               &state);
    bool progress = false;
    service.dispatcher().on(results, [&](ncqual::dds::Received<CheckResult> in) {
      progress = true;
      if (!in.error.empty()) {
        spdlog::error("result {} of '{}' ignored: {}", in.value.request_id, in.value.machine_id, in.error);
        return;
      }
      sched.result(in.value);
    });
    service.dispatcher().on(commands, [&](ncqual::dds::Received<CheckCommand> in) {
      if (others.count(in.value.machine_id)) return;  // another scheduler's machine
      progress = true;
      const std::string refused = in.error.empty() ? sched.command(in.value) : in.error;
      if (!refused.empty()) spdlog::error("check command {} refused: {}", in.value.request_id, refused);
    });
    service.dispatcher().on(interventions, [&](ncqual::dds::Received<Intervention> in) {
      if (others.count(in.value.machine_id)) return;  // another scheduler's machine
      progress = true;
      const std::string refused = in.error.empty() ? sched.intervention(in.value) : in.error;
      if (!refused.empty()) spdlog::warn("intervention {}: {}", in.value.intervention_id, refused);
    });
    // A restarted scheduler sends nothing until its writers have matched the readers the last
    // run had (historian, acquisitions), or 10 s passed. Otherwise a request could reach the
    // acquisition, which discovered the new writer first, and be lost to the historian if this
    // process were killed again before the historian matched it.
    scheduler::ReaderCounts known = scheduler::saved_reader_counts(state);
    if (known.requests > 0 || known.statuses > 0) {
      const bool matched = requests.wait_for_readers(known.requests, std::chrono::seconds(10)) &&
                           statuses.wait_for_readers(known.statuses, std::chrono::seconds(10));
      const scheduler::ReaderCounts now{requests.matched_readers(), statuses.matched_readers()};
      if (!matched) {
        spdlog::warn("after 10 s {} of {} request readers and {} of {} status readers are matched; "
                     "going on without the others",
                     now.requests, known.requests, now.statuses, known.statuses);
        known = now;  // the plant has changed: learn its readers afresh
        scheduler::save_reader_counts(state, known);
      } else {
        spdlog::info("{} request and {} status readers matched", now.requests, now.statuses);
      }
    }
    // Remembers more readers as they appear (services started after the scheduler).
    const auto learn_readers = [&] {
      const scheduler::ReaderCounts now{std::max(known.requests, requests.matched_readers()),
                                        std::max(known.statuses, statuses.matched_readers())};
      if (!(now == known)) {
        known = now;
        scheduler::save_reader_counts(state, known);
      }
    };
    sched.start(cycle);

    // Before the writers go: every reader (acquisition, historian) must have what was written,
    // or the last requests and statuses of a run would be lost with the process.
    const auto flush = [&] {
      if (!requests.wait_for_acknowledgments(std::chrono::seconds(10)) ||
          !statuses.wait_for_acknowledgments(std::chrono::seconds(10))) {
        spdlog::warn("not every reader acknowledged the last requests and statuses");
      }
    };
    if (!plant.simulated_clock) {
      service.dispatcher().every(std::chrono::seconds(1), [&] {
        sched.tick();
        learn_readers();
      });
      const int code = service.run();
      flush();
      return code;
    }

    // Simulated time: run the calendar as fast as the checks come back.
    auto& d = service.dispatcher();
    const auto stall = std::chrono::milliseconds(static_cast<std::int64_t>(stall_s * 1000));
    int spins = 0;
    while (!d.stopping()) {
      sched.tick();
      learn_readers();
      if (sched.idle()) {
        const auto next = sched.next_event_ns();
        if (until && (!next || *next > *until)) {
          char buffer[32];
          spdlog::info("simulated run complete at {}: nothing due before --until",
                       format_iso8601(simulated.now_ns(), buffer));
          sched.persist_clock();
          break;
        }
        if (next && *next > simulated.now_ns()) {
          simulated.set_ns(*next);
          sched.persist_clock();
          spins = 0;
          continue;
        }
        // Nothing to jump to (no calendar) or a decision due now that took none: wait for the
        // operator (commands, interventions) without spinning.
        if (++spins > 2) {
          progress = false;
          d.run_until([&] { return progress; }, std::chrono::milliseconds(500));
        }
        continue;
      }
      spins = 0;
      progress = false;
      if (!d.run_until([&] { return progress; }, stall) && !d.stopping()) {
        // No answer for a while: let simulated time run on to the next deadline (a timeout).
        const auto next = sched.next_event_ns();
        if (next && *next > simulated.now_ns()) {
          spdlog::warn("no answer for {} s of wall time: simulated clock runs on to the next deadline",
                       stall_s);
          simulated.set_ns(*next);
          sched.persist_clock();
        }
      }
    }
    flush();
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "ncqual-scheduler: " << e.what() << "\n";
    return 2;
  }
}
