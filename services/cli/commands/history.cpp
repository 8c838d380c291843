// SPDX-License-Identifier: Apache-2.0
// `ncqual history`: the stored checks, newest first.
//
//   ncqual history [--plant F | --db F] [--machine M] [--kind K] [--limit N] [--since-ns T]
//                  [--writers] [--secure DIR] [--json]
//
// The table shows per check its time (in the plant's time zone with the offset, UTC without a
// plant config), machine, kind, verdict, its data's origin (SIMULATED: produced by ncqual's
// simulator; measured; unknown: stored before ncqual recorded it, schema 11), who ordered it and
// at most six metrics; --json: "origin" of each check and of its measurement; --writers adds
// under each check the DataWriters its request, set and result came from, and on a secured plant
// (the plant's security.dir, or --secure) the identity each GUID names (ncqual/dds/identity.hpp).
// --json prints every stored record (ncqual/storage/json.hpp; times as ns since the epoch, UTC),
// its writers with their identities when known. A check whose raw points retention deleted (`ncqual
// db thin`, docs/export.md) says "points thinned on <date>" with the counts measured (--json:
// measurement.points_thinned_ns); its result is as it was judged. Exit codes: 0, 6 when there is no
// historian database at the path; 2 when the security material cannot be read, and for a machine
// the plant does not configure (without a plant config: that the historian holds nothing of).
#include "commands.hpp"

#include "ncqual/common/calendar.hpp"
#include "ncqual/common/clock.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/dds/identity.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/storage/json.hpp"

#include <fmt/format.h>

#include <iostream>

namespace ncqual::cli {
namespace {

// At most kShownMetrics per row: all of them when few, else the worst-case summaries ("max")
// and the ones out of tolerance first (--json has every metric).
constexpr std::size_t kShownMetrics = 6;
std::string format_metrics(const std::vector<Metric>& metrics) {
  std::vector<const Metric*> shown;
  if (metrics.size() <= kShownMetrics) {
    for (const auto& m : metrics) shown.push_back(&m);
  } else {
    for (const auto& m : metrics) {
      if (m.name.find("max") != std::string::npos) shown.push_back(&m);
    }
    for (const auto& m : metrics) {
      if (!m.pass && m.name.find("max") == std::string::npos) shown.push_back(&m);
    }
    if (shown.size() > kShownMetrics) shown.resize(kShownMetrics);
  }
  std::string out;
  for (const Metric* m : shown) {
    if (!out.empty()) out += "  ";
    out += fmt::format("{}={}{}", m->name, format_metric_value(*m), m->pass ? "" : "(!)");
  }
  if (shown.size() < metrics.size()) {
    out += fmt::format("  (+{} more; --json for all)", metrics.size() - shown.size());
  }
  return out;
}

// The data column: SIMULATED stands out (a verdict on the simulator's numbers says nothing of a
// machine); "unknown" for a check stored before the historian recorded it.
std::string origin_column(DataOrigin origin) {
  return origin == DataOrigin::Simulated ? "SIMULATED" : std::string(to_string(origin));
}

struct Options {
  std::string plant;
  std::optional<std::string> db, machine;
  std::optional<CheckKind> kind;
  int limit = 100;
  std::int64_t since_ns = storage::HistoryQuery{}.since_ns;
  bool writers = false;
  std::string secure;  // ncqual-pki's material; else the plant's security.dir
  bool json = false;
};

// The plant's identities, to name writers by: from --secure, else the plant's security.dir;
// none on an open plant.
std::vector<dds::PlantIdentity> identities_of(const Options& o) {
  std::string dir = o.secure;
  if (dir.empty()) {
    const std::string plant = plant_config_path(o.plant);
    if (!plant.empty()) dir = load_plant_config(plant).security.dir;
  }
  if (dir.empty()) return {};
  try {
    return dds::plant_identities(dir);
  } catch (const std::runtime_error& e) {
    throw UsageError(std::string("cannot name the writers: ") + e.what());
  }
}

// "solver (CN=solver,O=plant F)", or the GUID and why it names no identity.
std::string writer_text(const std::string& guid, const std::vector<dds::PlantIdentity>& ids) {
  if (guid.empty()) return "-";
  if (ids.empty()) return guid;
  if (const auto id = dds::identity_of_guid(guid, ids)) {
    return id->name + " (" + id->subject + ")";
  }
  return guid + " (no identity of the plant)";
}

void print_writers(const storage::CheckRecord& r, const std::vector<dds::PlantIdentity>& ids,
                   std::size_t indent) {
  fmt::print("{:{}} request written by {}\n", "", indent, writer_text(r.writers.request, ids));
  fmt::print("{:{}} set written by {}\n", "", indent, writer_text(r.writers.measurement, ids));
  fmt::print("{:{}} result written by {}\n", "", indent, writer_text(r.writers.result, ids));
}

// The writers of the JSON records, each with its identity and subject when the plant names it.
void add_identities(nlohmann::json& records, const std::vector<dds::PlantIdentity>& ids) {
  for (auto& record : records) {
    for (auto& [part, writer] : record["writers"].items()) {
      if (writer.is_null()) continue;
      if (const auto id = dds::identity_of_guid(writer["guid"].get<std::string>(), ids)) {
        writer["identity"] = id->name;
        writer["subject"] = id->subject;
      }
    }
  }
}

int run(const Options& o) {
  const std::string path = database_path(o.db, o.plant);
  const bool configured = o.machine && check_machines_configured({*o.machine}, o.plant);
  auto opened = open_historian(path, "history");
  if (!opened) return kExitNotFound;
  storage::Database& db = *opened;
  if (o.machine && !configured) check_machines_held({*o.machine}, db, path);
  storage::HistoryQuery q;
  q.machine_id = o.machine;
  q.kind = o.kind;
  q.limit = o.limit;
  q.since_ns = o.since_ns;
  const auto records = db.history(q);
  const auto identities =
      o.writers || o.json ? identities_of(o) : std::vector<dds::PlantIdentity>{};
  if (o.json) {
    nlohmann::json out(records);
    add_identities(out, identities);
    std::cout << out.dump(2) << "\n";
  } else {
    print_check_records(records, plant_calendar(o.plant), o.writers ? &identities : nullptr);
  }
  return kExitOk;
}

}  // namespace

void print_check_records(const std::vector<storage::CheckRecord>& records, const Calendar& calendar,
                         const std::vector<dds::PlantIdentity>* writers) {
  constexpr const char* kRow = "{:<30} {:<10} {:<22} {:<8} {:<10} {:<16} {}\n";
  fmt::print(kRow, "time (" + calendar.zone_name() + ")", "machine", "check", "verdict", "data",
             "ordered by", "metrics ((!) = out of tolerance)");
  constexpr std::size_t kIndent = 65;  // under the verdict
  for (const auto& r : records) {
    const std::int64_t t = r.result ? r.result->time_ns : (r.request ? r.request->time_ns : 0);
    const std::string_view verdict = r.result ? to_string(r.result->verdict) : "pending";
    const std::string_view kind = r.result    ? to_string(r.result->kind)
                                  : r.request ? to_string(r.request->kind)
                                              : "?";
    // Who ordered it: the scheduler's plan, an intervention, an operator; an imported file has no
    // request; "?" while the historian has the result without its request.
    const std::string by = r.request ? r.request->requested_by
                           : r.measurement && r.measurement->instrument == kImportedInstrument
                               ? std::string(kImportedInstrument)
                               : std::string("?");
    fmt::print(kRow, calendar.local_text(t, true), r.machine_id, kind, verdict,
               origin_column(storage::origin_of(r)), by,
               r.result ? format_metrics(r.result->metrics) : "");
    if (r.result && r.result->verdict != Verdict::Pass) {
      if (!r.result->reason.empty()) {
        // The table shows the start of a long reason; `history --json` has all of it.
        constexpr std::size_t kShownReason = 300;
        std::string reason = r.result->reason;
        if (reason.size() > kShownReason) reason = reason.substr(0, kShownReason) + " ...";
        fmt::print("{:{}} reason: {}\n", "", kIndent, reason);
      }
      if (!r.result->likely_causes.empty()) {
        fmt::print("{:{}} first likely cause: {}\n", "", kIndent, r.result->likely_causes.front());
      }
    }
    if (r.conflicts > 0) {
      // Another sample with this request id and other content reached the historian: the row
      // above is the one stored first; `ncqual conflicts` shows the other.
      fmt::print("{:{}} CONFLICT: {} other sample(s) with this request id kept beside it\n", "",
                 kIndent, r.conflicts);
    }
    if (r.measurement && r.measurement->points_thinned_ns) {
      // Retention deleted the raw points (ncqual db thin); the result above is as it was judged.
      fmt::print("{:{}} points thinned on {} ({} touches, {} tracker points no longer stored)\n",
                 "", kIndent, calendar.local_text(*r.measurement->points_thinned_ns),
                 r.measurement->touches, r.measurement->tracker_points);
    }
    if (writers) print_writers(r, *writers, kIndent);
  }
}

void add_history(CLI::App& app, Commands& commands) {
  const auto [cmd, o] = add_command(app, commands, "history", "stored checks, newest first", run);
  add_historian_options(cmd, o->plant, o->db);
  add_machine_option(cmd, o->machine, "only this machine's checks");
  add_kind_option(cmd, "--kind", o->kind, "only checks of this kind");
  cmd->add_option("--limit", o->limit, "at most N checks (0: all)")
      ->type_name("N")
      ->capture_default_str();
  cmd->add_option("--since-ns", o->since_ns,
                  "only checks from this time on (ns since the epoch, UTC)")
      ->type_name("T");
  cmd->add_flag("--writers", o->writers,
                "under each check, the DataWriters of its request, set and result, and on a "
                "secured plant the identity each belongs to");
  cmd->add_option("--secure", o->secure,
                  "ncqual-pki's material to name the writers by (default: the plant's "
                  "security.dir)")
      ->type_name("DIR");
  add_json_flag(cmd, o->json);
}

}  // namespace ncqual::cli
