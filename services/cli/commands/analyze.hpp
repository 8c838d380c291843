// SPDX-License-Identifier: Apache-2.0
// What the subcommands of `ncqual analyze` share (analyze.cpp): their options, the figures in mm,
// the refusal of an evaluation and the judging of touches and points; each subcommand adds itself
// to `analyze` (analyze_<subcommand>.cpp).
#pragma once

#include "commands.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace ncqual::cli::analysis {

// What the analyses take on the command line.
struct Options {
  std::string file;  // iso230-2 and circle
  bool json = false;
  std::optional<std::string> plane;         // circle
  std::optional<double> nominal_radius_mm;  // circle
  std::optional<std::string> centre_mm;     // circle
  std::string x_run, y_run, grid;           // grid
  std::optional<std::string> grid_machine;  // grid: the machine of tracker point exports
  std::string program, machine, plant;      // touches (program), points (the nominal list);
                                            // plant: grid too
};

// A length in mm as the tables print it (4 decimals); "-" for none.
std::string mm(double v);
std::string mm(const std::optional<double>& v);

// An evaluation refused (std::invalid_argument) is reported as "<file>: message", exit 1.
int refusing(const std::string& file, int (*run)(const Options&), const Options& o);

// The set of a file (o.file) and the program or nominal list it answers (o.program), read by
// `from_files` (touches_from_files, points_from_files), judged as the solver service judges it
// and printed (or its check record with --json). `what`: "touches" or "points"; `answers`:
// "program" or "nominals".
using SetFromFiles = MeasurementSet (*)(const std::string&, const std::string&,
                                        const MachineConfig&, std::int64_t);
int judge_files(const Options& o, SetFromFiles from_files, const char* what, const char* answers);
// A judged check's metrics against their tolerances, reason, likely causes and correction, as
// `analyze touches|points|grid --machine` print them.
void print_judgement(const CheckResult& r);
// The check record of `ncqual history --json` (ncqual/storage/json.hpp) of `r`, judged from `set`.
nlohmann::json check_record_json(const CheckResult& r, const MeasurementSet& set);

// What runs each subcommand (analyze_<subcommand>.cpp); add_analyze (analyze.cpp) lists them with
// their help, their file and a --json flag, in the order of the help.
int run_iso230_2(const Options& o);
int run_circle(const Options& o);
int run_grid(const Options& o);
int run_cmm(const Options& o);
int run_touches(const Options& o);
int run_points(const Options& o);
// The options of their own beside the file and --json.
void circle_options(CLI::App* circle, Options& o);
void grid_options(CLI::App* grid, Options& o);
void touches_options(CLI::App* touches, Options& o);
void points_options(CLI::App* points, Options& o);

}  // namespace ncqual::cli::analysis
