// SPDX-License-Identifier: Apache-2.0
// The CSV reader of instrument exports: header and rows, comments, CRLF, quotes, and the
// file:line:column of every refusal.
#include "ncqual/common/csv.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace ncqual {
namespace {

// The what() of the CsvError that `f` throws, or "" when it throws none.
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const CsvError& e) {
    return e.what();
  }
  return "";
}

TEST(Csv, ReadsHeaderAndRowsWithTheirLineNumbers) {
  const std::string text =
      "# exported by some laser\n"
      "\n"
      " target_mm , cycle,direction ,measured_mm\n"
      "0,1,up,0.001\n"
      "   # a comment between rows\n"
      "100 , 1 , down , 100.002\n"
      "\t\n"
      "200,2,up,199.999";  // no final newline
  const CsvTable t = read_csv(text, "run.csv");
  EXPECT_EQ(t.file, "run.csv");
  EXPECT_EQ(t.header_line, 3);
  ASSERT_EQ(t.header.size(), 4u);
  EXPECT_EQ(t.header[0], "target_mm");
  EXPECT_EQ(t.header[2], "direction");
  ASSERT_EQ(t.rows.size(), 3u);
  EXPECT_EQ(t.rows[0].line, 4);
  EXPECT_EQ(t.rows[1].line, 6);
  EXPECT_EQ(t.rows[2].line, 8);
  EXPECT_EQ(t.rows[1].cells[0], "100");
  EXPECT_EQ(t.rows[1].cells[2], "down");
  EXPECT_DOUBLE_EQ(t.number(t.rows[1], 3), 100.002);
  EXPECT_EQ(t.integer(t.rows[2], 1), 2);
  EXPECT_EQ(t.find_column("measured_mm"), std::optional<std::size_t>(3));
  EXPECT_FALSE(t.find_column("Measured_mm"));  // case-sensitive
  EXPECT_EQ(t.require_column("cycle"), 1u);
}

TEST(Csv, AcceptsCrlfAndAByteOrderMark) {
  const CsvTable t = read_csv(
      "\xEF\xBB\xBF"
      "a,b\r\n1,2\r\n\r\n3,4\r\n",
      "w.csv");
  ASSERT_EQ(t.header.size(), 2u);
  EXPECT_EQ(t.header[0], "a");
  EXPECT_EQ(t.header[1], "b");
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[1].line, 4);
  EXPECT_EQ(t.rows[1].cells[1], "4");
  EXPECT_DOUBLE_EQ(t.number(t.rows[1], 1), 4.0);
}

TEST(Csv, UnquotesQuotedCells) {
  const CsvTable t = read_csv("point,note\n\"P1\", \"a, \"\"b\"\" \"\nP2,\"\"\n", "q.csv");
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0].cells[0], "P1");
  EXPECT_EQ(t.rows[0].cells[1], "a, \"b\" ");  // inside quotes nothing is trimmed
  EXPECT_EQ(t.rows[1].cells[1], "");
}

TEST(Csv, TrailingCommaMeansAnEmptyLastCell) {
  const CsvTable t = read_csv("a,b\n1,\n", "e.csv");
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.rows[0].cells[1], "");
  EXPECT_EQ(error_of([&] { t.number(t.rows[0], 1); }),
            "e.csv:2:2: column 'b' = '': expected a number, the cell is empty");
}

TEST(Csv, HeaderOnlyGivesNoRows) {
  const CsvTable t = read_csv("# c\nx_mm,y_mm\n", "h.csv");
  EXPECT_EQ(t.header_line, 2);
  EXPECT_TRUE(t.rows.empty());
}

TEST(Csv, NumbersAcceptSignsAndExponents) {
  const CsvTable t = read_csv("v\n+1.5\n-2e-3\n.25\n1E3\n", "n.csv");
  EXPECT_DOUBLE_EQ(t.number(t.rows[0], 0), 1.5);
  EXPECT_DOUBLE_EQ(t.number(t.rows[1], 0), -0.002);
  EXPECT_DOUBLE_EQ(t.number(t.rows[2], 0), 0.25);
  EXPECT_DOUBLE_EQ(t.number(t.rows[3], 0), 1000.0);
}

TEST(Csv, RefusesCellsThatAreNotFiniteNumbersQuotingThem) {
  const CsvTable t =
      read_csv("a,b\n1,abc\n1,nan\n1,inf\n1,-Infinity\n1,1.5mm\n1,1e999\n1,+-2\n1,0x10\n", "n.csv");
  EXPECT_EQ(error_of([&] { t.number(t.rows[0], 1); }),
            "n.csv:2:2: column 'b' = 'abc': expected a number");
  EXPECT_EQ(error_of([&] { t.number(t.rows[1], 1); }),
            "n.csv:3:2: column 'b' = 'nan': expected a finite number");
  EXPECT_EQ(error_of([&] { t.number(t.rows[2], 1); }),
            "n.csv:4:2: column 'b' = 'inf': expected a finite number");
  EXPECT_EQ(error_of([&] { t.number(t.rows[3], 1); }),
            "n.csv:5:2: column 'b' = '-Infinity': expected a finite number");
  EXPECT_EQ(error_of([&] { t.number(t.rows[4], 1); }),
            "n.csv:6:2: column 'b' = '1.5mm': expected a number");
  EXPECT_EQ(error_of([&] { t.number(t.rows[5], 1); }),
            "n.csv:7:2: column 'b' = '1e999': out of the range of a double");
  EXPECT_EQ(error_of([&] { t.number(t.rows[6], 1); }),
            "n.csv:8:2: column 'b' = '+-2': expected a number");
  EXPECT_EQ(error_of([&] { t.number(t.rows[7], 1); }),
            "n.csv:9:2: column 'b' = '0x10': expected a number");
}

TEST(Csv, IntegersRefuseFractionsAndText) {
  const CsvTable t = read_csv("cycle\n+3\n-2\n3.0\nfive\n99999999999\n", "i.csv");
  EXPECT_EQ(t.integer(t.rows[0], 0), 3);
  EXPECT_EQ(t.integer(t.rows[1], 0), -2);
  EXPECT_EQ(error_of([&] { t.integer(t.rows[2], 0); }),
            "i.csv:4:1: column 'cycle' = '3.0': expected an integer");
  EXPECT_EQ(error_of([&] { t.integer(t.rows[3], 0); }),
            "i.csv:5:1: column 'cycle' = 'five': expected an integer");
  EXPECT_EQ(error_of([&] { t.integer(t.rows[4], 0); }),
            "i.csv:6:1: column 'cycle' = '99999999999': out of the range of an int");
}

TEST(Csv, WordsAreMatchedWithoutCaseAndReturnedAsListed) {
  const CsvTable t = read_csv("n,direction\n1,Up\n2,DOWN\n3,sideways\n", "w.csv");
  EXPECT_EQ(t.word(t.rows[0], 1, {"up", "down"}), "up");
  EXPECT_EQ(t.word(t.rows[1], 1, {"up", "down"}), "down");
  EXPECT_EQ(error_of([&] {
              t.word(t.rows[2], 1, {"up", "down"});
            }),
            "w.csv:4:2: column 'direction' = 'sideways': expected one of up, down");
}

TEST(Csv, MissingRequiredColumnNamesItAndListsTheHeader) {
  const CsvTable t = read_csv("# x\ntarget_mm,cycle\n1,2\n", "m.csv");
  EXPECT_EQ(error_of([&] { t.require_column("measured_mm"); }),
            "m.csv:2: missing column 'measured_mm'; the header has: target_mm, cycle");
}

TEST(Csv, RefusesRowsWithTheWrongNumberOfCells) {
  EXPECT_EQ(error_of([] { read_csv("a,b,c\n1,2,3\n1,2\n", "c.csv"); }),
            "c.csv:3:3: 2 cells, but the header (line 1) has 3 columns: a, b, c");
  EXPECT_EQ(error_of([] { read_csv("a,b\n\n1,2,3\n", "c.csv"); }),
            "c.csv:3:3: 3 cells, but the header (line 1) has 2 columns: a, b");
}

TEST(Csv, RefusesBadHeaders) {
  EXPECT_EQ(error_of([] { read_csv("a,,c\n", "h.csv"); }),
            "h.csv:1:2: empty column name in the header");
  EXPECT_EQ(error_of([] { read_csv("\n a , b, a\n", "h.csv"); }),
            "h.csv:2:3: column name 'a' repeats column 1");
  EXPECT_EQ(error_of([] { read_csv("", "h.csv"); }),
            "h.csv: the file is empty; expected a header line");
  EXPECT_EQ(error_of([] { read_csv("# only\n\n", "h.csv"); }),
            "h.csv: no header line (only blank and # comment lines)");
}

TEST(Csv, RefusesBrokenQuotes) {
  EXPECT_EQ(error_of([] { read_csv("a,b\n1,\"open\n", "q.csv"); }),
            "q.csv:2:2: unterminated quote (a quoted cell must end on its line)");
  EXPECT_EQ(error_of([] { read_csv("a,b\n\"x\"y,2\n", "q.csv"); }),
            "q.csv:2:1: text after the closing quote: 'y,2'");
}

TEST(Csv, CsvErrorKeepsItsParts) {
  const CsvError e("f.csv", 7, 3, "bad");
  EXPECT_STREQ(e.what(), "f.csv:7:3: bad");
  EXPECT_EQ(e.file(), "f.csv");
  EXPECT_EQ(e.line(), 7);
  EXPECT_EQ(e.column(), 3);
  EXPECT_EQ(e.message(), "bad");
  EXPECT_STREQ(CsvError("f.csv", 7, 0, "row").what(), "f.csv:7: row");
  EXPECT_STREQ(CsvError("f.csv", 0, 0, "file").what(), "f.csv: file");
}

TEST(Csv, ReadsFilesAndNamesAnUnreadablePath) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("ncqual-csv-test-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "ok.csv").string();
  std::ofstream(path) << "a,b\n1,2\n";
  const CsvTable t = read_csv_file(path);
  EXPECT_EQ(t.file, path);
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.rows[0].cells[1], "2");

  const std::string missing = (dir / "missing.csv").string();
  EXPECT_EQ(error_of([&] { read_csv_file(missing); }),
            missing + ": cannot read: No such file or directory");
  EXPECT_EQ(error_of([&] { read_csv_file(dir.string()); }),
            dir.string() + ": cannot read: is a directory");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ncqual
