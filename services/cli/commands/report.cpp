// SPDX-License-Identifier: Apache-2.0
// `ncqual report`: one machine's qualification report as one self-contained HTML file
// (docs/report.md).
//
//   ncqual report --machine M [--check ID | --since D] --out FILE.html [--plant F] [--db F]
//
// Gathers from the historian (read only) what report::gather_machine_report gathers: the
// machine's state and trend warnings, the newest monthly grid, ISO 230-2 run and circular tests
// of the range, each metric's trend, the checks of the range, the error budget; and writes
// report::machine_report_document into FILE (a temporary file beside it, renamed: FILE is whole
// or untouched). --since: a date or time in the plant's zone as `ncqual trend` takes it; --check:
// one check by its request id. "Now" is `ncqual status`'s: the wall clock, or on a simulated clock
// the machine's newest status time. The plant config (--plant or NCQUAL_PLANT) gives the machine's
// nominal positions and budget, the clock and the historian; without one, --db names the historian
// and the sections that need the machine's configuration say so.
//
// Exit codes: 0 written; 2 bad usage (a bad date, --check with --since, a machine the plant does
// not configure or, without a plant config, the historian holds nothing of; no plant and no
// --db); 6 no historian file, a check the historian does not know, or a configured machine with
// nothing stored yet; 1 anything else (FILE cannot be written: the message names it).
#include "commands.hpp"

#include "ncqual/common/version.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/status/plant_status.hpp"
#include "ncqual/report/machine_report.hpp"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include <unistd.h>

namespace ncqual::cli {
namespace {

struct Options {
  std::string plant, machine, out;
  std::optional<std::string> db, check, since;
};

// FILE's folder must exist and FILE must not be a folder: said before anything is gathered.
void check_out_path(const std::string& out) {
  namespace fs = std::filesystem;
  const fs::path path(out);
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    throw std::runtime_error("--out " + out + ": is a folder, not a file");
  }
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  if (!fs::is_directory(folder, ec)) {
    throw std::runtime_error("--out " + out + ": no folder " + folder.string());
  }
}

// Writes `text` to `out` through a temporary file beside it, renamed over it when whole.
void write_whole(const std::string& out, const std::string& text) {
  const std::string temporary = out + ".tmp-" + std::to_string(getpid());
  {
    std::ofstream f(temporary, std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error("--out " + out + ": cannot write " + temporary);
    f << text;
    f.close();
    if (!f) {
      std::filesystem::remove(temporary);
      throw std::runtime_error("--out " + out + ": writing " + temporary + " failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(temporary, out, ec);
  if (ec) {
    std::filesystem::remove(temporary);
    throw std::runtime_error("--out " + out + ": cannot be replaced: " + ec.message());
  }
}

int run(const Options& o) {
  if (o.check && o.since) throw UsageError("--check and --since: choose one");
  report::MachineReportQuery query;
  query.machine_id = o.machine;
  query.check_id = o.check;

  const std::string plant_file = plant_config_path(o.plant);
  if (plant_file.empty() && !o.db) {
    throw UsageError("pass --plant FILE (or set NCQUAL_PLANT), or --db FILE");
  }
  std::optional<PlantConfig> plant;
  if (!plant_file.empty()) {
    plant = load_plant_config(plant_file);
    query.machine = &configured_machine(*plant, o.machine);
  }
  const Calendar calendar(plant && plant->calendar ? *plant->calendar : default_calendar_config());
  if (o.since) query.since_ns = plant_time_option("--since", *o.since, calendar);
  query.calendar = &calendar;
  check_out_path(o.out);
  const std::string db_path = o.db.value_or(plant ? plant->historian_database : "");
  auto opened = open_historian(db_path, "report");
  if (!opened) return kExitNotFound;
  storage::Database& db = *opened;
  if (!plant) check_machines_held({o.machine}, db, db_path);

  // "Now" as `ncqual status` has it: the wall clock, or the machine's simulated clock.
  query.now_ns = WallClock().now_ns();
  if (plant) {
    const auto status = plant_status::plant_status(db, *plant, plant_status::plant_calendar(*plant),
                                                   {o.machine, query.now_ns});
    if (status.now_ns) query.now_ns = *status.now_ns;
  }
  report::MachineReport gathered;
  try {
    gathered = report::gather_machine_report(db, query);
  } catch (const std::invalid_argument& e) {
    std::cerr << "ncqual report: " << e.what() << " (" << db_path << ")\n";
    return kExitNotFound;
  }
  gathered.produced_by = version_line("ncqual report");
  write_whole(o.out, report::machine_report_document(gathered));
  std::cout << "wrote " << o.out << "\n";
  return kExitOk;
}

}  // namespace

void add_report(CLI::App& app, Commands& commands) {
  auto [cmd, o] = add_command(
      app, commands, "report",
      "one machine's qualification report as one self-contained HTML file (charts inline, no\n"
      "network, no script; prints to PDF): state, grid, ISO 230-2, circles, trends, checks, budget",
      run);
  add_machine_option(cmd, o->machine, "the machine to report on");
  cmd->add_option("--check", o->check, "only this check (its request id)")->type_name("ID");
  cmd->add_option("--since", o->since,
                  std::string("the checks at or after this date or time, ") + kPlantZoneHelp)
      ->type_name("D");
  cmd->add_option("--out", o->out, "the HTML file to write (replaced whole)")
      ->type_name("FILE.html")
      ->required();
  add_plant_option(cmd, o->plant);
  add_db_option(cmd, o->db);
}

}  // namespace ncqual::cli
