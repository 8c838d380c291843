// ncqual-scheduler: runs the qualification process. On start it issues the configured cycle of
// checks for every machine; on an operator's CheckCommand it issues that check; on each result
// it publishes the machine's status.
#include "scheduler.hpp"

#include "ncqual/args.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/log.hpp"

#include <spdlog/spdlog.h>

#include <iostream>

int main(int argc, char** argv) {
  using namespace ncqual;
  try {
    const Args args(std::vector<std::string>(argv + 1, argv + argc),
                    {"plant", "domain", "log-level", "cycle"}, {"help"});
    if (args.has("help")) {
      std::cout << "usage: ncqual-scheduler --plant FILE [--domain N] [--cycle kind,kind,...]\n"
                   "                        [--log-level info]\n"
                   "--cycle overrides the plant's scheduler.startup_checks ('' for none).\n";
      return 0;
    }
    init_logging("scheduler", args.get_or("log-level", "info"));
    const PlantConfig plant = load_plant_config(ncqual::dds::plant_file_from(args.get_or("plant", "")));
    std::vector<CheckKind> cycle = plant.startup_checks;
    if (auto text = args.get("cycle")) {
      cycle.clear();
      std::size_t start = 0;
      while (start < text->size()) {
        const auto comma = text->find(',', start);
        const std::string name = text->substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        const auto kind = parse_check_kind(name);
        if (!kind) throw ArgError("--cycle: '" + name + "' is not a check kind");
        cycle.push_back(*kind);
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
    }

    ncqual::dds::Service service({"scheduler", "",
                          ncqual::dds::resolve_domain_id(args.get_int("domain", -1), plant.domain_id),
                          plant.qos_profiles_file});
    auto& p = service.participant();
    ncqual::dds::Writer<ncqual::dds::CheckRequestTopic> requests(p);
    ncqual::dds::Writer<ncqual::dds::MachineStatusTopic> statuses(p);
    ncqual::dds::Reader<ncqual::dds::CheckResultTopic> results(p);
    ncqual::dds::Reader<ncqual::dds::CheckCommandTopic> commands(p);

    scheduler::Scheduler sched(plant, service.clock(),
                               {[&](const CheckRequest& r) {
                                  if (!requests.write(r)) spdlog::error("{}: request not queued", r.request_id);
                                },
                                [&](const MachineStatus& s) { statuses.write(s); }});
    service.dispatcher().on(results, [&](ncqual::dds::Received<CheckResult> in) {
      if (!in.error.empty()) {
        spdlog::error("result {} of '{}' ignored: {}", in.value.request_id, in.value.machine_id, in.error);
        return;
      }
      sched.result(in.value);
    });
    service.dispatcher().on(commands, [&](ncqual::dds::Received<CheckCommand> in) {
      const std::string refused = in.error.empty() ? sched.command(in.value) : in.error;
      if (!refused.empty()) spdlog::error("check command {} refused: {}", in.value.request_id, refused);
    });
    sched.start_cycle(cycle);
    return service.run();
  } catch (const std::exception& e) {
    std::cerr << "ncqual-scheduler: " << e.what() << "\n";
    return 2;
  }
}
