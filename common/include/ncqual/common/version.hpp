// SPDX-License-Identifier: Apache-2.0
// The version of this build: the CMake project version and `git describe --always --dirty` of
// the source tree when it was built ("unknown" without git). The definitions are generated in
// the build tree (common/cmake/version.cmake); link ncqual_version to use them.
#pragma once

#include <string>
#include <string_view>

namespace ncqual {

// "0.1.0"
std::string_view version();

// "8c8baf2-dirty", or "unknown".
std::string_view git_describe();

// "<program> 0.1.0 (git 8c8baf2-dirty)": what every executable's --version prints.
std::string version_line(std::string_view program);

}  // namespace ncqual
