// SPDX-License-Identifier: Apache-2.0
// ncqual-web: the live plant dashboard (docs/dashboard.md). Serves the pages and the JSON of
// ncqual/web/dashboard.hpp over HTTP (cpp-httplib 0.11) from the historian's database opened
// read-only. A process of its own, not a part of the historian: a slow page or a fault here can
// never hold up storage, and it joins no DDS domain.
//
//   ncqual-web [--plant F] [--db F] [--bind ADDR] [--port N] [--log-level L]
//
// --plant (else NCQUAL_PLANT) gives the machines, the calendar and, in its `web:` section, where
// to listen (default 127.0.0.1:8470); --bind and --port replace those (--port 0: any free port,
// logged). --db replaces the plant's historian database. The server and its life: serve.hpp.
#include "serve.hpp"

#include "ncqual/common/command_line.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/common/log.hpp"
#include "ncqual/storage/database.hpp"

#include <filesystem>
#include <string>

namespace {

using namespace ncqual;

int run(int argc, char** argv) {
  CLI::App app(
      "The live plant dashboard: the historian's machines, checks and warnings over "
      "HTTP, read-only (docs/dashboard.md).",
      "ncqual-web");
  command_line::configure(app);
  std::string plant_flag;
  std::string db;
  std::string bind;
  int port = -1;
  std::string log_level = "info";
  app.add_option("--plant", plant_flag, "the plant config (else $NCQUAL_PLANT)");
  app.add_option("--db", db, "the historian database, opened read-only (else the plant's)");
  app.add_option("--bind", bind,
                 "the IPv4 address to listen on (else the plant's web.bind, default 127.0.0.1)");
  app.add_option("--port", port, "the port (else the plant's web.port, default 8470; 0: any)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error, critical or off");
  if (const auto code = command_line::parse(app, argc, argv)) return *code;
  init_logging("web", log_level);

  const std::string plant_file = plant_config_path(plant_flag);
  if (plant_file.empty())
    throw ConfigError("no plant config: pass --plant FILE or set NCQUAL_PLANT");
  PlantConfig plant = load_plant_config(plant_file);
  if (!bind.empty()) {
    if (const auto a = parse_network_address(bind);
        !a || a->port != 0 || bind.find_first_not_of("0123456789.") != std::string::npos) {
      throw ConfigError("--bind '" + bind + "': expected an IPv4 address, e.g. 127.0.0.1");
    }
    plant.web.bind = bind;
  }
  if (port >= 0) plant.web.port = port;
  const std::string database = db.empty() ? plant.historian_database : db;
  if (!std::filesystem::exists(database)) {
    throw storage::StorageError("no historian database at " + database +
                                " (the historian creates it when it first starts)");
  }

  return web::serve(plant, database);
}

}  // namespace

int main(int argc, char** argv) {
  return ncqual::command_line::guarded_main("ncqual-web", [&] { return run(argc, argv); });
}
