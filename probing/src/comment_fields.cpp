// SPDX-License-Identifier: Apache-2.0
#include "comment_fields.hpp"

#include "ncqual/probing/program.hpp"
#include "ncqual/common/text.hpp"

#include <sstream>
#include <string_view>

namespace ncqual::probing::detail {

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::string_view t(text);
  if (t.substr(0, 3) == "\xEF\xBB\xBF") t.remove_prefix(3);
  std::size_t start = 0;
  while (start <= t.size()) {
    const std::size_t end = t.find('\n', start);
    std::string line(t.substr(start, end == std::string_view::npos ? end : end - start));
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(std::move(line));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  if (!lines.empty() && lines.back().empty()) lines.pop_back();
  return lines;
}

std::optional<int> parse_integer(const std::string& s) {
  if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 9) {
    return std::nullopt;
  }
  return std::stoi(s);
}

Fields fields_of(const std::string& body, const std::string& file, int line) {
  Fields fields;
  std::istringstream words(body);
  std::string word;
  while (words >> word) {
    const auto eq = word.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw ProgramError(file, line, "'" + word + "' is not key=value");
    }
    fields[word.substr(0, eq)] = word.substr(eq + 1);
  }
  return fields;
}

const std::string& field(const Fields& fields, const std::string& key, const std::string& comment,
                         const std::string& file, int line) {
  const auto it = fields.find(key);
  if (it == fields.end()) throw ProgramError(file, line, comment + ": no " + key + "=");
  return it->second;
}

double number_field(const Fields& fields, const std::string& key, const std::string& comment,
                    const std::string& file, int line) {
  const std::string& text = field(fields, key, comment, file, line);
  const auto v = parse_finite_number(text);
  if (!v) {
    throw ProgramError(file, line, comment + ": " + key + " = '" + text + "' is not a number");
  }
  return *v;
}

}  // namespace ncqual::probing::detail
