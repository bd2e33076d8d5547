// The fused inference kernel (host/field/field_infer.h) against the layered forward the training
// uses, bit for bit: default-width networks, padded widths, deep colour nets, and batch tails that are
// not multiples of 16 or 32 (nothing written past n).
#include "host/field/field_infer.h"

#include <gtest/gtest.h>

#include <cstring>

#include "field_test_util.h"
#include "host/cl/buffer.h"
#include "host/field/field.h"

using namespace lorgnette;
using namespace lorgnette::field;

namespace {

// The default network (16 levels, 64-wide MLPs, SH degree 4) with a small table, so it builds fast.
FieldConfig default_widths() {
  FieldConfig c;
  c.log2_table_size = 12;
  return c;
}

FieldConfig deep_colour() {
  FieldConfig c = test::small_config();
  c.color_hidden_layers = 4;  // hidden layers alternate between the two scratch blocks twice
  c.color_hidden = 36;
  return c;
}

// Runs forward(..., false) (fused) and forward(..., true) (layered) on the same n random samples
// with random hash tables and compares sigma and rgb bit for bit; sigma past n stays untouched.
void expect_fused_equals_layered(const FieldConfig& cfg, uint32_t capacity, const std::vector<uint32_t>& ns) {
  auto& rt = test::runtime();
  Field field(rt, cfg, capacity, 7, true);
  std::vector<float> params = field.download_params();
  auto h = test::random_vector(field.layout().hash_count, 0.5f, 3);
  std::copy(h.begin(), h.end(), params.begin());
  field.upload_params(params);
  const uint32_t S = field.max_batch();
  for (uint32_t n : ns) {
    SCOPED_TRACE("n = " + std::to_string(n));
    ref::Samples s = test::random_samples(n, S, 11 + n);
    cl::Buffer<float> pos(rt, s.pos), dir(rt, s.dir);
    const float sentinel = -12345.0f;
    cl::Buffer<float> sig_fused(rt, std::vector<float>(S, sentinel)), sig_layered(rt, S);
    cl::Buffer<float> rgb_fused(rt, 3 * size_t(S)), rgb_layered(rt, 3 * size_t(S));
    field.forward(pos, dir, n, sig_fused, rgb_fused, false);
    field.forward(pos, dir, n, sig_layered, rgb_layered, true);
    auto a = sig_fused.read(rt), b = sig_layered.read(rt);
    auto ca = rgb_fused.read(rt), cb = rgb_layered.read(rt);
    ASSERT_EQ(0, std::memcmp(a.data(), b.data(), n * sizeof(float))) << "sigma differs";
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(0, std::memcmp(ca.data() + size_t(c) * S, cb.data() + size_t(c) * S, n * sizeof(float)))
          << "rgb channel " << c << " differs";
    for (uint32_t i = n; i < S; ++i) ASSERT_EQ(a[i], sentinel) << "sigma written past n at " << i;
    bool varied = false;  // the comparison means something only if the outputs vary
    for (uint32_t i = 1; i < n; ++i) varied |= a[i] != a[0] || ca[i] != ca[0];
    EXPECT_TRUE(n == 1 || varied);
  }
}

}  // namespace

TEST(FieldInfer, EqualsTheLayeredForwardBitForBit) {
  expect_fused_equals_layered(default_widths(), 1000, {1000, 1, 16, 17, 32, 33, 300});
}

// Padding rows: 3 levels x 2 features padded to 8 encoding rows, 9 SH coefficients padded to 12,
// 15 geo features to 16, hidden widths 30 and 22 to 32 and 24.
TEST(FieldInfer, PaddedWidthsAndDeepColourNetsEqualTheLayeredForward) {
  expect_fused_equals_layered(default_widths(), 256, {256});
  expect_fused_equals_layered(test::odd_config(), 300, {300, 45});
  expect_fused_equals_layered(deep_colour(), 300, {300});
}

TEST(FieldInfer, TooDeepColourNetsUseTheLayeredPath) {
  FieldConfig c = test::small_config();
  c.color_hidden_layers = LGN_INFER_MAX_LAYERS - 1;  // 2 + 8 layers: beyond the fused kernel
  EXPECT_FALSE(FieldInfer::supports(make_layout(c)));
  // A device whose local memory cannot hold one group's scratch gets the layered path too.
  const ParamLayout lay = make_layout(test::small_config());
  EXPECT_TRUE(FieldInfer::supports(lay, FieldInfer::local_bytes(lay)));
  EXPECT_FALSE(FieldInfer::supports(lay, FieldInfer::local_bytes(lay) - 1));
  EXPECT_THROW(make_infer_params(c, make_layout(c), 64), std::invalid_argument);
  expect_fused_equals_layered(c, 64, {64});
}
