#pragma once
/// Error types shared by every module.
///
/// Two kinds of failure leave barnbench: bad input (a file, a field, a flag — exit code 2)
/// and a run that went wrong (exit code 1). Input problems are collected, each with the path
/// of the thing at fault, and thrown once so a user sees every mistake in one go.

#include <stdexcept>
#include <string>
#include <vector>

namespace barn::core {

/// Bad input: a file, field or flag that cannot be used. The CLI maps it to exit code 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A write that failed (disk full, permissions, I/O error): the run went wrong, not its input.
/// The message names the file and carries the system's reason. Exit code 1.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Collects validation messages, each prefixed by where the problem is ("world_000.yaml: grid").
class Errors {
 public:
  explicit Errors(std::string context = {}) : context_(std::move(context)) {}

  /// Records `message` for `field` unless `ok` holds; returns `ok`.
  bool check(bool ok, const std::string& field, const std::string& message);
  void add(const std::string& field, const std::string& message);

  bool empty() const { return messages_.empty(); }
  const std::vector<std::string>& messages() const { return messages_; }

  /// Throws one InputError listing every message (one per line) if any was recorded.
  void throwIfAny() const;

 private:
  std::string context_;                // file or object the messages are about
  std::vector<std::string> messages_;  // "context: field: message"
};

}  // namespace barn::core
