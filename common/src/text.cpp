// SPDX-License-Identifier: Apache-2.0
#include "ncqual/text.hpp"

namespace ncqual {

std::vector<std::string> split_at(std::string_view text, char sep) {
  std::vector<std::string> parts;
  std::size_t from = 0;
  for (std::size_t at; (at = text.find(sep, from)) != std::string_view::npos; from = at + 1) {
    parts.emplace_back(text.substr(from, at - from));
  }
  parts.emplace_back(text.substr(from));
  return parts;
}

}  // namespace ncqual
