// SPDX-License-Identifier: Apache-2.0
// export_csv: one CSV file per table from one read transaction (ncqual/storage/export.hpp).
#include "ncqual/storage/export.hpp"

#include "ncqual/storage/csv_fields.hpp"

#include "open.hpp"
#include "schema.hpp"
#include "sqlite.hpp"

#include "ncqual/common/model.hpp"
#include "ncqual/storage/database.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <unordered_set>

namespace ncqual::storage {
namespace {

using csv::append_int;
using csv::append_real;
using csv::append_text;
using csv::append_utc;

// One exported table: which rows, in which order. `from` names the table as `t` and, for the
// parts of a sample, joins its sample as `p`; `first`/`last` are the row's time (the same column
// for a row with one time; a span for machines and services), `machine` its machine.
// A table added to the schema gets one line here (and its section in docs/export.md).
struct TableSpec {
  const char* name;
  const char* from;
  const char* first;
  const char* last;
  const char* machine;
  const char* order;
};

// Through requests, measurement sets and results, a sample's parts follow it.
const std::array<TableSpec, 19> kTables{{
    {"machines", "machines AS t", "t.first_seen_ns", "t.last_seen_ns", "t.machine_id",
     "t.machine_id"},
    {"requests", "requests AS t", "t.time_ns", "t.time_ns", "t.machine_id",
     "t.time_ns, t.request_id"},
    {"request_parameters", "request_parameters AS t JOIN requests AS p USING (request_id)",
     "p.time_ns", "p.time_ns", "p.machine_id", "t.request_id, t.idx"},
    {"measurement_sets", "measurement_sets AS t", "t.time_ns", "t.time_ns", "t.machine_id",
     "t.time_ns, t.request_id"},
    {"measurement_parameters",
     "measurement_parameters AS t JOIN measurement_sets AS p USING (request_id)", "p.time_ns",
     "p.time_ns", "p.machine_id", "t.request_id, t.idx"},
    {"touches", "touches AS t JOIN measurement_sets AS p USING (request_id)", "p.time_ns",
     "p.time_ns", "p.machine_id", "t.request_id, t.idx"},
    {"tracker_points", "tracker_points AS t JOIN measurement_sets AS p USING (request_id)",
     "p.time_ns", "p.time_ns", "p.machine_id", "t.request_id, t.idx"},
    {"results", "results AS t", "t.time_ns", "t.time_ns", "t.machine_id",
     "t.time_ns, t.request_id"},
    {"metrics", "metrics AS t JOIN results AS p USING (request_id)", "p.time_ns", "p.time_ns",
     "p.machine_id", "t.request_id, t.idx"},
    {"causes", "causes AS t JOIN results AS p USING (request_id)", "p.time_ns", "p.time_ns",
     "p.machine_id", "t.request_id, t.rank"},
    {"result_offsets", "result_offsets AS t JOIN results AS p USING (request_id)", "p.time_ns",
     "p.time_ns", "p.machine_id", "t.request_id, t.idx"},
    {"checks", "checks AS t", "t.sort_ns", "t.sort_ns", "t.machine_id", "t.sort_ns, t.request_id"},
    {"status_changes", "status_changes AS t", "t.time_ns", "t.time_ns", "t.machine_id",
     "t.time_ns, t.id"},
    {"interventions", "interventions AS t", "t.time_ns", "t.time_ns", "t.machine_id",
     "t.time_ns, t.intervention_id"},
    {"compensations", "compensations AS t", "t.time_ns", "t.time_ns", "t.machine_id",
     "t.time_ns, t.id"},
    {"compensation_offsets",
     "compensation_offsets AS t JOIN compensations AS p ON p.id = t.compensation_id", "p.time_ns",
     "p.time_ns", "p.machine_id", "t.compensation_id, t.idx"},
    {"conflicts", "conflicts AS t", "t.received_ns", "t.received_ns", "t.machine_id",
     "t.received_ns, t.id"},
    {"services", "services AS t", "t.first_seen_ns", "t.last_seen_ns", "t.machine_id",
     "t.service, t.instance"},
    // A warning spans its start to its end (an active one: to now and on), so a range holds every
    // warning that was active in it, not only those that started in it.
    {"trend_warnings", "trend_warnings AS t", "t.started_ns",
     "coalesce(t.ended_ns, 9223372036854775807)", "t.machine_id",
     "t.started_ns, t.machine_id, t.metric, t.kind"},
}};

// ?1 since, ?2 until (a row's span meets [since, until)), ?3 the machines as a JSON array or NULL
// for all. Only the spec's identifiers go into the text; every value is bound.
std::string select_of(const TableSpec& spec) {
  return std::string("SELECT t.* FROM ") + spec.from + " WHERE " + spec.last + " >= ?1 AND " +
         spec.first + " < ?2 AND (?3 IS NULL OR " + spec.machine +
         " IN (SELECT value FROM json_each(?3))) ORDER BY " + spec.order;
}

// Columns whose 0 means "none" rather than the epoch: their _utc column stays empty then.
const std::unordered_set<std::string_view> kZeroIsNone{"oldest_unacknowledged_ns"};

bool ends_with(std::string_view text, std::string_view suffix) {
  return text.size() > suffix.size() && text.substr(text.size() - suffix.size()) == suffix;
}

// A column declared INTEGER (a CheckKind's number; trend_warnings.kind is a text).
bool is_integer_column(sqlite3_stmt* stmt, int column) {
  const char* type = sqlite3_column_decltype(stmt, column);
  return type != nullptr && std::string_view(type) == "INTEGER";
}

// What a column of the query becomes in the file: the value, then maybe a derived column.
struct Column {
  enum class Extra { None, Utc, KindName };
  std::string name;
  Extra extra = Extra::None;
  bool zero_is_none = false;
};

void append_hex(std::string& out, const unsigned char* data, int size) {
  constexpr std::string_view kDigits = "0123456789abcdef";
  for (int i = 0; i < size; ++i) {
    out += kDigits[data[i] >> 4];
    out += kDigits[data[i] & 0xf];
  }
}

// A file written through a buffer; every failure is an exception naming it.
class CsvFile {
 public:
  explicit CsvFile(std::string path) : path_(std::move(path)) {
    file_.reset(std::fopen(path_.c_str(), "wb"));
    if (!file_) fail("cannot create");
  }
  std::string& buffer() { return buffer_; }
  // Ends a row; writes the buffer out once it is large.
  void end_row() {
    buffer_ += "\r\n";
    if (buffer_.size() >= kFlushAt) flush();
  }
  std::int64_t close() {
    flush();
    if (std::fclose(file_.release()) != 0) fail("cannot write");
    return written_;
  }

 private:
  static constexpr std::size_t kFlushAt = 1 << 20;
  struct Closer {
    void operator()(std::FILE* f) const noexcept { std::fclose(f); }
  };
  void flush() {
    if (!buffer_.empty() &&
        std::fwrite(buffer_.data(), 1, buffer_.size(), file_.get()) != buffer_.size()) {
      fail("cannot write");
    }
    written_ += static_cast<std::int64_t>(buffer_.size());
    buffer_.clear();
  }
  [[noreturn]] void fail(const char* what) const {
    throw std::runtime_error(std::string(what) + " " + path_ + ": " + std::strerror(errno));
  }
  std::string path_;
  std::unique_ptr<std::FILE, Closer> file_;
  std::string buffer_;
  std::int64_t written_ = 0;
};

ExportedTable export_table(sqlite3* db, const TableSpec& spec, const ExportFilter& filter,
                           const std::string& dir) {
  const std::string sql = select_of(spec);
  const std::string name = std::string("export ") + spec.name;
  const sqlite::Sql named{name.c_str(), sql.c_str()};
  sqlite::Statement statement(db, named);
  sqlite::Query query(statement);
  std::optional<std::string> machines;
  if (!filter.machines.empty()) machines = nlohmann::json(filter.machines).dump();
  query.bind(filter.since_ns, filter.until_ns, machines);
  sqlite3_stmt* stmt = statement.get();

  ExportedTable table;
  table.table = spec.name;
  table.file = table.table + ".csv";
  const int count = sqlite3_column_count(stmt);
  std::vector<Column> columns;
  std::unordered_set<std::string> names;
  for (int i = 0; i < count; ++i) names.insert(sqlite3_column_name(stmt, i));
  for (int i = 0; i < count; ++i) {
    Column c{sqlite3_column_name(stmt, i)};
    table.columns.push_back(c.name);
    if (ends_with(c.name, "_ns")) {
      c.extra = Column::Extra::Utc;
      c.zero_is_none = kZeroIsNone.count(c.name) > 0;
      table.columns.push_back(c.name.substr(0, c.name.size() - 3) + "_utc");
    } else if ((c.name == "kind" || ends_with(c.name, "_kind")) && is_integer_column(stmt, i) &&
               names.count(c.name + "_name") == 0) {
      c.extra = Column::Extra::KindName;
      table.columns.push_back(c.name + "_name");
    }
    columns.push_back(std::move(c));
  }

  CsvFile file((std::filesystem::path(dir) / table.file).string());
  std::string& out = file.buffer();
  for (std::size_t i = 0; i < table.columns.size(); ++i) {
    if (i > 0) out += ',';
    append_text(out, table.columns[i]);
  }
  file.end_row();
  while (query.step()) {
    for (int i = 0; i < count; ++i) {
      if (i > 0) out += ',';
      const int type = sqlite3_column_type(stmt, i);
      switch (type) {
        case SQLITE_INTEGER: append_int(out, sqlite3_column_int64(stmt, i)); break;
        case SQLITE_FLOAT: append_real(out, sqlite3_column_double(stmt, i)); break;
        case SQLITE_TEXT:
          append_text(out,
                      std::string_view(reinterpret_cast<const char*>(sqlite3_column_text(stmt, i)),
                                       static_cast<std::size_t>(sqlite3_column_bytes(stmt, i))));
          break;
        case SQLITE_BLOB:
          append_hex(out, static_cast<const unsigned char*>(sqlite3_column_blob(stmt, i)),
                     sqlite3_column_bytes(stmt, i));
          break;
        default: break;  // NULL: an empty field
      }
      const Column& c = columns[static_cast<std::size_t>(i)];
      if (c.extra == Column::Extra::None) continue;
      out += ',';
      if (type != SQLITE_INTEGER) continue;
      const std::int64_t value = sqlite3_column_int64(stmt, i);
      if (c.extra == Column::Extra::Utc) {
        if (!(c.zero_is_none && value == 0)) append_utc(out, value);
      } else {
        append_text(out, to_string(static_cast<CheckKind>(value)));
      }
    }
    file.end_row();
    ++table.rows;
  }
  table.bytes = file.close();
  return table;
}

}  // namespace

std::vector<std::string> exported_tables() {
  std::vector<std::string> names;
  names.reserve(kTables.size());
  for (const TableSpec& spec : kTables) names.emplace_back(spec.name);
  return names;
}

ExportReport export_csv(const std::string& database, const ExportFilter& filter,
                        const std::string& dir) {
  const sqlite::Connection db = open_readonly_connection(database);
  ExportReport report;
  report.schema_version = schema::user_version(db.get());
  // One snapshot for every file: in WAL mode the historian commits on meanwhile, unseen here.
  sqlite::exec(db.get(), "begin the export's read transaction", "BEGIN");
  try {
    for (const TableSpec& spec : kTables) {
      report.tables.push_back(export_table(db.get(), spec, filter, dir));
    }
  } catch (...) {
    sqlite3_exec(db.get(), "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
  sqlite::exec(db.get(), "end the export's read transaction", "COMMIT");
  return report;
}

}  // namespace ncqual::storage
