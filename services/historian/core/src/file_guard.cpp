// SPDX-License-Identifier: Apache-2.0
// The historian's database file watched for removal or replacement (file_guard.hpp).
#include "ncqual/historian/file_guard.hpp"

#include "ncqual/common/clock.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace ncqual::historian {

std::string rescue_name(const std::string& path, std::int64_t now_ns) {
  char buffer[32];
  std::string stamp(format_iso8601(now_ns, buffer));
  stamp.erase(std::remove(stamp.begin(), stamp.end(), ':'), stamp.end());
  return path + ".rescued-" + stamp;
}

std::string FileGuard::check(std::int64_t now_ns) {
  const std::string problem = db_.file_problem();
  if (problem.empty()) {
    rescued_ = false;
    rescued_to_.clear();
    return "";
  }
  if (!rescued_) {
    rescued_ = true;
    const std::string copy = rescue_name(path_, now_ns);
    try {
      db_.copy_to(copy);
      rescued_to_ = copy;
      spdlog::error("{}: everything stored until now is copied to {}", problem, copy);
    } catch (const std::exception& e) {
      spdlog::error("{}: what was stored could not be copied to {}: {}", problem, copy, e.what());
    }
  }
  return problem +
         "; nothing is stored or acknowledged until it is back or the historian is restarted";
}

}  // namespace ncqual::historian
