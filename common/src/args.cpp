#include "ncqual/args.hpp"

#include <cmath>

namespace ncqual {

Args::Args(const std::vector<std::string>& argv, const std::set<std::string>& with_value,
           const std::set<std::string>& switches) {
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (a.rfind("--", 0) != 0 || a == "--") {
      positional_.push_back(a);
      continue;
    }
    std::string name = a.substr(2);
    std::optional<std::string> inline_value;
    if (const auto eq = name.find('='); eq != std::string::npos) {
      inline_value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    if (switches.count(name)) {
      if (inline_value) throw ArgError("--" + name + " takes no value (got '" + *inline_value + "')");
      switches_seen_.insert(name);
    } else if (with_value.count(name)) {
      if (inline_value) {
        values_[name] = *inline_value;
      } else if (i + 1 < argv.size()) {
        values_[name] = argv[++i];
      } else {
        throw ArgError("--" + name + " needs a value");
      }
    } else {
      throw ArgError("unknown option --" + name);
    }
  }
}

bool Args::has(const std::string& flag) const {
  return switches_seen_.count(flag) > 0 || values_.count(flag) > 0;
}

std::optional<std::string> Args::get(const std::string& flag) const {
  if (auto it = values_.find(flag); it != values_.end()) return it->second;
  return std::nullopt;
}

std::string Args::get_or(const std::string& flag, const std::string& fallback) const {
  return get(flag).value_or(fallback);
}

std::string Args::require(const std::string& flag) const {
  auto v = get(flag);
  if (!v || v->empty()) throw ArgError("--" + flag + " is required");
  return *v;
}

int Args::get_int(const std::string& flag, int fallback) const {
  auto v = get(flag);
  if (!v) return fallback;
  try {
    std::size_t used = 0;
    const int n = std::stoi(*v, &used);
    if (used == v->size()) return n;
  } catch (const std::logic_error&) {
  }
  throw ArgError("--" + flag + " = '" + *v + "': expected an integer");
}

std::int64_t Args::get_int64(const std::string& flag, std::int64_t fallback) const {
  auto v = get(flag);
  if (!v) return fallback;
  try {
    std::size_t used = 0;
    const long long n = std::stoll(*v, &used);
    if (used == v->size()) return n;
  } catch (const std::logic_error&) {
  }
  throw ArgError("--" + flag + " = '" + *v + "': expected an integer");
}

double Args::get_double(const std::string& flag, double fallback) const {
  auto v = get(flag);
  if (!v) return fallback;
  try {
    std::size_t used = 0;
    const double d = std::stod(*v, &used);
    if (used == v->size() && std::isfinite(d)) return d;
  } catch (const std::logic_error&) {
  }
  throw ArgError("--" + flag + " = '" + *v + "': expected a number");
}

}  // namespace ncqual
