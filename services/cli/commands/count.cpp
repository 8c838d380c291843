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
  const auto [cmd, o] = add_command(app, commands, "count", "number of stored results", run);
  add_historian_options(cmd, o->plant, o->db);
  add_machine_option(cmd, o->machine, "only this machine's results");
}

}  // namespace ncqual::cli
