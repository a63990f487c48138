#include "barn/core/base64.hpp"

#include <gtest/gtest.h>

#include <string_view>

namespace barn::core {
namespace {

std::string encode(std::string_view text) {
  return base64Encode({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
}

TEST(Base64, EncodesTheRfc4648TestVectors) {
  // RFC 4648, section 10.
  EXPECT_EQ(encode(""), "");
  EXPECT_EQ(encode("f"), "Zg==");
  EXPECT_EQ(encode("fo"), "Zm8=");
  EXPECT_EQ(encode("foo"), "Zm9v");
  EXPECT_EQ(encode("foob"), "Zm9vYg==");
  EXPECT_EQ(encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(encode("foobar"), "Zm9vYmFy");
}

TEST(Base64, UsesTheStandardAlphabetForHighBytes) {
  // 0xFB 0xFF 0xBF: 111110 111111 111110 111111 -> + / + /
  const std::uint8_t bytes[] = {0xFB, 0xFF, 0xBF};
  EXPECT_EQ(base64Encode(bytes), "+/+/");
}

}  // namespace
}  // namespace barn::core
