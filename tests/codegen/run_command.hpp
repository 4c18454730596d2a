#pragma once
// Runs a program as a user's shell would, under a time limit, and returns what
// it printed and how it ended: for the tests of the generator's command line.

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace symdyn::testing {

struct CommandResult {
  int exit_code =
      -1;  // the shell's: 128 + n when killed by signal n, 124 when the time limit ended it
  std::string out, err;
};

// A fresh directory of its own for each call, so that tests run in parallel.
inline std::filesystem::path scratch_directory(const std::string& what) {
  static std::atomic<int> counter{0};
  const auto dir = std::filesystem::temp_directory_path() /
                   fmt::format("symdyn_{}_{}_{}", what, ::getpid(), counter++);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string shell_quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c;
    }
  }
  out += '\'';
  return out;
}

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// argv[0] is the program, run in `cwd` (if given) for at most `seconds`. A
// sanitizer's report exits with 86, not with the generator's 1, so that it is
// never taken for a model error.
inline CommandResult run_command(const std::vector<std::string>& argv, int seconds = 120,
                                 const std::filesystem::path& cwd = {}) {
  const auto dir = scratch_directory("run");
  std::string command =
      cwd.empty() ? std::string() : fmt::format("cd {} && ", shell_quoted(cwd.string()));
  command += fmt::format("ASAN_OPTIONS=\"${{ASAN_OPTIONS}}:exitcode=86\" timeout -k 5 {}", seconds);
  for (const std::string& a : argv) command += fmt::format(" {}", shell_quoted(a));
  command += fmt::format(" >{} 2>{}", shell_quoted((dir / "out").string()),
                         shell_quoted((dir / "err").string()));
  const int status = std::system(command.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = read_text(dir / "out");
  r.err = read_text(dir / "err");
  std::filesystem::remove_all(dir);
  return r;
}

}  // namespace symdyn::testing
