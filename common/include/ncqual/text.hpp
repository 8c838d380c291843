// SPDX-License-Identifier: Apache-2.0
// Small text helpers shared by the configuration, the solver's labels and the state file.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual {

// `text` cut at every `sep`, entries untrimmed: "a,b" -> {"a", "b"}, "a," -> {"a", ""},
// "" -> {""}. Callers decide what an empty entry means.
std::vector<std::string> split_at(std::string_view text, char sep);

// The whole file at `path`, bytes as they are; nothing, with `*why` ("is a directory", the
// system's reason, "read error"), when it cannot be read. Callers name the file in their error.
std::optional<std::string> read_text_file(const std::string& path, std::string* why);

}  // namespace ncqual
