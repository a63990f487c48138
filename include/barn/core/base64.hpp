#pragma once
/// Base64 (RFC 4648, standard alphabet, '=' padding), for binary data inside JSON messages.

#include <cstdint>
#include <span>
#include <string>

namespace barn::core {

/// The bytes as base64 text: 4 characters per 3 bytes, the last group padded with '='.
std::string base64Encode(std::span<const std::uint8_t> bytes);

}  // namespace barn::core
