// SPDX-License-Identifier: Apache-2.0
#include "ncqual/scheduler/driver.hpp"

#include <CLI/CLI.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace ncqual::scheduler {

ServedPlant serve_only(PlantConfig plant, const std::optional<std::string>& machine_list) {
  ServedPlant out;
  if (machine_list) {
    std::vector<MachineConfig> served = plant.machines_named(*machine_list, "--machine");
    for (const auto& m : plant.machines) out.others.insert(m.machine_id);
    for (const auto& m : served) out.others.erase(m.machine_id);
    plant.machines = std::move(served);
    std::string ids = *machine_list;
    std::replace(ids.begin(), ids.end(), ',', '+');
    plant.scheduler_state_database =
        (std::filesystem::path(plant.scheduler_state_database).parent_path() /
         ("scheduler-" + ids + ".db"))
            .string();
  }
  out.plant = std::move(plant);
  return out;
}

void add_flags(CLI::App& app, Flags& flags) {
  app.add_option("--machine", flags.machine_list,
                 "serve only these machines (one scheduler per machine or group; default: all)")
      ->type_name("ID[,ID...]");
  app.add_option("--cycle", flags.cycle,
                 "checks to run once at start, in order (default without a calendar: the "
                 "plant's scheduler.startup_checks; '' for none)")
      ->type_name("KIND,KIND,...");
  app.add_option("--state", flags.state,
                 "the durable state file (default: the plant's scheduler.state_database; with "
                 "--machine, scheduler-<ids>.db beside it)")
      ->type_name("FILE");
  app.add_option("--days", flags.days,
                 "simulated clock only: stop once nothing is due before that time")
      ->type_name("N");
  app.add_option("--until", flags.until, "simulated clock only: as --days, to an ISO 8601 UTC time")
      ->type_name("ISO-TIME");
  app.add_option("--stall-s", flags.stall_s,
                 "simulated clock: wall seconds without an answer before the clock runs on to "
                 "the check's timeout")
      ->type_name("S")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--speed", flags.speed,
                 "simulated clock: at most X simulated seconds per wall second (default: as fast "
                 "as the checks come back)")
      ->type_name("X")
      ->check(CLI::PositiveNumber);
}

Settings settle(PlantConfig plant, const Flags& flags) {
  Settings out;
  out.served = serve_only(std::move(plant), flags.machine_list);
  const PlantConfig& served = out.served.plant;
  out.cycle = flags.cycle ? check_kind_list(*flags.cycle)
                          : (served.calendar ? std::vector<CheckKind>{} : served.startup_checks);
  out.run.until_ns = simulated_run_end(served, flags.days, flags.until);
  if (flags.speed && !served.simulated_clock) {
    throw std::invalid_argument("--speed needs the plant's clock.mode: simulated");
  }
  out.run.speed = flags.speed;
  out.run.stall = std::chrono::milliseconds(static_cast<std::int64_t>(flags.stall_s * 1000));
  out.state_file = flags.state.value_or(served.scheduler_state_database);
  return out;
}

std::vector<CheckKind> check_kind_list(const std::string& text) {
  std::vector<CheckKind> kinds;
  std::size_t start = 0;
  while (start < text.size()) {
    const auto comma = std::min(text.find(',', start), text.size());
    const std::string name = text.substr(start, comma - start);
    const auto kind = parse_check_kind(name);
    if (!kind) throw std::invalid_argument("--cycle: '" + name + "' is not a check kind");
    kinds.push_back(*kind);
    start = comma + 1;
  }
  return kinds;
}

std::optional<std::int64_t> simulated_run_end(const PlantConfig& plant, std::optional<double> days,
                                              const std::optional<std::string>& until) {
  if (!plant.simulated_clock) {
    if (days || until) {
      throw std::invalid_argument("--days/--until need the plant's clock.mode: simulated");
    }
    return std::nullopt;
  }
  if (until) {
    const auto t = parse_iso8601(*until);
    if (!t) throw std::invalid_argument("--until: '" + *until + "' is not an ISO 8601 UTC time");
    return t;
  }
  if (!days) return std::nullopt;
  if (!(*days > 0)) throw std::invalid_argument("--days: must be > 0");
  constexpr double kNsPerDay = 86'400e9;
  return plant.simulated_start_ns + static_cast<std::int64_t>(*days * kNsPerDay);
}

void run_simulated(Scheduler& sched, SimulatedClock& clock, const Events& events,
                   const SimulatedRunOptions& options) {
  if (options.speed && !(*options.speed > 0)) {
    throw std::invalid_argument("simulated run: speed must be > 0");
  }
  const auto wall_start = options.wall_now();
  const std::int64_t simulated_start = clock.now_ns();
  // With a speed: the wall time still to wait before the clock may reach `t` (zero when it may).
  const auto pace = [&](std::int64_t t) {
    if (!options.speed) return std::chrono::milliseconds(0);
    const double due_s = static_cast<double>(t - simulated_start) / 1e9 / *options.speed;
    const double elapsed_s = std::chrono::duration<double>(options.wall_now() - wall_start).count();
    return std::chrono::milliseconds(
        static_cast<std::int64_t>(std::ceil(std::max(0.0, due_s - elapsed_s) * 1000)));
  };
  int idle_waits = 0;
  while (!events.stopping()) {
    sched.tick();
    if (sched.idle()) {
      const auto next = sched.next_event_ns();
      if (options.until_ns && (!next || *next > *options.until_ns)) {
        char buffer[32];
        spdlog::info("simulated run complete at {}: nothing due before --until",
                     format_iso8601(clock.now_ns(), buffer));
        sched.persist_clock();
        return;
      }
      if (next && *next > clock.now_ns()) {
        if (const auto early = pace(*next); early.count() > 0) {
          // Too soon for the speed: wait, taking what arrives meanwhile (an order, a result).
          events.wait_for_progress(std::min(early, std::chrono::milliseconds(1000)));
          continue;
        }
        clock.set_ns(*next);
        sched.persist_clock();
        idle_waits = 0;
        continue;
      }
      // Nothing to jump to (no calendar) or a decision due now that took none: wait for the
      // operator (commands, interventions) without spinning.
      if (++idle_waits > 2) {
        if (events.wait_for_progress(options.operator_patience)) {
          idle_waits = 0;
        } else if (options.give_up_after_idle_waits &&
                   idle_waits > 2 + *options.give_up_after_idle_waits) {
          sched.persist_clock();
          return;
        }
      }
      continue;
    }
    idle_waits = 0;
    if (!events.wait_for_progress(options.stall) && !events.stopping()) {
      // No answer for a while: let simulated time run on to the next deadline (a timeout).
      const auto next = sched.next_event_ns();
      if (next && *next > clock.now_ns()) {
        spdlog::warn(
            "no answer for {} ms of wall time: simulated clock runs on to the next "
            "deadline",
            options.stall.count());
        clock.set_ns(*next);
        sched.persist_clock();
      }
    }
  }
}

}  // namespace ncqual::scheduler
