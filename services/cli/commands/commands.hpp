// SPDX-License-Identifier: Apache-2.0
// The commands of `ncqual`. Each file in this folder adds one command to the CLI11 app (its
// options, its help) and registers what runs it; a command with subcommands has one file per
// subcommand beside it (analyze_*.cpp, db_*.cpp, sharing analyze.hpp, db.hpp). main.cpp only
// builds the app from them, parses and dispatches. Exit codes: exit_codes.hpp.
#pragma once

#include "exit_codes.hpp"

#include "ncqual/common/calendar.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/dds/identity.hpp"
#include "ncqual/dds/participant.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/solver/instrument_files.hpp"
#include "ncqual/storage/database.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ncqual::dds {
struct TopicInfo;
}

namespace ncqual::cli {

// Bad usage found once the command line is parsed (a value that makes no sense, no plant
// config): main prints it with the command's usage and exits kExitUsage.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A (sub)command that runs: its CLI11 app, and what runs it once the command line is parsed.
struct Command {
  CLI::App* app;
  std::function<int()> run;
};
using Commands = std::vector<Command>;

// Each adds its command to `app` and its runner(s) to `commands`.
void add_history(CLI::App& app, Commands& commands);      // history.cpp
void add_check(CLI::App& app, Commands& commands);        // check.cpp
void add_wait(CLI::App& app, Commands& commands);         // wait.cpp
void add_count(CLI::App& app, Commands& commands);        // count.cpp
void add_budget(CLI::App& app, Commands& commands);       // budget.cpp
void add_analyze(CLI::App& app, Commands& commands);      // analyze.cpp
void add_import(CLI::App& app, Commands& commands);       // import.cpp
void add_program(CLI::App& app, Commands& commands);      // program.cpp
void add_status(CLI::App& app, Commands& commands);       // status.cpp
void add_intervene(CLI::App& app, Commands& commands);    // intervene.cpp
void add_trend(CLI::App& app, Commands& commands);        // trend.cpp
void add_uncertainty(CLI::App& app, Commands& commands);  // uncertainty.cpp
void add_config(CLI::App& app, Commands& commands);       // config.cpp
void add_db(CLI::App& app, Commands& commands);           // db.cpp
void add_export(CLI::App& app, Commands& commands);       // export.cpp
void add_backup(CLI::App& app, Commands& commands);       // export.cpp
void add_record(CLI::App& app, Commands& commands);       // record.cpp (record, recording)
void add_replay(CLI::App& app, Commands& commands);       // replay.cpp
void add_report(CLI::App& app, Commands& commands);       // report.cpp
void add_completion(CLI::App& app, Commands& commands);   // completion.cpp (hidden)

// ---- What several commands share (options.cpp) -------------------------------------------------

// Adds the command `name` to `parent`, its options in a new Options, and run(options) to
// `commands` as what runs it; returns the command and its options, for the command's own flags.
template <typename Options>
std::pair<CLI::App*, std::shared_ptr<Options>> add_command(CLI::App& parent, Commands& commands,
                                                           const std::string& name,
                                                           const std::string& description,
                                                           int (*run)(const Options&)) {
  auto options = std::make_shared<Options>();
  CLI::App* command = parent.add_subcommand(name, description);
  commands.push_back({command, [options, run] { return run(*options); }});
  return {command, options};
}

// --plant FILE (else $NCQUAL_PLANT).
CLI::Option* add_plant_option(CLI::App* command, std::string& plant);
// --db FILE: the historian database (read only).
CLI::Option* add_db_option(CLI::App* command, std::optional<std::string>& db);
// --machine M.
CLI::Option* add_machine_option(CLI::App* command, std::optional<std::string>& machine,
                                const std::string& description);
CLI::Option* add_machine_option(CLI::App* command, std::string& machine,
                                const std::string& description);  // required
// --domain N (else $NCQUAL_DOMAIN, else the plant's domain_id).
CLI::Option* add_domain_option(CLI::App* command, int& domain);
// --plant FILE and --db FILE: the historian database a command reads (database_path).
void add_historian_options(CLI::App* command, std::string& plant, std::optional<std::string>& db);
// What a command that joins DDS takes: the plant, the domain and, on a secured plant, the
// security material and the identity to run as.
struct DdsOptions {
  std::string plant;
  int domain = -1;
  std::string secure;    // --secure DIR: ncqual-pki's material (else the plant's security.dir)
  std::string identity;  // --identity NAME (else $NCQUAL_IDENTITY, else the command's default)
};
// --plant FILE, --domain N, --secure DIR and --identity NAME.
void add_dds_options(CLI::App* command, DdsOptions& options);
// The participant of a command on `plant`, named `name`; `default_identity` is the identity it
// runs as on a secured plant without --identity or NCQUAL_IDENTITY.
dds::ParticipantOptions command_participant(const PlantConfig& plant, const DdsOptions& options,
                                            const std::string& name,
                                            const std::string& default_identity);
// The default identity of an operator's command: operator-<this host's name>.
std::string operator_identity();
// --json: one JSON document instead of the table.
CLI::Option* add_json_flag(CLI::App* command, bool& json);
// --<name> KIND: a check kind, refused at parsing when it is not one.
CLI::Option* add_kind_option(CLI::App* command, const std::string& name,
                             std::optional<CheckKind>& kind, const std::string& description);

// The plant config of --plant or NCQUAL_PLANT; UsageError when neither names one.
PlantConfig plant_from(const std::string& plant_flag);
// The plant's machine `machine_id`; UsageError naming it, the machines the plant configures and
// the nearest of them when it is a likely typo, when the plant has no such machine.
const MachineConfig& configured_machine(const PlantConfig& plant, const std::string& machine_id);
// For the commands that read the historian (history, count, export), before they open it: each
// of `machines` must be one the plant config (--plant or NCQUAL_PLANT) configures, else
// UsageError (configured_machine). False when there is no plant config to check against: then
// check_machines_held, once the historian is open. A configured machine without a stored check is
// no error.
bool check_machines_configured(const std::vector<std::string>& machines,
                               const std::string& plant_flag);
// Without a plant config: each of `machines` must be one the historian `db` (at `db_path`) holds
// rows of; else UsageError naming it, the machines it holds and the nearest name.
void check_machines_held(const std::vector<std::string>& machines, storage::Database& db,
                         const std::string& db_path);

// One part of a tracker grid ("x_run", "y_run" or "grid") from `table`: a grid file
// (point,x_cmd,..,z_meas), or a tracker's point export (a name and x, y, z) whose commanded
// positions come from `machine`'s monthly program (solver::grid_points_from_export); exported
// points the program does not name are listed on stderr as warnings. UsageError for a point
// export without a machine.
std::vector<solver::GridFilePoint> read_grid_part(const CsvTable& table, const std::string& prefix,
                                                  const MachineConfig* machine);

// One part of a tracker grid read from `path` (read_grid_part), each point refused at its cell
// when no instrument on `machine` can have read it (solver::check_grid_envelope; no such check
// without a machine or its global_check: section). `last_line`: the file's last row's line.
struct GridPart {
  std::vector<solver::GridFilePoint> points;
  int last_line = 0;
};
GridPart read_grid_file(const std::string& path, const std::string& prefix,
                        const MachineConfig* machine);

// "warning: <file>: N points are not <what> and not used: 'NEST1' (line 3), ..." on stderr
// (up to five named); nothing when `unused` is empty.
void warn_unused(const std::string& file, const std::vector<solver::TrackerExportPoint>& unused,
                 const std::string& what);

// The calendar of the plant config of --plant or NCQUAL_PLANT (its time zone is the one people
// read times in); the default calendar (UTC) when neither names one.
Calendar plant_calendar(const std::string& plant_flag);
// The historian database of history, wait and count: --db, else the plant config's (--plant or
// NCQUAL_PLANT), else the demo's var/historian.db ($NCQUAL_VAR); UsageError when there is none.
std::string database_path(const std::optional<std::string>& db, const std::string& plant_flag);
// The historian database at `path`, read only; nothing, after "ncqual <command>: no historian
// database at <path>" on stderr, when there is no such file (the command exits kExitNotFound).
std::optional<storage::Database> open_historian(const std::string& path,
                                                const std::string& command);

// The MeasurementSet of a control's touch log and the probing program that wrote it
// (ncqual/probing/program.hpp; program.cpp), for `analyze touches` and `import touches`; throws
// probing::ProgramError naming the file and line.
MeasurementSet touches_from_files(const std::string& log_file, const std::string& program_file,
                                  const MachineConfig& machine, std::int64_t time_ns);

// The MeasurementSet of a tracker's point export (`export_file`: a name and x, y, z, as
// solver::read_tracker_points_csv reads it) of a check whose nominal list `ncqual program` wrote
// (`nominals_file`, ncqual/probing/tracker_nominals.hpp): the list names machine, check and
// request; each point is paired by name with the machine's program of that check
// (solver::tracker_points_from_export), refused at its cell when no instrument on the machine
// can have read it (solver::check_grid_envelope). The list must still be the machine's program
// (the same points at the same nominal positions, within 1 µm): a list written before the
// machine's global_check: section changed is refused. For `analyze points` and `import
// points`; throws probing::ProgramError (the list) or CsvError (the export) naming file and line;
// exported points the program does not name are warned of on stderr.
MeasurementSet points_from_files(const std::string& export_file, const std::string& nominals_file,
                                 const MachineConfig& machine, std::int64_t time_ns);

// --topics T,... and --machine M,... of the commands that record or replay samples.
void add_sample_filter_options(CLI::App* command, std::vector<std::string>& topics,
                               std::vector<std::string>& machines);
// The ncqual topics --topics names (recording::topics_named); UsageError naming an unknown one.
std::vector<const dds::TopicInfo*> topics_option(const std::vector<std::string>& names);

// A date or time given to `flag` (--since, --until, --before), read in the plant's time zone
// (Calendar::parse_time: "2027-01-15" is its local midnight, "2027-01-15T06:00" a local time, a
// time with Z or an offset means what it says), in ns since the epoch; UsageError naming the
// flag, the text and the zone when it is none of these.
std::int64_t plant_time_option(const std::string& flag, const std::string& text,
                               const Calendar& calendar);
// What a date flag's help says of its zone.
inline constexpr const char* kPlantZoneHelp =
    "in the plant's time zone (UTC without a plant config)";

// The operator: $USER, else the host name.
std::string operator_name();
// "<prefix>-<machine>-<now ns>-<pid>": the id of a sample this process publishes.
std::string new_sample_id(const std::string& prefix, const std::string& machine_id);

}  // namespace ncqual::cli

namespace ncqual::storage {
struct CheckRecord;
}
namespace ncqual::solver {
enum class Plane;
}

namespace ncqual::cli {

// --plane XY|YZ|XZ of the circular tests (analyze, import): nothing when not given; UsageError
// naming the value when it is not a plane.
std::optional<solver::Plane> plane_option(const std::optional<std::string>& text);
// --centre-mm U,V: two numbers (mm); UsageError naming the value otherwise.
std::pair<double, double> centre_option(const std::string& text);

// Checks as a table (history, check --wait; history.cpp): one row per check (its time in the
// calendar's zone with the offset, who ordered it), with the reason and the first likely cause of
// those that did not pass; with `writers`, who wrote each part (history --writers), named by
// those identities when there are any.
void print_check_records(const std::vector<storage::CheckRecord>& records, const Calendar& calendar,
                         const std::vector<dds::PlantIdentity>* writers = nullptr);

}  // namespace ncqual::cli
