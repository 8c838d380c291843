// SPDX-License-Identifier: Apache-2.0
// Logging with spdlog: one logger per process, named after the service, level from a flag.
#pragma once

#include <spdlog/spdlog.h>

#include <string>

namespace ncqual {

// Sets up the default logger for a process: stderr, "[time] [service] [level] message".
// `level` is one of trace, debug, info, warn, error, critical, off; throws
// std::invalid_argument naming the value otherwise.
void init_logging(const std::string& service, const std::string& level);

}  // namespace ncqual
