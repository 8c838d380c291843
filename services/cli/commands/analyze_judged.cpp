// SPDX-License-Identifier: Apache-2.0
// `ncqual analyze touches` and `ncqual analyze points`: a real control's touch log of a program
// `ncqual program` wrote, or a laser tracker's point export of a tracker check against the nominal
// list it wrote, judged exactly as the solver service judges the check.
#include "analyze.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/common/version.hpp"
#include "ncqual/solver/solve.hpp"
#include "ncqual/storage/json.hpp"

#include <fmt/format.h>

#include <iostream>

namespace ncqual::cli::analysis {
namespace {

// The file the judged one answers (`flag`: the program or the nominal list), the machine and the
// plant.
void answered_options(CLI::App* command, Options& o, const char* flag, const char* type,
                      const char* help, const char* machine_help) {
  command->add_option(flag, o.program, help)->type_name(type)->required();
  add_machine_option(command, o.machine, machine_help);
  add_plant_option(command, o.plant);
}

}  // namespace

int judge_files(const Options& o, SetFromFiles from_files, const char* what, const char* answers) {
  const PlantConfig plant = plant_from(o.plant);
  const MachineConfig& machine = configured_machine(plant, o.machine);
  const std::int64_t now = WallClock().now_ns();
  const MeasurementSet set = from_files(o.file, o.program, machine, now);
  CheckResult r = solver::solve(set, machine, now);
  r.produced_by = version_line("ncqual analyze");
  if (o.json) {
    std::cout << check_record_json(r, set).dump(2) << "\n";
  } else {
    fmt::print("{} on {}: {} {} of {} ({} {}, request {}): {}\n", to_string(r.kind), r.machine_id,
               set.touches.size() + set.tracker_points.size(), what, o.file, answers, o.program,
               r.request_id, to_string(r.verdict));
    print_judgement(r);
  }
  return exit_code_of(r.verdict);
}

void print_judgement(const CheckResult& r) {
  for (const Metric& m : r.metrics) {
    fmt::print("  {:<28} {:>12} {:<6} [{}, {}]{}\n", m.name, format_metric_value(m), m.unit,
               format_metric_value(Metric{m.name, m.lower, m.unit, m.lower, m.upper, true}),
               format_metric_value(Metric{m.name, m.upper, m.unit, m.lower, m.upper, true}),
               m.pass ? "" : "  (!) out of tolerance");
  }
  if (!r.reason.empty()) fmt::print("reason: {}\n", r.reason);
  for (std::size_t i = 0; i < r.likely_causes.size(); ++i) {
    fmt::print("likely cause {}: {}\n", i + 1, r.likely_causes[i]);
  }
  if (r.correction) {
    for (const auto& c : r.correction->offsets) {
      fmt::print("correction {}: {} = {} {}\n", r.correction->target, c.name, c.value, c.unit);
    }
  }
}

nlohmann::json check_record_json(const CheckResult& r, const MeasurementSet& set) {
  storage::CheckRecord rec;
  rec.machine_id = r.machine_id;
  rec.request_id = r.request_id;
  rec.kind = r.kind;
  rec.result = r;
  storage::MeasurementSummary measured;
  measured.instrument = set.instrument;
  measured.frame = set.frame;
  measured.time_ns = set.time_ns;
  measured.touches = static_cast<std::int64_t>(set.touches.size());
  measured.tracker_points = static_cast<std::int64_t>(set.tracker_points.size());
  rec.measurement = measured;
  return storage::to_json(rec);
}

int run_touches(const Options& o) {
  return judge_files(o, touches_from_files, "touches", "program");
}

int run_points(const Options& o) { return judge_files(o, points_from_files, "points", "nominals"); }

void touches_options(CLI::App* touches, Options& o) {
  answered_options(touches, o, "--program", "PROG", "the program that wrote it",
                   "the machine that ran it");
}

void points_options(CLI::App* points, Options& o) {
  answered_options(points, o, "--nominals", "LIST", "the nominal list the points were measured to",
                   "the machine measured");
}

}  // namespace ncqual::cli::analysis
