// SPDX-License-Identifier: Apache-2.0
// `ncqual analyze points`: a laser tracker's point export of a tracker check against the nominal
// list `ncqual program` wrote, judged as the solver service judges it (judge_files, analyze.cpp).
#include "analyze.hpp"

namespace ncqual::cli::analysis {
namespace {

int run_points(const Options& o) { return judge_files(o, points_from_files, "points", "nominals"); }

}  // namespace

void add_points(CLI::App* analyze, const std::shared_ptr<Options>& o, Commands& commands) {
  CLI::App* points = analyze->add_subcommand(
      "points",
      "judge a laser tracker's point export of a tracker check (a name and x, y, z per point)\n"
      "against the nominal list `ncqual program` wrote for it, exactly as the solver service\n"
      "judges the check (exit code: its verdict)");
  points->add_option("EXPORT", o->file, "the tracker software's point export")->required();
  points->add_option("--nominals", o->program, "the nominal list the points were measured to")
      ->type_name("LIST")
      ->required();
  add_machine_option(points, o->machine, "the machine measured");
  add_plant_option(points, o->plant);
  add_json_flag(points, o->json);
  commands.push_back({points, [o] { return refusing(o->file, run_points, *o); }});
}

}  // namespace ncqual::cli::analysis
