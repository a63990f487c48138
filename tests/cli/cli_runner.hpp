#pragma once
// Running the real `barn` executable from tests: shell quoting, temp paths, file helpers.

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

namespace barn::test {

namespace fs = std::filesystem;

inline const fs::path kBarn = fs::path(BARN_BINARY_DIR) / "barn";

/// `text` as one single-quoted shell word.
inline std::string quote(const std::string& text) {
  std::string out = "'";
  for (char ch : text) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}
inline std::string quote(const fs::path& path) { return quote(path.string()); }

inline std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

inline void writeFile(const fs::path& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << content;
}

inline void appendFile(const fs::path& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary | std::ios::app);
  out << content;
}

/// A fresh path in the temp folder; the random suffix keeps concurrent runs (two build trees,
/// ctest -j) apart.
inline fs::path uniqueTempPath(const std::string& stem) {
  std::random_device device;
  return fs::temp_directory_path() / (stem + "_" + std::to_string(device()) + "_" + std::to_string(device()));
}

/// Every line of `text` starting with `prefix` replaced by `replacement` (removed if empty).
inline std::string replaceLine(const std::string& text, const std::string& prefix, const std::string& replacement) {
  std::istringstream in(text);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(prefix, 0) == 0) {
      if (!replacement.empty()) out += replacement + "\n";
    } else {
      out += line + "\n";
    }
  }
  return out;
}

struct RunResult {
  int exit_code = -1;  // WEXITSTATUS, or -1 if the process did not exit normally
  std::string output;  // stdout and stderr, interleaved
};

/// Runs `barn <args>` through the shell; `args` must already be quoted where needed.
inline RunResult run(const std::string& args) {
  const fs::path capture = uniqueTempPath("barn_cli_output");
  const std::string command = quote(kBarn) + " " + args + " > " + quote(capture) + " 2>&1";
  const int status = std::system(command.c_str());
  RunResult result;
  result.output = readFile(capture);
  std::error_code ec;
  fs::remove(capture, ec);
  if (status != -1 && WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  return result;
}

}  // namespace barn::test
