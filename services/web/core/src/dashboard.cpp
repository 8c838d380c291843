// SPDX-License-Identifier: Apache-2.0
// The dashboard's routing, its JSON and its connections (ncqual/web/dashboard.hpp); the HTML of
// the pages is pages.cpp.
#include "ncqual/web/dashboard.hpp"

#include "pages.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/status/plant_status.hpp"
#include "ncqual/storage/json.hpp"
#include "ncqual/storage/changes.hpp"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <limits>
#include <optional>
#include <set>
#include <stdexcept>
#include <utility>

namespace ncqual::web {
namespace {

constexpr const char* kJsonType = "application/json";

bool starts_with(const std::string& text, std::string_view prefix) {
  return text.size() >= prefix.size() && text.compare(0, prefix.size(), prefix) == 0;
}

// At most `n` characters of what a client sent, for a message that names it.
std::string shown(const std::string& text, std::size_t n = 64) {
  std::string out;
  for (const char c : text.substr(0, n)) {
    out += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? '?' : c;
  }
  return text.size() > n ? out + "..." : out;
}

Reply json_reply(int status, const nlohmann::json& document) {
  Reply r;
  r.status = status;
  r.content_type = kJsonType;
  // Invalid UTF-8 in a stored text is replaced, never a failed reply.
  r.body = document.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  return r;
}

// A refusal: {"error": {"status", "message"}} under /api/, a small page elsewhere.
Reply refusal(bool json, int status, const std::string& message, const PlantConfig& plant) {
  if (json) return json_reply(status, {{"error", {{"status", status}, {"message", message}}}});
  Reply r;
  r.status = status;
  r.content_type = kHtmlType;
  r.body = error_page(plant, status, message);
  return r;
}

// A client's mistake in a request, answered with `status` and the message.
struct Refused : std::runtime_error {
  Refused(int status, const std::string& message) : std::runtime_error(message), status(status) {}
  int status;
};

// Refuses a parameter that `allowed` does not name and one given twice.
void only_parameters(const Request& request, const std::set<std::string>& allowed) {
  std::set<std::string> seen;
  for (const auto& [name, value] : request.params) {
    if (!allowed.count(name)) {
      std::string names;
      for (const auto& a : allowed) names += (names.empty() ? "" : ", ") + a;
      throw Refused(400, "unknown parameter '" + shown(name) + "'" +
                             (names.empty() ? "; this page takes none" : "; expected " + names));
    }
    if (!seen.insert(name).second) throw Refused(400, "parameter '" + name + "' given twice");
  }
}

std::optional<std::string> parameter(const Request& request, const std::string& name) {
  for (const auto& [n, value] : request.params) {
    if (n == name) return value;
  }
  return std::nullopt;
}

// A machine or request id from a path: printable, no '/', at most `max` characters.
std::string path_id(const std::string& id, std::size_t max, const char* what) {
  if (id.empty()) throw Refused(404, std::string("no ") + what + " named");
  if (id.size() > max) {
    throw Refused(400, std::string(what) + " '" + shown(id) + "' is longer than " +
                           std::to_string(max) + " characters");
  }
  for (const char c : id) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f || c == '/') {
      throw Refused(404, std::string("no ") + what + " '" + shown(id) + "'");
    }
  }
  return id;
}

nlohmann::json failures_json(
    const std::vector<std::pair<std::string, storage::FailureRecord>>& fs) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [machine, f] : fs) {
    out.push_back({{"machine_id", machine},
                   {"request_id", f.request_id},
                   {"kind", f.kind},
                   {"verdict", f.verdict},
                   {"reason", f.reason},
                   {"time_ns", f.time_ns}});
  }
  return out;
}

}  // namespace

// ---- Connections --------------------------------------------------------------------------------

void ConnectionPool::with(const std::function<void(storage::Database&)>& body) {
  std::unique_ptr<storage::Database> db;
  {
    const std::lock_guard lock(mutex_);
    if (!free_.empty()) {
      db = std::move(free_.back());
      free_.pop_back();
    }
  }
  if (!db) db = std::make_unique<storage::Database>(storage::Database::open_readonly(path_));
  body(*db);  // a connection whose query threw is not put back: the next one starts afresh
  const std::lock_guard lock(mutex_);
  free_.push_back(std::move(db));
}

ChangeWatch::ChangeWatch(const std::string& path) : db_(storage::Database::open_readonly(path)) {}

std::string ChangeWatch::token() {
  const std::lock_guard lock(mutex_);
  const std::int64_t version = storage::data_version(db_);
  if (version != version_ || token_.empty()) {
    token_ = storage::change_token(db_);
    version_ = version;
  }
  return token_;
}

// ---- The dashboard ------------------------------------------------------------------------------

Dashboard::Dashboard(PlantConfig plant, const std::string& database_path, Limits limits,
                     std::function<std::int64_t()> now_ns)
    : plant_(std::move(plant)),
      calendar_(plant_status::plant_calendar(plant_)),
      limits_(limits),
      now_ns_(now_ns ? std::move(now_ns) : [] { return WallClock().now_ns(); }),
      pool_(database_path),
      watch_(database_path) {}

std::size_t Dashboard::refresh_budgets(const std::function<bool()>& stop) {
  const std::size_t before = budgets_.evaluations();
  pool_.with([&](storage::Database& db) {
    const std::int64_t now = now_ns_();
    for (const auto& machine : plant_.machines) {
      if (stop && stop()) break;
      if (!machine.budget || !db.machine(machine.machine_id)) continue;
      (void)report::machine_budget(db, machine.machine_id, &machine, now, &budgets_, &calendar_);
    }
  });
  return budgets_.evaluations() - before;
}

Reply Dashboard::handle(const Request& request) {
  const bool json = starts_with(request.path, "/api/");
  Reply reply;
  try {
    reply = route(request);
  } catch (const Refused& e) {
    reply = refusal(json, e.status, e.what(), plant_);
  } catch (const storage::StorageError& e) {
    spdlog::warn("{} {}: the historian database: {}", request.method, shown(request.path, 200),
                 e.what());
    reply = refusal(json, 503,
                    std::string("the historian database cannot be read now: ") + e.what(), plant_);
  }
  // Never cached: every reply is the historian as of now. Pages may not be framed.
  reply.headers.emplace_back("Cache-Control", "no-store");
  reply.headers.emplace_back("X-Content-Type-Options", "nosniff");
  reply.headers.emplace_back("Content-Security-Policy",
                             "default-src 'self'; style-src 'unsafe-inline'; "
                             "script-src 'unsafe-inline'; img-src 'self' data:; "
                             "frame-ancestors 'none'");
  return reply;
}

Reply Dashboard::route(const Request& request) {
  const bool json = starts_with(request.path, "/api/");
  if (request.method != "GET" && request.method != "HEAD") {
    Reply r = refusal(json, 405,
                      "method " + shown(request.method, 16) +
                          " not allowed: the dashboard is read-only (GET and HEAD only)",
                      plant_);
    r.headers.emplace_back("Allow", "GET, HEAD");
    return r;
  }
  const std::string& p = request.path;
  if (p == "/" || p == "/index.html") return plant_page(request, false);
  if (p == "/api/v1/plant") return plant_page(request, true);
  if (p == "/api/v1/changes") return changes(request);
  for (const auto& [prefix, is_json] :
       {std::pair<std::string_view, bool>{"/machines/", false}, {"/api/v1/machines/", true}}) {
    if (starts_with(p, prefix)) {
      return machine_page(request, path_id(p.substr(prefix.size()), limits_.max_id, "machine"),
                          is_json);
    }
  }
  for (const auto& [prefix, is_json] :
       {std::pair<std::string_view, bool>{"/checks/", false}, {"/api/v1/checks/", true}}) {
    if (starts_with(p, prefix)) {
      return check_page(request, path_id(p.substr(prefix.size()), limits_.max_id, "check"),
                        is_json);
    }
  }
  throw Refused(404, "no page " + shown(p) +
                         (json ? "; the API: /api/v1/plant, /api/v1/machines/<id>, "
                                 "/api/v1/checks/<request id>, /api/v1/changes"
                               : ""));
}

Reply Dashboard::changes(const Request& request) {
  only_parameters(request, {"since"});
  const auto since = parameter(request, "since");
  if (since && (since->size() > limits_.max_token ||
                since->find_first_not_of("0123456789.") != std::string::npos)) {
    throw Refused(400, "since '" + shown(*since) +
                           "' is not a change token (digits and dots, as /api/v1/changes gave)");
  }
  const std::string token = watch_.token();
  return json_reply(200, {{"token", token}, {"changed", !since || *since != token}});
}

Reply Dashboard::plant_page(const Request& request, bool json) {
  only_parameters(request, {});
  // The token first: what changes while the page is gathered moves the token past this one.
  const std::string token = watch_.token();
  PlantView view;
  view.token = token;
  pool_.with([&](storage::Database& db) {
    view.status = plant_status::plant_status(db, plant_, calendar_, {{}, now_ns_()});
    for (const auto& m : plant_.machines) {
      for (auto& f : storage::recent_failures(db, m.machine_id, limits_.failures)) {
        view.failures.emplace_back(m.machine_id, std::move(f));
      }
    }
  });
  // The newest across machines, at most limits_.failures.
  std::stable_sort(view.failures.begin(), view.failures.end(), [](const auto& a, const auto& b) {
    return a.second.time_ns > b.second.time_ns;
  });
  if (view.failures.size() > static_cast<std::size_t>(limits_.failures)) {
    view.failures.resize(static_cast<std::size_t>(limits_.failures));
  }
  if (json) {
    return json_reply(200, {{"token", token},
                            {"status", view.status},
                            {"failures", failures_json(view.failures)},
                            {"limits", {{"failures", limits_.failures}}}});
  }
  Reply r;
  r.content_type = kHtmlType;
  r.body = plant_html(plant_, calendar_, view, limits_);
  return r;
}

Reply Dashboard::machine_page(const Request& request, const std::string& id, bool json) {
  only_parameters(request, {json ? "checks" : "days"});
  const MachineConfig* config = plant_.find_machine(id);
  if (!config) throw Refused(404, "no machine '" + shown(id) + "' in plant '" + plant_.plant + "'");
  // A count from a parameter: digits only, within 1..max.
  const auto count = [&](const char* name, int fallback, int max) {
    const auto n = parameter(request, name);
    if (!n) return fallback;
    const bool digits =
        !n->empty() && n->size() <= 4 && n->find_first_not_of("0123456789") == std::string::npos;
    const int value = digits ? std::stoi(*n) : 0;
    if (value < 1 || value > max) {
      throw Refused(400, std::string(name) + " '" + shown(*n) + "' is not a number within 1.." +
                             std::to_string(max));
    }
    return value;
  };
  const int checks = count("checks", limits_.checks, limits_.max_checks);
  const int days = count("days", limits_.days, limits_.max_days);
  const std::string token = watch_.token();
  MachineView view;
  view.token = token;
  view.days = days;
  pool_.with([&](storage::Database& db) {
    const std::int64_t now = now_ns_();
    auto status = plant_status::plant_status(db, plant_, calendar_, {id, now});
    view.now_ns = status.now_ns.value_or(now);
    view.wall_now_ns = now;
    view.machine = std::move(status.machines.front());
    for (auto& f : storage::recent_failures(db, id, limits_.failures)) {
      view.failures.emplace_back(id, std::move(f));
    }
    storage::HistoryQuery history;
    history.machine_id = id;
    history.limit = checks;
    view.checks = db.history(history);
    if (!json) {
      const std::pair<std::string, int> key{id, days};
      {
        const std::lock_guard lock(report_cache_mutex_);
        const auto it = report_cache_.find(key);
        if (it != report_cache_.end() && it->second.token == token) {
          view.report_sections = it->second.sections;
          view.report_problem = it->second.problem;
          return;
        }
      }
      try {
        constexpr std::int64_t kDayNs = 86'400'000'000'000;
        view.report_sections = report_sections(db, *config, calendar_, view.now_ns - days * kDayNs,
                                               view.now_ns, &budgets_);
      } catch (const std::invalid_argument& e) {
        view.report_problem = e.what();  // e.g. the historian has nothing of the machine yet
      }
      const std::lock_guard lock(report_cache_mutex_);
      if (report_cache_.size() >= kReportCacheEntries) report_cache_.clear();
      report_cache_[key] = {token, view.report_sections, view.report_problem};
    }
  });
  if (json) {
    nlohmann::json records = nlohmann::json::array();
    for (const auto& c : view.checks) records.push_back(storage::document_of(c));
    return json_reply(200, {{"token", token},
                            {"now_ns", view.now_ns},
                            {"machine", view.machine},
                            {"failures", failures_json(view.failures)},
                            {"checks", std::move(records)},
                            {"limits", {{"failures", limits_.failures}, {"checks", checks}}}});
  }
  Reply r;
  r.content_type = kHtmlType;
  r.body = machine_html(plant_, calendar_, view, limits_);
  return r;
}

Reply Dashboard::check_page(const Request& request, const std::string& id, bool json) {
  only_parameters(request, {});
  const std::string token = watch_.token();
  std::optional<storage::CheckRecord> record;
  pool_.with([&](storage::Database& db) { record = db.find_check(id); });
  if (!record) throw Refused(404, "no check with request id '" + shown(id) + "'");
  if (json) {
    nlohmann::json document = storage::to_json(*record);
    document["token"] = token;
    return json_reply(200, document);
  }
  Reply r;
  r.content_type = kHtmlType;
  r.body = check_html(plant_, calendar_, *record, token, limits_);
  return r;
}

}  // namespace ncqual::web
