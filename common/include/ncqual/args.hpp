// Command-line arguments: "--name value", "--name=value" and bare "--flag". Unknown flags and
// missing values are errors that name the flag, so a typo never silently changes behaviour.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual {

class ArgError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Args {
 public:
  // `with_value`: flags that take a value; `switches`: flags that do not.
  Args(const std::vector<std::string>& argv, const std::set<std::string>& with_value,
       const std::set<std::string>& switches);

  bool has(const std::string& flag) const;
  std::optional<std::string> get(const std::string& flag) const;
  std::string get_or(const std::string& flag, const std::string& fallback) const;
  std::string require(const std::string& flag) const;
  // Integer/number values; the error names the flag and the value.
  int get_int(const std::string& flag, int fallback) const;
  std::int64_t get_int64(const std::string& flag, std::int64_t fallback) const;
  double get_double(const std::string& flag, double fallback) const;
  const std::vector<std::string>& positional() const { return positional_; }

 private:
  std::map<std::string, std::string> values_;
  std::set<std::string> switches_seen_;
  std::vector<std::string> positional_;
};

}  // namespace ncqual
