// SPDX-License-Identifier: Apache-2.0
// Small text helpers shared by the configuration, the solver's labels and the state file.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual {

// `text` cut at every `sep`, entries untrimmed: "a,b" -> {"a", "b"}, "a," -> {"a", ""},
// "" -> {""}. Callers decide what an empty entry means.
std::vector<std::string> split_at(std::string_view text, char sep);

// `v` with `decimals` digits after the point, never "-0.000": a zero is a zero whatever side it
// was rounded from.
std::string format_fixed(double v, int decimals);

// The whole of `word` as a finite number ("12", "-0.5", "1e-3"); nothing for anything else
// ("", "1.5mm", "nan", "inf", out of range).
std::optional<double> parse_finite_number(const std::string& word);

// The whole file at `path`, bytes as they are; nothing, with `*why` ("is a directory", the
// system's reason, "read error"), when it cannot be read. Callers name the file in their error.
std::optional<std::string> read_text_file(const std::string& path, std::string* why);

// The Levenshtein distance of `a` and `b` (insertions, deletions and substitutions of a byte),
// for "did you mean" in messages.
std::size_t edit_distance(std::string_view a, std::string_view b);

// Of `candidates`, the one nearest `word` by edit_distance when it is a likely typo of it (at
// most a third of the word's length in edits, and at most 3), for "did you mean 'X'?"; nothing
// when none is that near (another word, not a typo). The first of equally near ones wins.
std::optional<std::string_view> closest_word(std::string_view word,
                                             const std::vector<std::string_view>& candidates);

// Writes `text` to `path` so that a reader never sees part of it: into ".<name>.part" beside it,
// flushed to disk, then renamed over `path`. False, with `*why` (the system's reason), when it
// could not; then `path` is as it was and the part file is removed.
bool write_file_atomically(const std::string& path, const std::string& text, std::string* why);

}  // namespace ncqual
