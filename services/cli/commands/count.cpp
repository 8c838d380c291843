// SPDX-License-Identifier: Apache-2.0
// `ncqual count [--plant F | --db F] [--machine M]`: the number of stored results. Exit codes: 0,
// 6 when there is no historian database at the path: a removed historian file must not look like
// a plant with nothing stored (`ncqual wait --count N` waits for a database still to come); 2 for
// a machine the plant does not configure (without a plant config: that the historian holds
// nothing of).
#include "commands.hpp"

#include "ncqual/storage/database.hpp"

#include <iostream>

namespace ncqual::cli {
namespace {

struct Options {
  std::string plant;
  std::optional<std::string> db, machine;
};

int run(const Options& o) {
  const std::string path = database_path(o.db, o.plant);
  const bool configured = o.machine && check_machines_configured({*o.machine}, o.plant);
  auto db = open_historian(path, "count");
  if (!db) return kExitNotFound;
  if (o.machine && !configured) check_machines_held({*o.machine}, *db, path);
  std::cout << db->count_results(o.machine) << "\n";
  return kExitOk;
}

}  // namespace

void add_count(CLI::App& app, Commands& commands) {
  const auto [cmd, o] = add_command(app, commands, "count", "number of stored results", run);
  add_historian_options(cmd, o->plant, o->db);
  add_machine_option(cmd, o->machine, "only this machine's results");
}

}  // namespace ncqual::cli
