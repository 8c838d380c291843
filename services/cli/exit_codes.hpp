// SPDX-License-Identifier: Apache-2.0
// The exit codes of `ncqual`, every command's, in one place: one mistake gives one code whatever
// the command (docs/running.md, "Exit codes"). Scripts and tests depend on the numbers: append,
// never renumber. `ncqual --help` prints kExitCodesHelp.
#pragma once

#include "ncqual/common/model.hpp"

namespace ncqual::cli {

enum ExitCode : int {
  kExitOk = 0,        // done; for a verdict (`check --wait`): PASS
  kExitError = 1,     // an error the command reported (bad file, nobody listening, ...)
  kExitUsage = 2,     // bad usage: unknown flag, missing or bad value (the message names it)
  kExitFail = 3,      // the check's verdict is FAIL
  kExitInvalid = 4,   // the check's verdict is INVALID: the data were refused
  kExitTimedOut = 5,  // `wait` or `check --wait` gave up
  kExitNotFound = 6,  // what was asked for is not there (e.g. no historian database)
  kExitCorrupt = 7,   // `db check`: the database fails PRAGMA integrity_check or cannot be read;
                      // `db recover`: the recovered file fails it; `backup`: the copy fails it
  // 8 is kept for the verdict INCONCLUSIVE (a value within its limits by less than its
  // measurement uncertainty, under the plant's decision rule): not used yet.
  kExitRefused = 9,  // a service refused the order or sample (`check`, `intervene`, `import`):
                     // the reason it gave is printed; nothing was done
};

// The exit code of a check's verdict (`check --wait`, `analyze`): 0 PASS, 3 FAIL, 4 INVALID.
inline int exit_code_of(Verdict verdict) {
  return verdict == Verdict::Pass ? kExitOk : verdict == Verdict::Fail ? kExitFail : kExitInvalid;
}

inline constexpr const char* kExitCodesHelp =
    "Exit codes: 0 ok/PASS, 1 error, 2 usage (an unknown flag, a bad value, a machine the plant "
    "does not configure), 3 FAIL, 4 INVALID (a check's data refused by the solver; config check: "
    "problems), 5 timed out, 6 not found, 7 corrupt database (db check, db recover, backup), "
    "8 kept for INCONCLUSIVE, 9 refused by a service (check, intervene, import).";

}  // namespace ncqual::cli
