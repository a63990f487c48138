#include "barn/core/errors.hpp"

namespace barn::core {

bool Errors::check(bool ok, const std::string& field, const std::string& message) {
  if (!ok) add(field, message);
  return ok;
}

void Errors::add(const std::string& field, const std::string& message) {
  std::string line;
  if (!context_.empty()) line += context_ + ": ";
  if (!field.empty()) line += field + ": ";
  line += message;
  messages_.push_back(std::move(line));
}

void Errors::throwIfAny() const {
  if (messages_.empty()) return;
  std::string all;
  for (const auto& m : messages_) {
    if (!all.empty()) all += '\n';
    all += m;
  }
  throw InputError(all);
}

}  // namespace barn::core
