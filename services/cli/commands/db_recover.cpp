// SPDX-License-Identifier: Apache-2.0
// `ncqual db recover`: what can be read of a damaged historian database, salvaged into a new file
// through two sqlite3 shells run without a shell between (the child processes are here too).
#include "db.hpp"

#include "ncqual/common/text.hpp"
#include "ncqual/storage/database.hpp"

#include <fmt/format.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

extern char** environ;

namespace ncqual::cli::database {
namespace {

namespace fs = std::filesystem;

// The historian's tables, the ones every schema version has and `db recover` counts.
constexpr std::array<const char*, 6> kMainTables = {
    "requests", "measurement_sets", "results", "status_changes", "interventions", "compensations"};
constexpr const char* kDumpErrorsLine = "ROLLBACK; -- due to errors";

// ---- Child processes, without a shell ----------------------------------------------------------

// A file descriptor, closed when it goes.
class Fd {
 public:
  Fd() = default;
  explicit Fd(int fd) : fd_(fd) {}
  Fd(Fd&& other) noexcept : fd_(other.release()) {}
  Fd& operator=(Fd&& other) noexcept {
    reset(other.release());
    return *this;
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() { reset(); }
  int get() const { return fd_; }
  int release() { return std::exchange(fd_, -1); }
  void reset(int fd = -1) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = fd;
  }

 private:
  int fd_ = -1;
};

std::string errno_text(int error) { return std::strerror(error); }

// A pipe whose ends are closed on exec: a child gets an end only through dup2.
std::pair<Fd, Fd> make_pipe() {
  std::array<int, 2> ends{};
  if (::pipe2(ends.data(), O_CLOEXEC) != 0) {
    throw std::runtime_error("cannot create a pipe: " + errno_text(errno));
  }
  return {Fd(ends[0]), Fd(ends[1])};
}

// A new, unlinked file in `dir` for what a child prints, read back once the child has ended.
Fd capture_file(const fs::path& dir) {
  std::string pattern = (dir / "output-XXXXXX").string();
  const int fd = ::mkostemp(pattern.data(), O_CLOEXEC);
  if (fd < 0) {
    throw std::runtime_error("cannot create a file in " + dir.string() + ": " + errno_text(errno));
  }
  ::unlink(pattern.c_str());
  return Fd(fd);
}

std::string read_all(int fd) {
  std::string text;
  if (::lseek(fd, 0, SEEK_SET) < 0) return text;
  std::array<char, 65536> buffer{};
  for (;;) {
    const ssize_t n = ::read(fd, buffer.data(), buffer.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    text.append(buffer.data(), static_cast<std::size_t>(n));
  }
  return text;
}

// Starts argv (argv[0] looked up in PATH) with stdin from `in` (-1: /dev/null), stdout to `out`
// and stderr to `err`, with the default action for SIGPIPE (this process ignores it while it
// feeds a pipe). Returns the child's pid.
pid_t spawn(const std::vector<std::string>& argv, int in, int out, int err) {
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  if (in >= 0) {
    posix_spawn_file_actions_adddup2(&files, in, 0);
  } else {
    posix_spawn_file_actions_addopen(&files, 0, "/dev/null", O_RDONLY, 0);
  }
  posix_spawn_file_actions_adddup2(&files, out, 1);
  posix_spawn_file_actions_adddup2(&files, err, 2);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t defaults;
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGPIPE);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF);
  std::vector<std::string> args = argv;
  std::vector<char*> pointers;
  pointers.reserve(args.size() + 1);
  for (auto& a : args) pointers.push_back(a.data());
  pointers.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, args[0].c_str(), &files, &attributes, pointers.data(), environ);
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&files);
  if (rc != 0) throw std::runtime_error("cannot start " + argv[0] + ": " + errno_text(rc));
  return pid;
}

// The child's exit code; 128 + the signal when a signal ended it.
int wait_for(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
}

struct Outcome {
  int exit_code = -1;
  std::string out, err;
};

// Runs argv to its end with nothing on stdin; what it printed, captured in files under `dir`.
Outcome run_to_end(const std::vector<std::string>& argv, const fs::path& dir) {
  Fd out = capture_file(dir);
  Fd err = capture_file(dir);
  Outcome outcome;
  outcome.exit_code = wait_for(spawn(argv, -1, out.get(), err.get()));
  outcome.out = read_all(out.get());
  outcome.err = read_all(err.get());
  return outcome;
}

// The program `name` in PATH, or "" when there is none.
std::string find_in_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path && *path ? path : "/usr/local/bin:/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / name;
    std::error_code error;
    if (fs::is_regular_file(candidate, error) && ::access(candidate.c_str(), X_OK) == 0) {
      return candidate.string();
    }
  }
  return "";
}

// A new folder in the folder of `beside`, removed with everything in it when the object goes.
class TemporaryFolder {
 public:
  explicit TemporaryFolder(const fs::path& beside) {
    const fs::path parent = beside.parent_path().empty() ? fs::path(".") : beside.parent_path();
    std::string pattern = (parent / ".ncqual-recover-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) {
      throw std::runtime_error("cannot create a temporary folder in " + parent.string() + ": " +
                               errno_text(errno));
    }
    path_ = pattern;
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  ~TemporaryFolder() {
    std::error_code error;
    fs::remove_all(path_, error);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// ---- db recover --------------------------------------------------------------------------------

struct RecoverOptions {
  std::string from, to;
};

// Writes all of `text` to `fd`; false when the reader has gone (EPIPE) or another error.
bool write_all(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t count = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) {
    ++count;
  }
  return count;
}

// What the SQL of the recovering shell said, as it went by.
struct Stream {
  bool began = false;        // it opened a transaction
  bool committed = false;    // its last line commits it (after the rewrite below)
  bool rewritten = false;    // .dump's closing ROLLBACK (it met errors) was made a COMMIT
  std::size_t errors = 0;    // the errors .dump wrote into its output (corrupt pages, ...)
  bool loader_gone = false;  // the sqlite3 writing TO stopped reading
};

void note(Stream& stream, const std::string& lines) {
  stream.errors +=
      occurrences(lines, "/****** CORRUPTION ERROR") + occurrences(lines, "/**** ERROR");
  if (lines.rfind("BEGIN", 0) == 0 || lines.find("\nBEGIN") != std::string::npos) {
    stream.began = true;
  }
}

// Copies the SQL from `in` to `out`, holding back its last line: .dump ends with "ROLLBACK; --
// due to errors" when it met a damaged page, which would throw away everything it did read; that
// line becomes a COMMIT. A transaction the SQL left open (the shell died) is committed too.
Stream pass_sql(int in, int out) {
  Stream stream;
  std::string pending;
  std::array<char, 65536> buffer{};
  for (;;) {
    const ssize_t n = ::read(in, buffer.data(), buffer.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    pending.append(buffer.data(), static_cast<std::size_t>(n));
    // Everything before the last complete line goes on.
    const std::size_t last = pending.rfind('\n');
    if (last == std::string::npos || last == 0) continue;
    const std::size_t before = pending.rfind('\n', last - 1);
    if (before == std::string::npos) continue;
    const std::string lines = pending.substr(0, before + 1);
    note(stream, lines);
    if (!stream.loader_gone && !write_all(out, lines)) stream.loader_gone = true;
    pending.erase(0, before + 1);
  }
  note(stream, pending);
  while (!pending.empty() && (pending.back() == '\n' || pending.back() == '\r')) pending.pop_back();
  const std::size_t start = pending.rfind('\n');
  const std::string last_line = pending.substr(start == std::string::npos ? 0 : start + 1);
  if (last_line == kDumpErrorsLine) {
    pending.replace(pending.size() - last_line.size(), last_line.size(), "COMMIT;");
    stream.rewritten = true;
  }
  stream.committed = stream.rewritten || last_line == "COMMIT;";
  if (!pending.empty()) pending += '\n';
  if (stream.began && !stream.committed) pending += "COMMIT;\n";
  if (!stream.loader_gone && !write_all(out, pending)) stream.loader_gone = true;
  return stream;
}

// The first lines of `text`, indented, at most `count`.
std::string first_lines(const std::string& text, std::size_t count) {
  std::istringstream lines(text);
  std::string out;
  std::size_t shown = 0;
  for (std::string line; shown < count && std::getline(lines, line);) {
    if (line.empty()) continue;
    out += "    " + line + "\n";
    ++shown;
  }
  return out;
}

// The non-empty lines of `text`.
std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines = split_at(text, '\n');
  lines.erase(std::remove(lines.begin(), lines.end(), ""), lines.end());
  return lines;
}

// What TO holds (rows per table, through the shell: TO may be of an older schema version) and
// whether it is a historian database that passes the full integrity check; the exit code.
int report_recovered(const std::string& shell, const std::string& from, const std::string& to,
                     const FileHeader& header, const fs::path& tmp) {
  const auto query = [&](const std::string& sql) {
    return run_to_end({shell, "-batch", "-readonly", "-noheader", "-list", to, sql}, tmp);
  };
  const std::vector<std::string> names =
      split_lines(query("SELECT name FROM sqlite_schema WHERE type = 'table' ORDER BY name").out);
  std::vector<std::string> counted, missing, lost;
  for (const char* t : kMainTables) {
    (std::find(names.begin(), names.end(), t) != names.end() ? counted : missing).emplace_back(t);
  }
  for (const auto& name : names) {
    if (name.rfind("lost_and_found", 0) == 0) lost.push_back(name);
  }
  counted.insert(counted.end(), lost.begin(), lost.end());
  std::string sql;
  for (const auto& t : counted) {
    sql += (sql.empty() ? "" : " UNION ALL ") + ("SELECT '" + t + "', count(*) FROM \"" + t + "\"");
  }
  if (!sql.empty()) {
    const Outcome counts = query(sql);
    std::cout << "  rows recovered:\n";
    for (const auto& line : split_lines(counts.out)) {
      const auto bar = line.find('|');
      if (bar != std::string::npos) {
        std::cout << fmt::format("    {:<18}{}\n", line.substr(0, bar), line.substr(bar + 1));
      }
    }
    std::cout << first_lines(counts.err, 3);
  }
  if (lost.empty()) std::cout << "  no lost_and_found table: no orphaned rows were kept\n";
  const Outcome orphans = query("SELECT count(*) FROM pragma_foreign_key_check");
  const auto orphan_count = split_lines(orphans.out);
  if (orphans.exit_code == 0 && !orphan_count.empty() && orphan_count.front() != "0") {
    std::cout << "  " << orphan_count.front()
              << " rows refer to a row that was not recovered (PRAGMA foreign_key_check), e.g. "
                 "the metrics of a lost result\n";
  }
  if (!missing.empty()) {
    std::string list;
    for (const auto& t : missing) list += (list.empty() ? "" : ", ") + t;
    std::cerr << "ncqual db recover: " << to << " lacks the table(s) " << list
              << ": the historian's schema was not recovered from " << from;
    if (missing.size() == kMainTables.size()) {  // it holds nothing of the historian's
      std::error_code error;
      fs::remove(to, error);
      std::cerr << " (" << to << " removed)";
    }
    std::cerr << "\n";
    return kExitError;
  }

  const int latest = storage::Database::latest_schema_version();
  const FileHeader recovered = read_header(to);
  std::string integrity;
  try {
    auto db = storage::Database::open_readonly(to);
    integrity = db.integrity_check();
  } catch (const storage::StorageError& e) {
    const bool other_version = header.sqlite && recovered.application_id == header.application_id &&
                               recovered.user_version > 0 && recovered.user_version != latest;
    if (!other_version) {
      std::cerr << "ncqual db recover: " << to << " is not a historian database: " << e.what()
                << "\n";
      return kExitError;
    }
    const Outcome check = query("PRAGMA integrity_check");
    integrity = check.exit_code == 0 ? check.out : check.err;
    while (!integrity.empty() && integrity.back() == '\n') integrity.pop_back();
    std::cout << "  " << to << " has schema version " << recovered.user_version
              << ", this build's is " << latest
              << (recovered.user_version < latest
                      ? ": the historian of this build migrates it when it starts on it"
                      : ": it was written by a newer ncqual; upgrade ncqual to use it")
              << "\n";
  }
  if (integrity != "ok") {
    std::cout << to << ": CORRUPT (PRAGMA integrity_check)\n"
              << first_lines(integrity, kShownProblems);
    return kExitCorrupt;
  }
  std::cout << to << ": ok (PRAGMA integrity_check)\n"
            << "next: start the historian with --db " << to << ", or move " << to << " to " << from
            << " after keeping " << from << " elsewhere\n";
  return kExitOk;
}

// What the two shells did.
struct Recovery {
  Stream stream;
  int dump_exit = -1, load_exit = -1;
  std::string dump_messages, load_messages;
};

// sqlite3 COPY .recover|.dump  ->  this process (pass_sql)  ->  sqlite3 TO, then the header's
// application_id and user_version.
Recovery pipe_into(const std::string& shell, const std::string& method, const fs::path& copy,
                   const std::string& to, const FileHeader& header, const fs::path& tmp) {
  Fd dump_err = capture_file(tmp);
  Fd load_out = capture_file(tmp);
  auto [sql_in, sql_out] = make_pipe();
  auto [load_in, load_feed] = make_pipe();
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  struct sigaction previous {};
  ::sigaction(SIGPIPE, &ignore, &previous);  // a loader that died is an EPIPE, not our death
  Recovery r;
  const pid_t dumper =
      spawn({shell, "-batch", copy.string(), method}, -1, sql_out.get(), dump_err.get());
  sql_out.reset();
  const pid_t loader = spawn({shell, "-batch", to}, load_in.get(), load_out.get(), load_out.get());
  load_in.reset();
  r.stream = pass_sql(sql_in.get(), load_feed.get());
  sql_in.reset();
  if (header.sqlite && !r.stream.loader_gone) {
    write_all(load_feed.get(),
              "PRAGMA application_id = " + std::to_string(header.application_id) +
                  ";\nPRAGMA user_version = " + std::to_string(header.user_version) + ";\n");
  }
  load_feed.reset();
  r.dump_exit = wait_for(dumper);
  r.load_exit = wait_for(loader);
  ::sigaction(SIGPIPE, &previous, nullptr);
  r.dump_messages = read_all(dump_err.get());
  r.load_messages = read_all(load_out.get());
  return r;
}

int run_recover(const RecoverOptions& o) {
  const std::string& from = o.from;
  const std::string& to = o.to;
  if (!fs::exists(from)) {
    std::cerr << "ncqual db recover: no historian database at " << from << "\n";
    return kExitNotFound;
  }
  std::error_code error;
  if (fs::exists(fs::symlink_status(to, error))) {
    std::cerr << "ncqual db recover: " << to
              << " exists; it is never overwritten: name a new file\n";
    return kExitError;
  }
  const std::string shell = find_in_path("sqlite3");
  if (shell.empty()) {
    throw std::runtime_error(
        "the sqlite3 command-line shell is not in PATH; install the Debian package sqlite3 "
        "(deploy/install-deps.sh does)");
  }
  const FileHeader header = read_header(from);
  if (!header.sqlite) {
    std::cout << "warning: " << from
              << " has no SQLite header: its application_id and user_version are lost\n";
  }
  if (!fs::path(to).parent_path().empty()) fs::create_directories(fs::path(to).parent_path());

  // FROM is never written: the shells read a copy (the WAL holds the newest commits, a hot
  // journal the undo of an interrupted one).
  const TemporaryFolder tmp(to);
  const fs::path copy = tmp.path() / "from.db";
  fs::copy_file(from, copy);
  for (const char* suffix : {"-wal", "-journal"}) {
    if (fs::exists(from + suffix)) fs::copy_file(from + suffix, copy.string() + suffix);
  }

  // .recover needs the sqlite_dbpage table, which SQLite has only when built with
  // SQLITE_ENABLE_DBPAGE_VTAB (Debian's is not): without it .recover fails with "SQL logic error".
  const bool has_recover =
      run_to_end({shell, "-batch", ":memory:", "SELECT count(*) FROM sqlite_dbpage"}, tmp.path())
          .exit_code == 0;
  const std::string method = has_recover ? ".recover" : ".dump";

  // TO is created here, exclusively: a file that appeared meanwhile is not taken over. Until the
  // shells have run, a failure removes it again.
  const Fd claimed(::open(to.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644));
  if (claimed.get() < 0) {
    const int why = errno;
    std::cerr << "ncqual db recover: cannot create " << to << ": " << errno_text(why) << "\n";
    return kExitError;
  }
  Recovery r;
  try {
    r = pipe_into(shell, method, copy, to, header, tmp.path());
  } catch (...) {
    fs::remove(to, error);
    throw;
  }

  std::cout << "recovered " << from << " into " << to << " with sqlite3 " << method << "\n";
  if (!has_recover) {
    std::cout
        << "  this sqlite3 has no .recover (its SQLite lacks SQLITE_ENABLE_DBPAGE_VTAB); .dump "
           "reads each\n  table through its b-tree: the rows of a damaged page, and those "
           "below a damaged interior\n  page, are lost, and none is kept in a "
           "lost_and_found table\n";
  }
  if (r.stream.errors > 0) {
    std::cout << "  " << method << " met " << r.stream.errors << " damaged place"
              << (r.stream.errors == 1 ? "" : "s") << " in " << from << "\n";
  }
  if (r.dump_exit != 0) {
    std::cout << "  sqlite3 " << method << " exited with " << r.dump_exit << ":\n"
              << first_lines(r.dump_messages, 5);
  }
  const std::size_t failed = occurrences(r.load_messages, "error near line");
  if (failed > 0 || r.load_exit != 0) {
    std::cout << "  " << failed << " statement" << (failed == 1 ? "" : "s")
              << " of the recovered SQL failed (e.g. rows refused by a constraint); the first:\n"
              << first_lines(r.load_messages, 3);
  }
  return report_recovered(shell, from, to, header, tmp.path());
}

}  // namespace

void add_recover(CLI::App* db, Commands& commands) {
  const auto [recover, r] = add_command(
      *db, commands, "recover",
      "salvage what can be read of FROM into the new file TO (sqlite3 .recover, else .dump);\n"
      "FROM is only read, TO is never overwritten; stop the historian first",
      run_recover);
  recover->add_option("FROM", r->from, "the damaged historian database")
      ->type_name("FILE")
      ->required();
  recover->add_option("TO", r->to, "the new file (must not exist)")->type_name("FILE")->required();
}

}  // namespace ncqual::cli::database
