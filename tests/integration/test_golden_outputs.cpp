// SPDX-License-Identifier: Apache-2.0
// The printed outputs of `analyze`, `budget` and `uncertainty`, byte for byte (but for the last
// digit of a double printed whole: same_to_rounding), against the files under tests/data/golden/.
// These pin the text a user and their scripts read while the code behind them is restructured: a
// change of a figure or of the layout shows up here as a diff. The figures themselves are checked
// against hand-worked and independent values by the other CLI tests and the solver's unit tests;
// the golden files only say "unchanged".
//
// A deliberate change of an output: run the test with NCQUAL_UPDATE_GOLDEN=1, read the diff of
// tests/data/golden/ and commit it with the change that explains it.
#include "cli_runner.hpp"

#include "ncqual/storage/database.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#ifndef NCQUAL_SOURCE_DIR
#error "NCQUAL_SOURCE_DIR must be defined by the test target"
#endif

namespace ncqual {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = NCQUAL_SOURCE_DIR;
const fs::path kGolden = kSource / "tests/data/golden";

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Replaces every occurrence of `from` in `text` with `to`.
std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos;
       at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

// Runs `ncqual <args>` in the source directory (so relative paths in the output are the same on
// every machine), stdout and stderr as written and the exit code; absolute paths of the source
// and of `scratch` are written as $SRC and $TMP.
std::string run_in_source(std::vector<std::string> args, const fs::path& scratch) {
  args.insert(args.begin(), NCQUAL_CLI_EXE);
  const testing::Outcome r =
      testing::run(testing::Launch(args, testing::Output::Merged).in(kSource.string()));
  std::string out = r.out + "[exit " + std::to_string(r.exit_code) + "]\n";
  out = replace_all(out, scratch.string(), "$TMP");
  return replace_all(out, kSource.string(), "$SRC");
}

// `text` cut into the runs between numbers and the numbers themselves.
struct Cut {
  std::vector<std::string> words;
  std::vector<double> numbers;
};
Cut cut_numbers(const std::string& text) {
  static const std::regex number(R"(-?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?)");
  Cut c;
  std::size_t from = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), number);
       it != std::sregex_iterator(); ++it) {
    c.words.push_back(text.substr(from, static_cast<std::size_t>(it->position()) - from));
    c.numbers.push_back(std::strtod(it->str().c_str(), nullptr));
    from = static_cast<std::size_t>(it->position() + it->length());
  }
  c.words.push_back(text.substr(from));
  return c;
}

// The same text with the same numbers, but for the last of 17 significant digits: the JSON
// documents print doubles whole, and glibc's libm picks its code for sin, atan, exp, ... by the
// CPU (with or without FMA), which moves a result by an ulp or two from one machine to another.
// A figure that moved by more than 1e-12 of itself is a change.
bool same_to_rounding(const std::string& actual, const std::string& expected) {
  const Cut a = cut_numbers(actual), e = cut_numbers(expected);
  if (a.words != e.words || a.numbers.size() != e.numbers.size()) return false;
  for (std::size_t k = 0; k < a.numbers.size(); ++k) {
    if (std::abs(a.numbers[k] - e.numbers[k]) > 1e-12 * std::abs(e.numbers[k])) return false;
  }
  return true;
}

void expect_golden(const std::string& name, const std::string& actual) {
  const fs::path file = kGolden / name;
  if (std::getenv("NCQUAL_UPDATE_GOLDEN")) {
    fs::create_directories(kGolden);
    std::ofstream(file, std::ios::binary) << actual;
    std::printf("rewrote %s\n", file.c_str());
    return;
  }
  ASSERT_TRUE(fs::exists(file)) << file << " is missing; run with NCQUAL_UPDATE_GOLDEN=1";
  const std::string expected = read_file(file);
  if (same_to_rounding(actual, expected)) return;
  EXPECT_EQ(actual, expected) << "the output differs from " << file
                              << " (NCQUAL_UPDATE_GOLDEN=1 rewrites it after a deliberate change)";
}

class Golden : public ::testing::Test {
 protected:
  testing_cli::TempDir tmp_{"ncqual-golden"};
};

constexpr const char* kIso = "tests/data/instrument/iso230-2_x.csv";
constexpr const char* kCircle = "tests/data/instrument/circle_xy.csv";
const std::vector<std::string> kGrid = {"--x-run", "tests/data/instrument/grid_x_run.csv",
                                        "--y-run", "tests/data/instrument/grid_y_run.csv",
                                        "--grid",  "tests/data/instrument/grid.csv"};

// `args` with `--json` after them.
std::vector<std::string> with_json(std::vector<std::string> args) {
  args.push_back("--json");
  return args;
}

TEST_F(Golden, AnalyzeIso230_2) {
  const std::vector<std::string> args = {"analyze", "iso230-2", kIso};
  expect_golden("analyze-iso230-2.txt", run_in_source(args, tmp_.path()));
  expect_golden("analyze-iso230-2.json", run_in_source(with_json(args), tmp_.path()));
}

TEST_F(Golden, AnalyzeCircle) {
  const std::vector<std::string> args = {"analyze", "circle", kCircle, "--nominal-radius-mm",
                                         "150"};
  expect_golden("analyze-circle.txt", run_in_source(args, tmp_.path()));
  expect_golden("analyze-circle.json", run_in_source(with_json(args), tmp_.path()));
}

TEST_F(Golden, AnalyzeGrid) {
  std::vector<std::string> args = {"analyze", "grid"};
  args.insert(args.end(), kGrid.begin(), kGrid.end());
  expect_golden("analyze-grid.txt", run_in_source(args, tmp_.path()));
  expect_golden("analyze-grid.json", run_in_source(with_json(args), tmp_.path()));
}

// The example machine's budget against a historian holding a few daily checks of pm1.
TEST_F(Golden, BudgetOfTheExampleMachine) {
  const std::string db = (tmp_.path() / "historian.db").string();
  {
    auto database = storage::Database::open(db);
    const std::int64_t t0 = 1'800'000'000'000'000'000;
    const double dy[] = {0.004, -0.003, 0.006, 0.001, 0.002, 0.012};
    for (int i = 0; i < 6; ++i) {
      CheckResult r;
      r.machine_id = "pm1";
      r.request_id = "pos-" + std::to_string(i);
      r.kind = CheckKind::MonumentPositioning;
      r.verdict = Verdict::Pass;
      r.time_ns = t0 + i * 1'000'000'000LL;
      r.metrics = {{"center_dx_mm", 0.001 * i, "mm", -0.025, 0.025, true},
                   {"center_dy_mm", dy[i], "mm", -0.025, 0.025, true},
                   {"face_dz_mm", 0.01 - 0.001 * i, "mm", -0.025, 0.025, true}};
      database.store(r);
    }
  }
  const std::vector<std::string> args = {
      "budget", "--machine", "pm1", "--plant", "deploy/plant.yaml", "--db", db};
  expect_golden("budget-pm1.txt", run_in_source(args, tmp_.path()));
  expect_golden("budget-pm1.json", run_in_source(with_json(args), tmp_.path()));
}

TEST_F(Golden, UncertaintyOfACoarseGrid) {
  const std::vector<std::string> args = {"uncertainty",
                                         "--machine",
                                         "small1",
                                         "--plant",
                                         "tests/data/plants/small/plant.yaml",
                                         "--trials",
                                         "40",
                                         "--seed",
                                         "7",
                                         "--threads",
                                         "1"};
  expect_golden("uncertainty-small1.txt", run_in_source(args, tmp_.path()));
  expect_golden("uncertainty-small1.json", run_in_source(with_json(args), tmp_.path()));
}

}  // namespace
}  // namespace ncqual
