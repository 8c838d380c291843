// SPDX-License-Identifier: Apache-2.0
// The fields of ncqual's CSV files (RFC 4180, docs/export.md): `ncqual export` and `ncqual trend
// --metric --csv` write their values through these, so both read the same way.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace ncqual::storage::csv {

// "2027-01-15T08:00:01.000000123Z": every digit of the ns since the epoch, UTC.
void append_utc(std::string& out, std::int64_t ns);
void append_int(std::string& out, std::int64_t value);
// The shortest text that reads back to the same double; "1200.0" rather than "1200", so a reader
// guessing types sees a real; "inf", "-inf" for the infinite bounds of one-sided bands.
void append_real(std::string& out, double value);
// Quoted (its quotes doubled) when it holds a comma, a quote or a line break; an empty text is
// quoted too, so that it differs from NULL (an empty field).
void append_text(std::string& out, std::string_view text);

}  // namespace ncqual::storage::csv
