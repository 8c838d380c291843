// SPDX-License-Identifier: Apache-2.0
// `ncqual count [--plant F | --db F] [--machine M]`: the number of stored results (0 when there
// is no historian database yet).
#include "commands.hpp"

#include "ncqual/storage.hpp"

#include <filesystem>
#include <iostream>

namespace ncqual::cli {
namespace {

struct Options {
  std::string plant;
  std::optional<std::string> db, machine;
};

int run(const Options& o) {
  const std::string path = database_path(o.db, o.plant);
  if (!std::filesystem::exists(path)) {
    std::cout << 0 << "\n";
    return kExitOk;
  }
  auto db = storage::Database::open_readonly(path);
  std::cout << db.count_results(o.machine) << "\n";
  return kExitOk;
}

}  // namespace

void add_count(CLI::App& app, Commands& commands) {
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("count", "number of stored results");
  add_plant_option(cmd, o->plant);
  add_db_option(cmd, o->db);
  add_machine_option(cmd, o->machine, "only this machine's results");
  commands.push_back({cmd, [o] { return run(*o); }});
}

}  // namespace ncqual::cli
