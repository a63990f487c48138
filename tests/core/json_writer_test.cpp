#include "barn/core/json_writer.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

namespace barn::core {
namespace {

using Layout = JsonWriter::Layout;

TEST(JsonWriter, WritesNestedValuesOnOneLine) {
  JsonWriter json;
  json.beginObject().key("id").value(7).key("name").value("a \"b\"\n").key("cell").beginArray().value(1).value(2).endArray();
  json.key("none").value(std::numeric_limits<double>::quiet_NaN()).key("big").value(std::uint64_t{18446744073709551615u});
  json.key("ok").value(true).endObject();
  EXPECT_EQ(json.str(), R"({"id": 7, "name": "a \"b\"\n", "cell": [1, 2], "none": null, "big": 18446744073709551615, "ok": true})");
}

TEST(JsonWriter, OneItemPerLineIndentsTwoSpacesPerLevel) {
  JsonWriter json;
  json.beginObject(Layout::OneItemPerLine).key("set").value("test50");
  json.key("rows").beginArray(Layout::OneItemPerLine);
  json.beginObject().key("x").value(0.5).endObject();
  json.beginObject().key("x").value(-1.25).endObject();
  json.endArray();
  json.key("empty").beginArray(Layout::OneItemPerLine).endArray().endObject();
  EXPECT_EQ(json.str(), "{\n  \"set\": \"test50\",\n  \"rows\": [\n    {\"x\": 0.5},\n    {\"x\": -1.25}\n  ],\n"
                        "  \"empty\": [\n  ]\n}");
}

}  // namespace
}  // namespace barn::core
