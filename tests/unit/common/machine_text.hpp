// SPDX-License-Identifier: Apache-2.0
// Shared by the tests of a machine config's sections: the smallest machine to add a section to,
// and a section's YAML text with one piece replaced.
#pragma once

#include "ncqual/common/config.hpp"

#include <stdexcept>
#include <string>

namespace ncqual::testing {

// A machine config with only what every machine needs: its id, probe and monument.
inline const std::string kMachineHead = R"(
machine_id: t1
probe: {tool_length_mm: 300, ball_radius_mm: 2}
monument: {hole_center_mm: [10, 20], hole_diameter_mm: 40, face_z_mm: 100}
)";

// The machine of kMachineHead with `section` (YAML) after it, read as the file t1.yaml.
inline MachineConfig parse_machine_section(const std::string& section) {
  return parse_machine_config(kMachineHead + section, "t1.yaml");
}

// `text` with the first occurrence of `from` replaced by `to`; std::logic_error when there is
// none (the test's text changed under it).
inline std::string replace_first(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::logic_error("no '" + from + "' in the text");
  return text.replace(at, from.size(), to);
}

}  // namespace ncqual::testing
