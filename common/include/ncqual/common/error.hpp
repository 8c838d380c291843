// SPDX-License-Identifier: Apache-2.0
// The one error convention of ncqual's libraries (docs/architecture.md, "Errors"):
//
//   1. Input from outside that cannot be used (a config file, an instrument file, a database or
//      a DDS entity that cannot be had): an exception derived from ncqual::Error, whose what()
//      names where (file:line:column, or file: key = value) and why. Each executable catches
//      ncqual::Error at one boundary (its main, or the handler of one received sample), reports
//      it and goes on or exits with the code `ncqual --help` documents.
//   2. Measurement data a check cannot judge: not an exception but a result. The solver returns
//      an INVALID CheckResult whose reason names the field and the value; it is stored like any
//      verdict. Its find_*_problem functions say the same before an evaluation is attempted.
//   3. A broken precondition of a pure function (a caller's bug: a documented find_*_problem
//      skipped, a kind the function does not take): std::invalid_argument or std::logic_error.
//      These are never caught to be hidden; they end the request or the test that caused them.
//
// No error codes or empty results stand for failures, and nothing is refused without naming
// the field and the value.
#pragma once

#include <stdexcept>
#include <string>

namespace ncqual {

// Base of the errors of class 1 above: ConfigError, CsvError, storage::StorageError,
// dds::DdsError.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ncqual
