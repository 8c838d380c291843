// SPDX-License-Identifier: Apache-2.0
#include "ncqual/common/log.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>

#include <stdexcept>

namespace ncqual {

void init_logging(const std::string& service, const std::string& level) {
  const auto lvl = spdlog::level::from_str(level);
  if (lvl == spdlog::level::off && level != "off") {
    throw std::invalid_argument("--log-level '" + level +
                                "': expected trace, debug, info, warn, error, critical or off");
  }
  auto logger = spdlog::stderr_color_mt(service);
  logger->set_pattern("[%Y-%m-%dT%H:%M:%S.%e] [%n] [%l] %v");
  logger->set_level(lvl);
  spdlog::set_default_logger(logger);
}

}  // namespace ncqual
