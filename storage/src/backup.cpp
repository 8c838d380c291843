// SPDX-License-Identifier: Apache-2.0
// backup: SQLite's online backup API from one read transaction of the running historian's file
// into a temporary file, checked, then renamed (ncqual/storage/export.hpp).
#include "ncqual/storage/export.hpp"

#include "open.hpp"
#include "schema.hpp"
#include "sqlite.hpp"

#include "ncqual/storage/database.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

namespace ncqual::storage {
namespace {

namespace fs = std::filesystem;

std::string errno_text() { return std::strerror(errno); }

// A new empty file beside `file` (".<name>.backup-XXXXXX"), removed with its journal files unless
// kept.
class TemporaryFile {
 public:
  explicit TemporaryFile(const fs::path& file) {
    const fs::path dir = file.parent_path().empty() ? fs::path(".") : file.parent_path();
    std::string pattern = (dir / ("." + file.filename().string() + ".backup-XXXXXX")).string();
    const int fd = ::mkostemp(pattern.data(), O_CLOEXEC);
    if (fd < 0) {
      throw StorageError("backup to '" + file.string() + "': cannot create a file in '" +
                         dir.string() + "': " + errno_text());
    }
    ::close(fd);
    path_ = pattern;
  }
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  ~TemporaryFile() {
    if (kept_) return;
    for (const char* suffix : {"", "-journal", "-wal", "-shm"}) ::unlink((path_ + suffix).c_str());
  }
  const std::string& path() const { return path_; }
  void keep() { kept_ = true; }

 private:
  std::string path_;
  bool kept_ = false;
};

struct BackupFinisher {
  void operator()(sqlite3_backup* backup) const noexcept { sqlite3_backup_finish(backup); }
};

// fsync of a file or folder by name: the copy's bytes, then its new name, survive a power cut.
void sync_path(const std::string& path, int flags, const std::string& what) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0 || ::fsync(fd) != 0) {
    const std::string why = errno_text();
    if (fd >= 0) ::close(fd);
    throw StorageError(what + ": cannot sync '" + path + "': " + why);
  }
  ::close(fd);
}

// The report of PRAGMA integrity_check or quick_check: "ok", or the problems one per line.
std::string check_copy(sqlite3* db, bool quick) {
  const sqlite::Sql sql{quick ? "quick check of the copy" : "integrity check of the copy",
                        quick ? "PRAGMA quick_check" : "PRAGMA integrity_check"};
  sqlite::Statement statement(db, sql);
  std::string report;
  for (;;) {
    const int rc = sqlite3_step(statement.get());
    if (rc == SQLITE_DONE) break;
    if (rc != SQLITE_ROW) return sqlite3_errmsg(db);
    const auto* text = sqlite3_column_text(statement.get(), 0);
    if (!report.empty()) report += '\n';
    report += text ? reinterpret_cast<const char*>(text) : "";
  }
  return report;
}

}  // namespace

BackupReport backup(const std::string& database, const std::string& file,
                    const BackupOptions& options) {
  const std::string what = "backup of '" + database + "' to '" + file + "'";
  const auto started = std::chrono::steady_clock::now();
  const sqlite::Connection source = open_readonly_connection(database);
  std::error_code error;
  if (!options.overwrite && fs::exists(fs::symlink_status(file, error))) {
    throw StorageError(what + ": '" + file + "' exists; it is not overwritten");
  }
  BackupReport report;
  report.schema_version = schema::user_version(source.get());

  TemporaryFile copy(file);
  {
    sqlite::Connection target =
        sqlite::open_connection(copy.path(), SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
    // The source's snapshot for the whole copy: in WAL mode its writers go on (their commits are
    // not in the copy), and the copy never starts over because one of them committed.
    sqlite::exec(source.get(), what, "BEGIN");
    sqlite::query_text(source.get(), what, "SELECT count(*) FROM sqlite_schema");
    {
      const std::unique_ptr<sqlite3_backup, BackupFinisher> step(
          sqlite3_backup_init(target.get(), "main", source.get(), "main"));
      if (!step) sqlite::throw_error(target.get(), what);
      for (;;) {
        const int rc = sqlite3_backup_step(step.get(), std::max(1, options.pages_per_step));
        ++report.steps;
        if (rc == SQLITE_DONE) break;
        if (rc != SQLITE_OK && rc != SQLITE_BUSY && rc != SQLITE_LOCKED) {
          sqlite::throw_error(target.get(), what);
        }
        if (options.pause.count() > 0) std::this_thread::sleep_for(options.pause);
      }
      report.pages = sqlite3_backup_pagecount(step.get());
    }
    sqlite::exec(source.get(), what, "COMMIT");
    report.page_size = std::stoll(sqlite::query_text(target.get(), what, "PRAGMA page_size"));
    report.check = check_copy(target.get(), options.quick_check);
  }  // closed: a WAL of the copy is checkpointed into it and removed
  for (const char* suffix : {"-wal", "-journal"}) {
    if (fs::exists(copy.path() + suffix)) {
      throw StorageError(what + ": the copy left " + copy.path() + suffix + " behind");
    }
  }
  report.bytes = static_cast<std::int64_t>(fs::file_size(copy.path()));
  if (report.check == "ok") {
    // The copy is as readable as the historian's file (mkostemp made it 0600).
    fs::permissions(copy.path(), fs::status(database).permissions(), error);
    sync_path(copy.path(), O_RDONLY, what);
    if (options.overwrite) {
      if (std::rename(copy.path().c_str(), file.c_str()) != 0) {
        throw StorageError(what + ": cannot rename the copy: " + errno_text());
      }
    } else {
      // link() never replaces: a file that appeared under the name meanwhile is kept.
      if (::link(copy.path().c_str(), file.c_str()) != 0) {
        throw StorageError(what + ": cannot name the copy '" + file + "': " + errno_text());
      }
      ::unlink(copy.path().c_str());
    }
    copy.keep();
    const fs::path dir = fs::path(file).parent_path();
    sync_path(dir.empty() ? "." : dir.string(), O_RDONLY | O_DIRECTORY, what);
    report.written = true;
  }
  report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return report;
}

}  // namespace ncqual::storage
