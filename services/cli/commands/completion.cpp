// SPDX-License-Identifier: Apache-2.0
// `ncqual completion bash` (hidden): prints a bash completion script derived from the app itself,
// so it never goes stale: per command path its subcommands and its flags, and which flags take
// a value. The build writes it to share/bash-completion/completions/ncqual (services/cli/
// CMakeLists.txt), and `install` puts it where bash-completion looks.
//
// The script completes subcommands where a subcommand is expected, the command's flags on
// "-", check kinds after --kind and --check, and file names after any other flag that takes a
// value and for positional FILEs.
#include "commands.hpp"
#include "help.hpp"

#include <iostream>
#include <map>

namespace ncqual::cli {
namespace {

struct Path {
  std::vector<std::string> subcommands, flags, valued;
};

// Every command path from `app` ("ncqual", "ncqual analyze", "ncqual analyze circle", ...) with
// what it takes (bash has no empty key).
void walk(const CLI::App& app, const std::string& path, std::map<std::string, Path>& out) {
  Path& p = out[path];
  for (const CLI::Option* opt : app.get_options()) {
    if (opt->get_positional()) continue;
    for (const auto& s : opt->get_snames()) p.flags.push_back("-" + s);
    for (const auto& l : opt->get_lnames()) {
      p.flags.push_back("--" + l);
      if (takes_value(*opt)) p.valued.push_back("--" + l);
    }
  }
  for (const CLI::App* sub : app.get_subcommands({})) {
    if (sub->get_group().empty()) continue;  // hidden, as this command
    p.subcommands.push_back(sub->get_name());
    walk(*sub, path + " " + sub->get_name(), out);
  }
}

std::string joined(const std::vector<std::string>& words) {
  std::string out;
  for (const auto& w : words) out += (out.empty() ? "" : " ") + w;
  return out;
}

int print_bash(const CLI::App& root) {
  std::map<std::string, Path> paths;
  walk(root, root.get_name(), paths);
  std::string kinds;
  for (CheckKind k : all_check_kinds())
    kinds += (kinds.empty() ? "" : " ") + std::string(to_string(k));
  std::cout << "# bash completion of " << root.get_name() << ", written by `" << root.get_name()
            << " completion bash` from its command line.\n"
            << "_" << root.get_name() << "() {\n"
            << "  local -A subcommands=(";
  for (const auto& [path, p] : paths)
    std::cout << " [\"" << path << "\"]=\"" << joined(p.subcommands) << "\"";
  std::cout << " )\n  local -A flags=(";
  for (const auto& [path, p] : paths)
    std::cout << " [\"" << path << "\"]=\"" << joined(p.flags) << "\"";
  std::cout << " )\n  local -A valued=(";
  for (const auto& [path, p] : paths)
    std::cout << " [\"" << path << "\"]=\"" << joined(p.valued) << "\"";
  std::cout << " )\n"
            << "  local kinds=\"" << kinds << "\"\n"
            << R"(  local cur=${COMP_WORDS[COMP_CWORD]} prev= path=)" << root.get_name()
            << R"( word i
  ((COMP_CWORD > 0)) && prev=${COMP_WORDS[COMP_CWORD - 1]}
  # The command path: the words before the cursor that name a subcommand where one is expected
  # (the value of a flag never does).
  for ((i = 1; i < COMP_CWORD; i++)); do
    word=${COMP_WORDS[i]}
    if [[ " ${valued[$path]} " == *" $word "* ]]; then
      ((i++))
    elif [[ " ${subcommands[$path]} " == *" $word "* ]]; then
      path="$path $word"
    fi
  done
  COMPREPLY=()
  if [[ " ${valued[$path]} " == *" $prev "* ]]; then
    case $prev in
      --kind | --check) COMPREPLY=($(compgen -W "$kinds" -- "$cur")) ;;
      *) COMPREPLY=($(compgen -f -- "$cur")) ;;
    esac
  elif [[ $cur == -* ]]; then
    COMPREPLY=($(compgen -W "${flags[$path]}" -- "$cur"))
  elif [[ -n ${subcommands[$path]} ]]; then
    COMPREPLY=($(compgen -W "${subcommands[$path]}" -- "$cur"))
  else
    COMPREPLY=($(compgen -f -- "$cur"))
  fi
}
complete -o filenames -F _)"
            << root.get_name() << " " << root.get_name() << "\n";
  return kExitOk;
}

}  // namespace

void add_completion(CLI::App& app, Commands& commands) {
  auto shell = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("completion", "print the shell completion script");
  cmd->group("");  // hidden from the help
  cmd->add_option("SHELL", *shell, "the shell: bash")->required()->check(CLI::IsMember({"bash"}));
  commands.push_back({cmd, [cmd] { return print_bash(*cmd->get_parent()); }});
}

}  // namespace ncqual::cli
