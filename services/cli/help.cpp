// SPDX-License-Identifier: Apache-2.0
#include "help.hpp"

#include <sstream>

namespace ncqual::cli {
namespace {

constexpr std::size_t kWidth = 100;

// Lines of at most kWidth columns: words after the first line are indented to `indent`.
std::string wrap(const std::vector<std::string>& words, std::size_t indent) {
  std::string out, line;
  for (const auto& w : words) {
    if (!line.empty() && line.size() + 1 + w.size() > kWidth) {
      out += line + "\n";
      line = std::string(indent, ' ');
    } else if (!line.empty() && line.find_first_not_of(' ') != std::string::npos) {
      line += " ";
    }
    line += w;
  }
  return out + line + "\n";
}

bool visible(const CLI::App* sub) { return !sub->get_group().empty() && !sub->get_name().empty(); }

}  // namespace

bool takes_value(const CLI::Option& option) { return option.get_expected_max() != 0; }

std::string synopsis(const CLI::App& command) {
  std::vector<std::string> path;
  for (const CLI::App* a = &command; a->get_parent() != nullptr; a = a->get_parent()) {
    path.insert(path.begin(), a->get_name());
  }
  std::vector<std::string> words{"  "};
  for (const auto& p : path) words.back() += (words.back().size() > 2 ? " " : "") + p;
  const std::size_t indent = words.back().size() + 1;
  for (const CLI::Option* opt : command.get_options()) {
    if (opt == command.get_help_ptr() || opt == command.get_help_all_ptr()) continue;
    if (opt->get_positional()) {
      words.push_back(opt->get_name());
      continue;
    }
    if (opt->get_lnames().empty()) continue;
    std::string word = "--" + opt->get_lnames().front();
    if (takes_value(*opt)) word += " " + opt->get_type_name();
    words.push_back(opt->get_required() ? word : "[" + word + "]");
  }
  return wrap(words, indent);
}

HelpFormatter::HelpFormatter() { label("Usage", "usage"); }

std::string HelpFormatter::make_subcommand(const CLI::App* sub) const {
  std::string out;
  const auto children = sub->get_subcommands([](const CLI::App* c) { return visible(c); });
  if (children.empty()) {
    out += synopsis(*sub);
  } else {
    for (const CLI::App* c : children) out += synopsis(*c);
  }
  std::istringstream description(sub->get_description());
  for (std::string line; std::getline(description, line);) out += "      " + line + "\n";
  return out;
}

}  // namespace ncqual::cli
