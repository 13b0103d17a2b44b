#pragma once
// Runs the annex-runtime executable as a user would and captures what it prints.

#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace annex::test {

struct CliRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

inline CliRun run_cli(const std::string& args) {
  CliRun r;
  const std::string cmd = shell_quote(ANNEX_RUNTIME_EXE) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline std::string source_path(const std::string& rel) {
  return std::string(ANNEX_SOURCE_DIR) + "/" + rel;
}

}  // namespace annex::test
