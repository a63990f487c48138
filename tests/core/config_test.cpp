#include "barn/core/config.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

namespace barn::core {
namespace {

using ::testing::HasSubstr;

struct Inner {
  double offset = 0.04;  // [m]
  bool enabled = true;
  template <class V> void visit(V& v) { v("offset", offset); v("enabled", enabled); }
};

struct Outer {
  int beams = 720;
  std::string name = "fi";
  std::vector<double> speeds = {0.5, 1.0};
  std::vector<std::string> command = {"python3", "ctrl.py"};
  Inner safety;
  template <class V> void visit(V& v) {
    v("beams", beams); v("name", name); v("speeds", speeds); v("command", command); v("safety", safety);
  }
};

enum class Shape { Box, Disc };
std::span<const std::string_view> enumNames(Shape) {
  static constexpr std::string_view kNames[] = {"box", "disc"};
  return kNames;
}

struct WithEnum {
  Shape shape = Shape::Box;
  template <class V> void visit(V& v) { v("shape", shape); }
};

std::string errorOf(const std::string& yaml) {
  try {
    readConfig<Outer>(ConfigNode::parseString(yaml, "test.yaml"));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, MissingKeysKeepDefaults) {
  const Outer config = readConfig<Outer>(ConfigNode::parseString("beams: 360\nsafety: {offset: 0.1}", "test.yaml"));
  EXPECT_EQ(config.beams, 360);
  EXPECT_EQ(config.name, "fi");
  EXPECT_EQ(config.safety.offset, 0.1);
  EXPECT_TRUE(config.safety.enabled);
}

TEST(Config, AnEmptyFileGivesTheDefaults) {
  const Outer config = readConfig<Outer>(ConfigNode::parseString("", "empty.yaml"));
  EXPECT_EQ(config.beams, 720);
}

TEST(Config, UnknownKeysNameTheirFullPath) {
  EXPECT_THAT(errorOf("safety: {ofset: 0.1}"), HasSubstr("test.yaml: safety.ofset: unknown key (known: offset, enabled)"));
  EXPECT_THAT(errorOf("beam: 3"), HasSubstr("test.yaml: beam: unknown key"));
}

TEST(Config, WrongTypesNameTheField) {
  EXPECT_THAT(errorOf("beams: many"), HasSubstr("test.yaml: beams: expected an integer, got 'many'"));
  EXPECT_THAT(errorOf("beams: 3.5"), HasSubstr("beams: expected an integer"));
  EXPECT_THAT(errorOf("safety: {enabled: yes}"), HasSubstr("safety.enabled: expected true or false"));
  EXPECT_THAT(errorOf("safety: 3"), HasSubstr("safety: expected a map"));
  EXPECT_THAT(errorOf("speeds: [1, x]"), HasSubstr("speeds: expected a list of numbers"));
  EXPECT_THAT(errorOf("safety: {offset: .nan}"), HasSubstr("safety.offset: expected a finite number"));
}

TEST(Config, AStringListMustHoldOnlyStrings) {
  EXPECT_THAT(errorOf("command: [python3, {a: 1}]"), HasSubstr("test.yaml: command: expected a list of strings"));
  EXPECT_THAT(errorOf("command: python3"), HasSubstr("command: expected a list of strings"));
}

TEST(Config, DuplicateKeysAreErrors) {
  EXPECT_THAT(errorOf("beams: 1\nbeams: 2"), HasSubstr("beams: duplicate key"));
}

TEST(Config, ReportsEveryErrorAtOnce) {
  const std::string message = errorOf("beams: x\nsafety: {offset: y, colour: red}");
  EXPECT_THAT(message, HasSubstr("beams: expected an integer"));
  EXPECT_THAT(message, HasSubstr("safety.offset: expected a finite number"));
  EXPECT_THAT(message, HasSubstr("safety.colour: unknown key"));
}

TEST(Config, MalformedYamlNamesTheFile) {
  EXPECT_THAT(errorOf("beams: [1, 2"), HasSubstr("test.yaml: not valid YAML"));
  EXPECT_THAT(errorOf("- 1\n- 2"), HasSubstr("expected a map"));
}

TEST(Config, MalformedYamlNamesTheLine) {
  // The unclosed list runs to the end of the text, where yaml-cpp notices (line 2).
  EXPECT_THAT(errorOf("beams: 3\nspeeds: [1, 2"), HasSubstr("test.yaml: not valid YAML: line 2"));
}

TEST(Config, AKeyThatIsAListNamesTheFileAndLine) {
  EXPECT_THAT(errorOf("beams: 3\n[1]: 2"),
              HasSubstr("test.yaml: line 2: a key is a list or a map, expected a plain name"));
  EXPECT_THAT(errorOf("safety:\n  ? {a: 1}\n  : 2"),
              HasSubstr("test.yaml: line 2: a key in safety is a list or a map, expected a plain name"));
}

TEST(Config, AKeyThatIsAListDoesNotHideTheOtherErrors) {
  const std::string message = errorOf("beams: x\n[1]: 2");
  EXPECT_THAT(message, HasSubstr("beams: expected an integer"));
  EXPECT_THAT(message, HasSubstr("line 2: a key is a list or a map"));
}

TEST(Config, KeysOfAMapWithAListKeyIsAnInputError) {
  const ConfigNode node = ConfigNode::parseString("? [1, 2]\n: 3", "test.yaml");
  EXPECT_THROW(node.keys(), InputError);
}

TEST(Config, OverridesSetNestedKeys) {
  ConfigNode node = ConfigNode::parseString("beams: 360", "test.yaml");
  node.set("safety.offset", "0.08");
  node.set("name", "mpc");
  const Outer config = readConfig<Outer>(node);
  EXPECT_EQ(config.beams, 360);
  EXPECT_EQ(config.safety.offset, 0.08);
  EXPECT_EQ(config.name, "mpc");
}

TEST(Config, WritingAndReadingBackGivesTheSameStruct) {
  Outer config;
  config.beams = 100;
  config.name = "with: colon";
  config.speeds = {0.1, 0.30000000000000004};
  config.command = {"/usr/bin/python3", "-u", "a b.py", "", "[x]", "key: value"};
  config.safety.offset = 1.0 / 3.0;
  config.safety.enabled = false;
  const std::string text = writeConfig(config);
  const Outer back = readConfig<Outer>(ConfigNode::parseString(text, "written.yaml"));
  EXPECT_EQ(back.beams, 100);
  EXPECT_EQ(back.name, "with: colon");
  EXPECT_EQ(back.speeds, config.speeds);
  EXPECT_EQ(back.command, config.command);
  EXPECT_EQ(back.safety.offset, 1.0 / 3.0);  // exact: shortest round-trip formatting
  EXPECT_FALSE(back.safety.enabled);
  EXPECT_EQ(writeConfig(back), text);
}

}  // namespace
}  // namespace barn::core

namespace barn::core {
namespace {

TEST(Config, AnEnumIsReadAndWrittenByName) {
  const WithEnum read = readConfig<WithEnum>(ConfigNode::parseString("shape: disc", "test.yaml"));
  EXPECT_EQ(read.shape, Shape::Disc);
  EXPECT_EQ(enumName(read.shape), "disc");
  EXPECT_EQ(writeConfig(read), writeConfig(readConfig<WithEnum>(ConfigNode::parseString(writeConfig(read), "back.yaml"))));
  EXPECT_EQ(readConfig<WithEnum>(ConfigNode::parseString(writeConfig(read), "back.yaml")).shape, Shape::Disc);
  try {
    readConfig<WithEnum>(ConfigNode::parseString("shape: cube", "test.yaml"));
    FAIL() << "an unknown name must be an error";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("test.yaml: shape"));
    EXPECT_THAT(std::string(e.what()), HasSubstr("expected one of box, disc"));
  }
}

}  // namespace
}  // namespace barn::core

namespace barn::core {
namespace {

// A pair written [a, b]: a field type that reads itself.
struct Pair {
  int a = 0, b = 0;
};
void readConfigValue(const ConfigNode& node, Pair& pair, Errors& errors) {
  if (node.size() != 2 || !node.element(0).read(pair.a) || !node.element(1).read(pair.b))
    errors.add(node.where(), "expected [a, b]");
}

struct WithPair {
  Pair pair;
  int count = 3;
  template <class V> void visit(V& v) { v("pair", pair); v("count", count); }
};

std::string requiredErrorOf(const std::string& yaml) {
  Errors errors;
  WithPair config;
  ConfigReader reader(ConfigNode::parseString(yaml, "test.yaml"), errors, MissingKeys::Error);
  config.visit(reader);
  reader.finish();
  std::string all;
  for (const auto& m : errors.messages()) all += m + "\n";
  return all;
}

TEST(Config, ATypeThatReadsItselfGetsItsNode) {
  const WithPair read = readConfig<WithPair>(ConfigNode::parseString("pair: [4, 5]", "test.yaml"));
  EXPECT_EQ(read.pair.a, 4);
  EXPECT_EQ(read.pair.b, 5);
  try {
    readConfig<WithPair>(ConfigNode::parseString("pair: [4, x]", "test.yaml"));
    FAIL() << "a malformed pair must be an error";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("test.yaml: pair: expected [a, b]"));
  }
}

TEST(Config, WithMissingKeysAnErrorEveryFieldIsRequired) {
  EXPECT_EQ(requiredErrorOf("pair: [1, 2]\ncount: 4"), "");
  EXPECT_EQ(requiredErrorOf("pair: [1, 2]"), "test.yaml: count: missing\n");
}

TEST(Config, SequenceSizeCountsElements) {
  const ConfigNode root = ConfigNode::parseString("list: [[1, 2], [3]]\nmap: {a: 1}", "test.yaml");
  EXPECT_TRUE(root.child("list").isSequence());
  EXPECT_EQ(root.child("list").size(), 2u);
  EXPECT_EQ(root.child("list").element(1).size(), 1u);
  EXPECT_FALSE(root.child("map").isSequence());
  EXPECT_EQ(root.child("map").size(), 0u);  // not a sequence
}

}  // namespace
}  // namespace barn::core

namespace barn::core {
namespace {

struct Item {
  std::string name;
  std::vector<double> sizes;
  template <class V> void visit(V& v) { v("name", name); v("sizes", sizes); }
};

struct WithList {
  std::vector<Item> items;
  int count = 0;
  template <class V> void visit(V& v) { v("items", items); v("count", count); }
};

TEST(Config, AListOfStructsIsWrittenAsABlockListAndReadBack) {
  WithList list;
  list.items = {{"a", {1.0, 2.5}}, {"b", {}}};
  list.count = 2;
  const std::string text = writeConfig(list);
  EXPECT_EQ(text, "items:\n  - name: a\n    sizes: [1, 2.5]\n  - name: b\n    sizes: []\ncount: 2\n");
  const WithList back = readConfig<WithList>(ConfigNode::parseString(text, "list.yaml"));
  ASSERT_EQ(back.items.size(), 2u);
  EXPECT_EQ(back.items[0].name, "a");
  EXPECT_EQ(back.items[0].sizes, (std::vector<double>{1.0, 2.5}));
  EXPECT_EQ(back.items[1].name, "b");
  EXPECT_EQ(writeConfig(back), text);
  EXPECT_EQ(writeConfig(WithList{}), "items: []\ncount: 0\n");
}

TEST(Config, AMalformedListElementIsAnErrorNamingIt) {
  try {
    readConfig<WithList>(ConfigNode::parseString("items:\n  - name: a\n  - 4\n  - nmae: c\n", "list.yaml"));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("list.yaml: items[1]: expected a map"));
    EXPECT_THAT(std::string(e.what()), HasSubstr("list.yaml: items[2].nmae: unknown key"));
  }
}

TEST(Config, ASecondDocumentIsRefusedNotDropped) {
  EXPECT_THAT([] { ConfigNode::parseString("beams: 1\n---\nbeams: 2\n", "t.yaml"); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("t.yaml: line 2: a second YAML document")));
  // Text after the end marker is parsed too: invalid text is an error, not ignored.
  EXPECT_THROW(ConfigNode::parseString("beams: 1\n...\ngarbage: [\n", "t.yaml"), InputError);
  EXPECT_EQ(readConfig<Outer>(ConfigNode::parseString("beams: 3\n...\n", "t.yaml")).beams, 3);
  EXPECT_TRUE(ConfigNode::parseString("# only a comment\n", "t.yaml").isNull());
}

TEST(Config, IntegersAreReadExactlyNeverWrappedOrSaturated) {
  std::uint64_t u = 7;
  int i = 7;
  for (const char* bad : {"\" -1\"", "\"+5\"", "\"5 \"", "0x10", "18446744073709551616", "1.0", "1e3"}) {
    EXPECT_FALSE(ConfigNode::parseString(std::string("v: ") + bad, "t").child("v").read(u)) << bad;
    EXPECT_FALSE(ConfigNode::parseString(std::string("v: ") + bad, "t").child("v").read(i)) << bad;
  }
  EXPECT_TRUE(ConfigNode::parseString("v: 18446744073709551615", "t").child("v").read(u));
  EXPECT_EQ(u, 18446744073709551615ull);
  EXPECT_FALSE(ConfigNode::parseString("v: 2147483648", "t").child("v").read(i));  // INT_MAX + 1
  EXPECT_TRUE(ConfigNode::parseString("v: -2147483648", "t").child("v").read(i));
  EXPECT_EQ(i, -2147483647 - 1);
}

TEST(Config, TextThatIsNotYamlTextIsRefusedNamingTheLine) {
  // Bytes no writer could give back: a control character, invalid or overlong UTF-8, a C1
  // control, a surrogate. UTF-8 text (and a BOM) reads.
  const std::vector<std::string> bad_texts = {"a: 1\nb: \x01\n", "a: 1\nb: \xff\n", "a: 1\nb: \xc0\xaf\n",
                                             "a: 1\nb: \xc2\x90\n", "a: 1\nb: \xed\xa0\x80\n", "a: 1\nb: \x7f\n"};
  for (const std::string& bad : bad_texts)
    EXPECT_THAT([&] { ConfigNode::parseString(bad, "t.yaml"); },
                ::testing::ThrowsMessage<InputError>(HasSubstr("t.yaml: line 2: not YAML text"))) << bad;
  EXPECT_NO_THROW(ConfigNode::parseString("\xef\xbb\xbf" "name: \xc3\xa9t\xc3\xa9\r\nx: \"a\tb\"\n", "t.yaml").isMap());
}

TEST(Config, AnEmptyKeyIsNamedAsSuch) {
  EXPECT_THAT(errorOf("~: 2\n"), HasSubstr("test.yaml: line 1: a key is empty"));
}

// A struct whose fields carry their schema in visit().
struct WithSchema {
  double speed = 0.5;
  int samples = 6;
  double share = 0.25;
  std::vector<double> gains = {1.0, 2.0};
  Shape shape = Shape::Box;
  Inner inner;  // no schema: its own validate() would check it
  template <class V> void visit(V& v) {
    v("speed", speed, {.unit = "m/s", .range = kPositive, .doc = "forward speed"});
    v("samples", samples, {.range = atLeast(2), .doc = "speeds sampled"});
    v("share", share, {.range = kUnit});
    v("gains", gains, {.unit = "1/s", .range = kNonNegative});
    v("shape", shape, {.doc = "outline"});
    v("inner", inner);
  }
};

std::vector<std::string> fieldErrors(const WithSchema& config) {
  Errors errors;
  validateFields(config, errors, "c.yaml: block");
  return errors.messages();
}

TEST(ConfigSchema, ARangeViolationNamesTheKeyTheRangeAndTheUnit) {
  WithSchema config;
  config.speed = -1.0;
  EXPECT_THAT(fieldErrors(config), ::testing::ElementsAre("c.yaml: block.speed: must be > 0 m/s, got -1 m/s"));
  config = WithSchema{};
  config.samples = 1;    // >= 2, dimensionless
  config.share = 1.5;    // in [0, 1]
  config.gains[1] = -2;  // each element >= 0
  EXPECT_THAT(fieldErrors(config), ::testing::ElementsAre("c.yaml: block.samples: must be >= 2, got 1",
                                                          "c.yaml: block.share: must be in [0, 1], got 1.5",
                                                          "c.yaml: block.gains[1]: must be >= 0 1/s, got -2 1/s"));
  // Not-a-number is outside every bounded range.
  config = WithSchema{};
  config.speed = std::nan("");
  EXPECT_THAT(fieldErrors(config), ::testing::SizeIs(1));
  EXPECT_THAT(fieldErrors(WithSchema{}), ::testing::IsEmpty());
}

TEST(ConfigSchema, RangesReadAsTheyAreWritten) {
  EXPECT_EQ(kPositive.text(), "> 0");
  EXPECT_EQ(atMost(1.5).text(), "<= 1.5");
  EXPECT_EQ(below(0).text(), "< 0");
  EXPECT_EQ(openClosed(0, 1).text(), "in (0, 1]");
  EXPECT_EQ(Range{}.text(), "");
  // Ends: (0, 1] holds 1 and not 0.
  EXPECT_TRUE(openClosed(0, 1).contains(1.0));
  EXPECT_FALSE(openClosed(0, 1).contains(0.0));
}

TEST(ConfigSchema, TheSchemaListsEveryFieldWithValueUnitRangeAndDoc) {
  const std::vector<FieldRow> rows = schemaOf(WithSchema{});
  ASSERT_EQ(rows.size(), 7u);  // five fields, and Inner's two flattened
  EXPECT_EQ(rows[0].key, "speed");
  EXPECT_EQ(rows[0].value, "0.5");
  EXPECT_EQ(rows[0].unit, "m/s");
  EXPECT_EQ(rows[0].range, "> 0");
  EXPECT_EQ(rows[0].doc, "forward speed");
  EXPECT_EQ(rows[3].value, "[1, 2]");
  EXPECT_EQ(rows[4].value, "box");
  EXPECT_EQ(rows[4].range, "one of box, disc");
  EXPECT_EQ(rows[5].key, "inner.offset");
  EXPECT_EQ(rows[5].unit, "");
}

TEST(ConfigSchema, TheReaderAndWriterIgnoreTheSchema) {
  WithSchema config = readConfig<WithSchema>(ConfigNode::parseString("speed: -3\nshape: disc\n", "c.yaml"));
  EXPECT_EQ(config.speed, -3.0);  // reading does not check ranges; validateFields does
  EXPECT_EQ(config.shape, Shape::Disc);
  EXPECT_EQ(writeConfig(config),
            "speed: -3\nsamples: 6\nshare: 0.25\ngains: [1, 2]\nshape: disc\ninner:\n  offset: 0.04\n  enabled: true\n");
}

}  // namespace
}  // namespace barn::core
