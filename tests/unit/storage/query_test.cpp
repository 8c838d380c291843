// SPDX-License-Identifier: Apache-2.0
// history(), find_check() and the JSON the command-line tool prints.
#include "ncqual/storage/json.hpp"
#include "storage_test_support.hpp"

#include <gtest/gtest.h>

namespace ncqual::storage {
namespace {

using namespace testing;  // storage_test_support.hpp

std::vector<std::string> ids(const std::vector<CheckRecord>& records) {
  std::vector<std::string> out;
  for (const auto& record : records) out.push_back(record.request_id);
  return out;
}

class StorageQuery : public ::testing::Test {
 protected:
  // M1: a finished check (a), a pending request (b), a result without request (c), a
  // measurement only (d); M2: a finished check of another kind (e).
  void SetUp() override {
    ASSERT_TRUE(db_.store(make_request("a", "M1", 100)));
    ASSERT_TRUE(db_.store(make_measurement_set("a", "M1", 150)));
    ASSERT_TRUE(db_.store(make_result("a", "M1", 500)));  // sorts by its result time
    ASSERT_TRUE(db_.store(make_request("b", "M1", 400)));
    ASSERT_TRUE(db_.store(make_result("c", "M1", 300)));
    ASSERT_TRUE(db_.store(make_measurement_set("d", "M1", 200)));
    CheckRequest other = make_request("e", "M2", 50);
    other.kind = CheckKind::GlobalGrid;
    CheckResult other_result = make_result("e", "M2", 600);
    other_result.kind = CheckKind::GlobalGrid;
    other_result.verdict = Verdict::Pass;
    other_result.correction.reset();
    ASSERT_TRUE(db_.store(other));
    ASSERT_TRUE(db_.store(other_result));
  }

  TempDir dir_;
  Database db_ = Database::open(dir_.file("historian.db"));
};

TEST_F(StorageQuery, HistoryIsNewestFirstByResultElseRequestElseMeasurementTime) {
  EXPECT_EQ(ids(db_.history({})), (std::vector<std::string>{"e", "a", "b", "c", "d"}));
}

TEST_F(StorageQuery, HistoryFiltersByMachineKindSinceAndLimit) {
  HistoryQuery query;
  query.machine_id = "M1";
  EXPECT_EQ(ids(db_.history(query)), (std::vector<std::string>{"a", "b", "c", "d"}));
  query.since_ns = 300;
  EXPECT_EQ(ids(db_.history(query)), (std::vector<std::string>{"a", "b", "c"}));
  query.limit = 2;
  EXPECT_EQ(ids(db_.history(query)), (std::vector<std::string>{"a", "b"}));
  query.limit = 0;  // no limit
  EXPECT_EQ(ids(db_.history(query)).size(), 3u);

  HistoryQuery by_kind;
  by_kind.kind = CheckKind::GlobalGrid;
  EXPECT_EQ(ids(db_.history(by_kind)), (std::vector<std::string>{"e"}));
  by_kind.machine_id = "M1";
  EXPECT_TRUE(db_.history(by_kind).empty());
  HistoryQuery unknown_machine;
  unknown_machine.machine_id = "M9";
  EXPECT_TRUE(db_.history(unknown_machine).empty());
}

TEST_F(StorageQuery, HistoryJoinsTheParts) {
  HistoryQuery query;
  query.machine_id = "M1";
  const auto records = db_.history(query);
  ASSERT_EQ(records.size(), 4u);
  const CheckRecord& a = records[0];
  EXPECT_TRUE(a.request && a.measurement && a.result);
  EXPECT_EQ(a.measurement->touches, 4);
  const CheckRecord& b = records[1];
  EXPECT_TRUE(b.request && !b.measurement && !b.result);
  EXPECT_EQ(b.machine_id, "M1");
  const CheckRecord& c = records[2];
  EXPECT_TRUE(!c.request && !c.measurement && c.result);
  const CheckRecord& d = records[3];
  EXPECT_TRUE(!d.request && d.measurement && !d.result);
  EXPECT_EQ(d.kind, CheckKind::MonumentCAlignment);
}

TEST_F(StorageQuery, CountsResultsPerMachine) {
  EXPECT_EQ(db_.count_results(), 3);
  EXPECT_EQ(db_.count_results("M1"), 2);
  EXPECT_EQ(db_.count_results("M2"), 1);
  EXPECT_EQ(db_.count_results("M9"), 0);
  EXPECT_EQ(db_.machines(), (std::vector<std::string>{"M1", "M2"}));
}

TEST_F(StorageQuery, FindCheckOfAnUnknownRequestIsEmpty) {
  EXPECT_FALSE(db_.find_check("zz").has_value());
}

TEST_F(StorageQuery, JsonOfAFinishedCheckHasTheStableNames) {
  const auto record = db_.find_check("a");
  ASSERT_TRUE(record.has_value());
  const nlohmann::json json = to_json(*record);
  EXPECT_EQ(json["machine_id"], "M1");
  EXPECT_EQ(json["request_id"], "a");
  EXPECT_EQ(json["kind"], "monument_c_alignment");
  EXPECT_EQ(json["requested_by"], "operator:ada");
  EXPECT_EQ(json["requested_at_ns"], 100);
  EXPECT_EQ(json["result_at_ns"], 500);
  EXPECT_EQ(json["verdict"], "FAIL");
  EXPECT_EQ(json["reason"], "center_dx_mm out of tolerance");
  ASSERT_EQ(json["metrics"].size(), 3u);
  EXPECT_EQ(json["metrics"][0], (nlohmann::json{{"name", "center_dx_mm"},
                                                {"value", 0.0123456789012345},
                                                {"unit", "mm"},
                                                {"lower", -0.01},
                                                {"upper", 0.01},
                                                {"pass", false}}));
  EXPECT_EQ(json["likely_causes"],
            (nlohmann::json{"probe stylus bent", "C axis encoder offset", "monument moved"}));
  EXPECT_EQ(json["correction"]["target"], "machine:work_offset");
  EXPECT_EQ(json["correction"]["offsets"][0],
            (nlohmann::json{{"name", "dx_mm"}, {"value", -0.0123}, {"unit", "mm"}}));
  EXPECT_EQ(json["measurement"], (nlohmann::json{{"instrument", "touch_probe"},
                                                 {"touches", 4},
                                                 {"tracker_points", 3},
                                                 {"error", ""},
                                                 {"points_thinned_ns", nullptr},
                                                 {"origin", "unknown"}}));
  // Schema 11: whether the check's numbers were measured or simulated; this one did not say.
  EXPECT_EQ(json["origin"], "unknown");
  // An infinite bound prints as null: JSON has no infinity.
  EXPECT_NE(json.dump().find("\"lower\":null"), std::string::npos);
}

TEST_F(StorageQuery, JsonOfAPendingCheckHasNullsWhereNothingArrived) {
  const auto record = db_.find_check("b");
  ASSERT_TRUE(record.has_value());
  const nlohmann::json json = *record;  // through nlohmann's ADL conversion
  EXPECT_EQ(json["requested_at_ns"], 400);
  EXPECT_TRUE(json["verdict"].is_null());
  EXPECT_TRUE(json["reason"].is_null());
  EXPECT_TRUE(json["result_at_ns"].is_null());
  EXPECT_TRUE(json["correction"].is_null());
  EXPECT_TRUE(json["measurement"].is_null());
  EXPECT_EQ(json["metrics"], nlohmann::json::array());
  EXPECT_EQ(json["likely_causes"], nlohmann::json::array());

  const auto result_only = db_.find_check("c");
  ASSERT_TRUE(result_only.has_value());
  const nlohmann::json c = to_json(*result_only);
  EXPECT_TRUE(c["requested_by"].is_null());
  EXPECT_TRUE(c["requested_at_ns"].is_null());
  EXPECT_EQ(c["verdict"], "FAIL");

  const nlohmann::json all = db_.history({});
  ASSERT_TRUE(all.is_array());
  EXPECT_EQ(all.size(), 5u);
  EXPECT_EQ(all[0]["correction"], nullptr);  // e: PASS without correction
  EXPECT_EQ(all[0]["verdict"], "PASS");
  EXPECT_EQ(all[0]["kind"], "global_grid");
}

}  // namespace
}  // namespace ncqual::storage
