// tests/support/cli.hpp -- running the `tetia` executable from a test: one command line with
// its standard input from a file (or /dev/null), its outputs captured.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace tetia::testcli {

struct Result {
  int status = -1;  ///< exit status, or -1 if the process did not exit normally
  std::string out, err;
};

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') q += "'\\''";
    else q += c;
  }
  return q + "'";
}

/// Runs `program args` through the shell in `dir` (outputs go to files there), standard input
/// from `input` (empty path: /dev/null).
inline Result run(const std::string& program, const std::string& args, const std::filesystem::path& dir,
                  const std::filesystem::path& input = {}) {
  const std::filesystem::path out = dir / "stdout", err = dir / "stderr";
  const std::string in = input.empty() ? std::string("/dev/null") : shell_quote(input.string());
  const std::string cmd = shell_quote(program) + " " + args + " < " + in + " > " + shell_quote(out.string()) +
                          " 2> " + shell_quote(err.string());
  const int raw = std::system(cmd.c_str());
  Result r;
  r.status = (raw != -1 && WIFEXITED(raw)) ? WEXITSTATUS(raw) : -1;
  r.out = read_file(out);
  r.err = read_file(err);
  return r;
}

}  // namespace tetia::testcli
