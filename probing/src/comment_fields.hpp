// SPDX-License-Identifier: Apache-2.0
// Reading the NCQUAL comments that make a program or a nominal list self-describing: the lines
// of a file and the "key=value" words of a comment, with errors (ProgramError) naming file, line
// and field. Internal to ncqual_probing.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::probing::detail {

// The lines of `text`: a UTF-8 BOM dropped, LF or CRLF, no empty last line.
std::vector<std::string> lines_of(const std::string& text);

// A count: digits only, at most nine.
std::optional<int> parse_integer(const std::string& s);

using Fields = std::map<std::string, std::string>;

// "key=value" words after the keyword of an NCQUAL comment.
Fields fields_of(const std::string& body, const std::string& file, int line);

// The value of `key`; ProgramError "<comment>: no <key>=" when there is none.
const std::string& field(const Fields& fields, const std::string& key, const std::string& comment,
                         const std::string& file, int line);

// The value of `key` as a finite number.
double number_field(const Fields& fields, const std::string& key, const std::string& comment,
                    const std::string& file, int line);

}  // namespace ncqual::probing::detail
