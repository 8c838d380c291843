// SPDX-License-Identifier: Apache-2.0
// ncqual-web's HTTP server: serves web::Dashboard on the plant's web.bind and web.port (0: any
// free port, logged) until SIGTERM or SIGINT, when the listener closes and requests under way
// finish. Under systemd (Type=notify) it says READY once it listens and, with WatchdogSec=, pings
// the watchdog while it still answers its own requests.
#pragma once

#include "ncqual/common/config.hpp"

#include <string>

namespace ncqual::web {

// Returns the exit code: 0 after a stop, 1 when listening failed. Throws ConfigError when it
// cannot listen on the address.
int serve(const PlantConfig& plant, const std::string& database);

}  // namespace ncqual::web
