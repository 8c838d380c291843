// SPDX-License-Identifier: Apache-2.0
// Shared by the storage tests: a temporary directory per test, a raw SQLite handle to look at the
// file behind the library's back, and sample builders with every field set to something
// distinguishable.
#pragma once

#include "ncqual/storage/database.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>

namespace ncqual::storage::testing {

// A fresh directory under the system temp dir, removed with everything in it at the end.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = "ncqual-storage-" + std::to_string(::getpid()) + "-" +
                       std::to_string(counter++) + "-" + (info ? info->name() : "x");
    path_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// While it lives, writes that grow a file past 1 KiB fail with EFBIG, as they fail with ENOSPC on a
// full disk (RLIMIT_FSIZE: no root needed): SQLite reports an I/O error or "disk full". SIGXFSZ is
// ignored meanwhile, as the services ignore it, or the kernel would end the process.
class FullDisk {
 public:
  FullDisk() : old_handler_(std::signal(SIGXFSZ, SIG_IGN)) {
    if (getrlimit(RLIMIT_FSIZE, &saved_) != 0) throw std::runtime_error("getrlimit failed");
    rlimit tiny = saved_;
    tiny.rlim_cur = 1024;  // below every file's size: every write past it fails
    if (setrlimit(RLIMIT_FSIZE, &tiny) != 0) throw std::runtime_error("setrlimit failed");
  }
  ~FullDisk() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, old_handler_);
  }
  FullDisk(const FullDisk&) = delete;
  FullDisk& operator=(const FullDisk&) = delete;

 private:
  void (*old_handler_)(int);
  rlimit saved_{};
};

// A plain SQLite connection for looking at what the library wrote.
class RawDb {
 public:
  explicit RawDb(const std::string& path, int flags = SQLITE_OPEN_READWRITE) {
    if (sqlite3_open_v2(path.c_str(), &db_, flags, nullptr) != SQLITE_OK) {
      const std::string message = db_ ? sqlite3_errmsg(db_) : "out of memory";
      sqlite3_close(db_);
      throw std::runtime_error("raw open " + path + ": " + message);
    }
    sqlite3_busy_timeout(db_, 5000);
  }
  ~RawDb() { sqlite3_close(db_); }
  RawDb(const RawDb&) = delete;
  RawDb& operator=(const RawDb&) = delete;

  void exec(const std::string& sql) {
    char* error = nullptr;
    if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
      const std::string message = error ? error : "?";
      sqlite3_free(error);
      throw std::runtime_error("raw exec '" + sql + "': " + message);
    }
  }

  // First column of the first row, as text ("" when no row).
  std::string text(const std::string& sql) {
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &stmt, nullptr) != SQLITE_OK) {
      throw std::runtime_error("raw prepare '" + sql + "': " + sqlite3_errmsg(db_));
    }
    std::string value;
    const int rc = sqlite3_step(stmt);
    if (rc == SQLITE_ROW && sqlite3_column_text(stmt, 0) != nullptr) {
      value = reinterpret_cast<const char*>(sqlite3_column_text(stmt, 0));
    }
    sqlite3_finalize(stmt);
    if (rc != SQLITE_ROW && rc != SQLITE_DONE) {
      throw std::runtime_error("raw step '" + sql + "': " + sqlite3_errmsg(db_));
    }
    return value;
  }

  std::int64_t count(const std::string& table, const std::string& where = "1") {
    return std::stoll(text("SELECT count(*) FROM " + table + " WHERE " + where));
  }

  sqlite3* get() const { return db_; }

 private:
  sqlite3* db_ = nullptr;
};

// Field by field, exactly: SQLite stores IEEE doubles, nothing may be lost on the way.
inline void expect_axes_eq(const AxisPosition& a, const AxisPosition& b) {
  // Exact: SQLite stores IEEE doubles, nothing may be lost on the way.
  EXPECT_EQ(a.x_mm, b.x_mm);
  EXPECT_EQ(a.y_mm, b.y_mm);
  EXPECT_EQ(a.z_mm, b.z_mm);
  EXPECT_EQ(a.w_mm, b.w_mm);
  EXPECT_EQ(a.a_rad, b.a_rad);
  EXPECT_EQ(a.c_rad, b.c_rad);
}

inline void expect_result_eq(const CheckResult& a, const CheckResult& b) {
  EXPECT_EQ(a.machine_id, b.machine_id);
  EXPECT_EQ(a.request_id, b.request_id);
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.verdict, b.verdict);
  EXPECT_EQ(a.reason, b.reason);
  EXPECT_EQ(a.time_ns, b.time_ns);
  EXPECT_EQ(a.produced_by, b.produced_by);
  EXPECT_EQ(a.origin, b.origin);
  ASSERT_EQ(a.metrics.size(), b.metrics.size());
  for (std::size_t i = 0; i < a.metrics.size(); ++i) {
    EXPECT_EQ(a.metrics[i].name, b.metrics[i].name);
    EXPECT_EQ(a.metrics[i].value, b.metrics[i].value);
    EXPECT_EQ(a.metrics[i].unit, b.metrics[i].unit);
    EXPECT_EQ(a.metrics[i].lower, b.metrics[i].lower);
    EXPECT_EQ(a.metrics[i].upper, b.metrics[i].upper);
    EXPECT_EQ(a.metrics[i].pass, b.metrics[i].pass);
  }
  EXPECT_EQ(a.likely_causes, b.likely_causes);
  ASSERT_EQ(a.correction.has_value(), b.correction.has_value());
  if (a.correction) {
    EXPECT_EQ(a.correction->target, b.correction->target);
    ASSERT_EQ(a.correction->offsets.size(), b.correction->offsets.size());
    for (std::size_t i = 0; i < a.correction->offsets.size(); ++i) {
      EXPECT_EQ(a.correction->offsets[i].name, b.correction->offsets[i].name);
      EXPECT_EQ(a.correction->offsets[i].value, b.correction->offsets[i].value);
      EXPECT_EQ(a.correction->offsets[i].unit, b.correction->offsets[i].unit);
    }
  }
}

inline CheckRequest make_request(const std::string& request_id,
                                 const std::string& machine_id = "M1",
                                 std::int64_t time_ns = 1'000) {
  CheckRequest request;
  request.machine_id = machine_id;
  request.request_id = request_id;
  request.kind = CheckKind::MonumentCAlignment;
  request.requested_by = "operator:ada";
  request.time_ns = time_ns;
  request.attempt = 2;
  return request;
}

inline MeasurementSet make_measurement_set(const std::string& request_id,
                                           const std::string& machine_id = "M1",
                                           std::int64_t time_ns = 2'000) {
  MeasurementSet set;
  set.machine_id = machine_id;
  set.request_id = request_id;
  set.kind = CheckKind::MonumentCAlignment;
  set.instrument = "touch_probe";
  set.frame = "machine";
  set.time_ns = time_ns;
  for (int i = 0; i < 4; ++i) {
    Touch touch;
    touch.feature = i < 2 ? "hole_edge" : "face";
    // Values with no short decimal form: a round trip through text would lose their last bits.
    touch.axes = AxisPosition{100.0 / 3 + i, -0.1 * i, 7.0 / 9, 1e-9 * i, 0.5 + i, -3.0 / 7};
    touch.approach = Eigen::Vector3d(1.0 / std::sqrt(3.0), -1.0 / std::sqrt(3.0), 1.0 / 3);
    set.touches.push_back(touch);
  }
  for (int i = 0; i < 3; ++i) {
    TrackerPoint point;
    point.label = "P" + std::to_string(i);
    point.commanded = AxisPosition{10.0 * i, 20.0 / 7, -30.0, 0.0, 0.25, 1.0 / 11};
    point.measured_mm = Eigen::Vector3d(10.0 * i + 1e-4, 20.0 / 7 - 2e-5, -30.0 + 1.0 / 17);
    set.tracker_points.push_back(point);
  }
  return set;
}

inline CheckResult make_result(const std::string& request_id, const std::string& machine_id = "M1",
                               std::int64_t time_ns = 3'000) {
  CheckResult result;
  result.machine_id = machine_id;
  result.request_id = request_id;
  result.kind = CheckKind::MonumentCAlignment;
  result.verdict = Verdict::Fail;
  result.metrics = {
      Metric{"center_dx_mm", 0.0123456789012345, "mm", -0.01, 0.01, false},
      Metric{"center_dy_mm", -1.0 / 3000, "mm", -0.01, 0.01, true},
      // A one-sided band: the bound is infinite.
      Metric{"tilt_arcsec", 2.5, "arcsec", -std::numeric_limits<double>::infinity(), 4.0, true},
  };
  result.likely_causes = {"probe stylus bent", "C axis encoder offset", "monument moved"};
  result.reason = "center_dx_mm out of tolerance";
  result.correction =
      Correction{"machine:work_offset",
                 {NamedValue{"dx_mm", -0.0123, "mm"}, NamedValue{"dc_rad", 1e-6, "rad"}}};
  result.time_ns = time_ns;
  result.produced_by = "ncqual-solver 0.1.0 (git 1a2b3c4)";
  return result;
}

}  // namespace ncqual::storage::testing
