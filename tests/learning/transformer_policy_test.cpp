#include "barn/learning/transformer_policy.hpp"


#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "barn/core/errors.hpp"
#include "barn/core/text_io.hpp"
#include "tests/scratch_dir.hpp"

namespace barn::learning {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using test::ScratchDir;

// Written by tools/make_lics_test_data.py: a random network of the LiCS architecture (720 beams
// in 36 patches, width 32, 4 heads; feed-forward 48, 2 + 2 blocks), and torch's outputs for it.
const fs::path kData = fs::path(BARN_SOURCE_DIR) / "tests" / "data";
const fs::path kSmall = kData / "lics_transformer_small.policy";

struct TorchCase {
  Eigen::Vector2d goal;
  Eigen::Vector2d expected;  // torch's (v_hat, w_hat)
  core::LaserScan scan;
};

std::vector<TorchCase> torchCases() {
  std::istringstream in(core::readTextFile(kData / "lics_transformer_small_cases.txt"));
  std::vector<TorchCase> cases;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<double> values;
    for (std::string field; fields >> field;) {
      double value = 0.0;
      EXPECT_TRUE(core::parseDouble(field, value)) << field;
      values.push_back(value);
    }
    EXPECT_EQ(values.size(), 4u + 720u);
    TorchCase c;
    c.goal = {values[0], values[1]};
    c.expected = {values[2], values[3]};
    c.scan.ranges.assign(values.begin() + 4, values.end());
    cases.push_back(c);
  }
  return cases;
}

TEST(TransformerPolicy, ForwardPassEqualsTorchOnTheCommittedCases) {
  const TransformerPolicy policy = TransformerPolicy::load(kSmall);
  EXPECT_EQ(policy.info().shape.ffn_dim, 48);
  EXPECT_EQ(policy.info().shape.encoder_layers, 2);
  EXPECT_EQ(policy.info().range_clip, 5.0);
  const std::vector<TorchCase> cases = torchCases();
  ASSERT_EQ(cases.size(), 6u);
  double worst = 0.0;
  for (const TorchCase& c : cases) {
    const Eigen::Vector2d y = policy.act(c.scan, c.goal);
    worst = std::max(worst, (y - c.expected).cwiseAbs().maxCoeff());
  }
  // float32 both sides, summed in other orders: they agree to rounding.
  EXPECT_LT(worst, 1e-5);
  // The cases are not all alike (outputs that differ by far more than the tolerance).
  EXPECT_GT((cases[0].expected - cases[1].expected).cwiseAbs().maxCoeff(), 0.01);
}

TEST(TransformerPolicy, RangesPastTheClipAndNoReturnReadAsTheClip) {
  const TransformerPolicy policy = TransformerPolicy::load(kSmall);
  core::LaserScan at_clip, beyond;
  at_clip.ranges.assign(720, 5.0);
  beyond.ranges.assign(720, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < 720; i += 3) beyond.ranges[i] = 17.0;
  beyond.ranges[5] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(policy.act(beyond, {1.0, 0.0}), policy.act(at_clip, {1.0, 0.0}));
  // The goal is taken as given: its length matters (LiCS feeds a unit vector, or (0, 0)).
  EXPECT_NE(policy.act(at_clip, {2.0, 0.0}), policy.act(at_clip, {1.0, 0.0}));
}

TEST(TransformerPolicy, AScanWithTheWrongBeamCountIsAnInputError) {
  const TransformerPolicy policy = TransformerPolicy::load(kSmall);
  core::LaserScan scan;
  scan.ranges.assign(360, 1.0);
  EXPECT_THROW(policy.act(scan, {1.0, 0.0}), core::InputError);
}

TEST(TransformerPolicyFile, WritingTheLoadedFileGivesTheImportersBytes) {
  // tools/import_lics_weights.py wrote the file; barnbench's writer gives the same bytes, so a
  // digest of a converted file means the same to both.
  const std::string file = core::readTextFile(kSmall);
  const TransformerPolicy policy = TransformerPolicy::parse(file, "small");
  EXPECT_EQ(transformerPolicyBytes(policy.info(), policy.network().weights()), file);
  const ScratchDir scratch("barn_transformer_policy_roundtrip");
  writeTransformerPolicyFile(scratch.path() / "back.policy", policy.info(), policy.network().weights());
  EXPECT_EQ(core::readTextFile(scratch.path() / "back.policy"), file);
}

TEST(TransformerPolicyFile, TheFuzzSeedLoads) {
  const TransformerPolicy tiny =
      TransformerPolicy::load(fs::path(BARN_SOURCE_DIR) / "tests" / "fuzz" / "seeds" / "policy" / "tiny_transformer.policy");
  EXPECT_EQ(tiny.info().shape.beams, 8);
  EXPECT_EQ(tiny.info().shape.model_dim, 4);
}

// Every way a file can be wrong, each with the message that names it.
class TransformerPolicyErrors : public ::testing::Test {
 protected:
  void SetUp() override { good_ = core::readTextFile(kSmall); }
  std::string errorOf(const std::string& content) const {
    try {
      TransformerPolicy::parse(content, "bad.policy");
    } catch (const core::InputError& e) {
      return e.what();
    }
    return "no error";
  }
  std::string replaced(const std::string& from, const std::string& to) const {
    std::string text = good_;
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    return text;
  }
  std::size_t payload() const { return good_.find("end_header\n") + 11; }
  std::string good_;
};

TEST_F(TransformerPolicyErrors, WrongMagic) {
  EXPECT_THAT(errorOf(core::readTextFile(fs::path(BARN_SOURCE_DIR) / "configs" / "policies" / "lflh_1ms.policy")),
              HasSubstr("bad.policy: wrong magic: the first line must be 'format: barnbench-transformer-policy' (not a "
                        "transformer policy file)"));
  EXPECT_THAT(errorOf(""), HasSubstr("wrong magic"));
}

TEST_F(TransformerPolicyErrors, TruncatedOrTrailingBytesNameTheTensor) {
  // Payload 4 x 31522 = 126088 bytes; the last tensor, prediction_head.bias, is 2 floats.
  EXPECT_THAT(errorOf(good_.substr(0, good_.size() - 4)),
              HasSubstr("truncated: expected 126088 bytes of weights, found 126084 (the file ends in tensor prediction_head.bias)"));
  // Cut inside the first tensor (32 x 20 floats = 2560 bytes).
  EXPECT_THAT(errorOf(good_.substr(0, payload() + 100)), HasSubstr("ends in tensor encoder.embedding.linear.weight"));
  EXPECT_THAT(errorOf(good_.substr(0, good_.find("end_header"))), HasSubstr("truncated header"));
  EXPECT_THAT(errorOf(good_ + "xx"), HasSubstr("2 bytes after the weights"));
}

TEST_F(TransformerPolicyErrors, WrongShape) {
  EXPECT_THAT(errorOf(replaced("heads: 4\n", "heads: 5\n")), HasSubstr("bad.policy: wrong shape: heads 5 does not divide model_dim 32"));
  EXPECT_THAT(errorOf(replaced("ffn_dim: 48\n", "ffn_dim: 256\n")),
              HasSubstr("wrong shape: payload_bytes 126088 does not match the shape"));
  EXPECT_THAT(errorOf(replaced("model_dim: 32\n", "model_dim: 5000\n")),
              HasSubstr("header: model_dim '5000': expected an integer in [1, 4096]"));
}

TEST_F(TransformerPolicyErrors, HeaderContractFields) {
  EXPECT_THAT(errorOf(replaced("version: 1\n", "version: 2\n")), HasSubstr("unsupported version 2 (this build reads versions 1 to 1)"));
  EXPECT_THAT(errorOf(replaced("scores q.k / sqrt(model_dim)", "scores q.k / sqrt(head_dim)")), HasSubstr("header: attention is"));
  EXPECT_THAT(errorOf(replaced("output: v_hat, w_hat", "output: v, w")), HasSubstr("header: output is"));
  EXPECT_THAT(errorOf(replaced("source: ", "origin: ")), HasSubstr("unknown key 'origin'"));
  EXPECT_THAT(errorOf(replaced("range_clip: 5\n", "")), HasSubstr("missing key 'range_clip'"));
  EXPECT_THAT(errorOf(replaced("range_clip: 5\n", "range_clip: 0\n")), HasSubstr("range_clip must be > 0"));
  EXPECT_THAT(errorOf(replaced("layer_norm_eps: 1e-05\n", "layer_norm_eps: 0\n")), HasSubstr("wrong shape: layer_norm_eps must be > 0"));
}

TEST_F(TransformerPolicyErrors, AnAlteredOrNonFiniteWeightIsRefused) {
  // One bit of the last weight flipped: finite, but not the weights the header's digest names.
  std::string altered = good_;
  altered[altered.size() - 1] ^= 0x01;
  EXPECT_THAT(errorOf(altered), HasSubstr("weights: their FNV-1a 64 digest is 0x"));
  // A NaN in the position embedding (after the 32 x 20 + 32 floats before it) names its tensor.
  std::string nan = good_;
  const float value = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(nan.data() + payload() + 4 * (32 * 20 + 32), &value, 4);
  EXPECT_THAT(errorOf(nan), HasSubstr("weights: tensor encoder.embedding.pos_embed holds a non-finite value"));
}

TEST_F(TransformerPolicyErrors, AHugeShapeInAShortFileIsRefusedBeforeAllocating) {
  // 64 + 64 blocks of width 4096 and feed-forward 65536 claim 4 x 77 G floats: refused on the
  // payload size, before any allocation.
  std::string text = replaced("model_dim: 32\n", "model_dim: 4096\n");
  text.replace(text.find("ffn_dim: 48\n"), 12, "ffn_dim: 65536\n");
  text.replace(text.find("encoder_layers: 2\n"), 18, "encoder_layers: 64\n");
  EXPECT_THAT(errorOf(text), HasSubstr("wrong shape: payload_bytes 126088 does not match the shape"));
  // The same with payload_bytes to match: the file's 126088 bytes end inside the first tensor
  // (4096 x 20 floats), and the message names it, still without allocating the network.
  TransformerShape huge;
  huge.model_dim = 4096;
  huge.ffn_dim = 65536;
  huge.encoder_layers = 64;
  huge.decoder_layers = 2;
  const std::string bytes = std::to_string(4 * huge.parameterCount());
  text.replace(text.find("payload_bytes: 126088"), 21, "payload_bytes: " + bytes);
  EXPECT_THAT(errorOf(text), HasSubstr("truncated: expected " + bytes +
                                       " bytes of weights, found 126088 (the file ends in tensor encoder.embedding.linear.weight)"));
}

TEST(TransformerPolicyLoad, AFolderOrADeviceIsRefusedNamingIt) {
  const ScratchDir scratch("barn_transformer_policy_folder");
  EXPECT_THROW(TransformerPolicy::load(scratch.path()), core::InputError);
  EXPECT_THROW(TransformerPolicy::load("/dev/zero"), core::InputError);
  EXPECT_THROW(TransformerPolicy::load("/nonexistent/x.policy"), core::InputError);
}

}  // namespace
}  // namespace barn::learning
