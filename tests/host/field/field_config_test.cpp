// FieldConfig: JSON round-trip, validation messages, and the parameter layout (counts, dense
// levels, padding) of the Instant-NGP default shapes.
#include <nlohmann/json.hpp>

#include "field_test_util.h"

using namespace lorgnette::field;

TEST(FieldConfig, JsonRoundTripAndPartialObjects) {
  FieldConfig c = test::odd_config();
  c.finest_resolution = 777;
  EXPECT_EQ(FieldConfig::from_json(c.to_json()), c);
  FieldConfig d = FieldConfig::from_json(nlohmann::json{{"levels", 8}});
  EXPECT_EQ(d.levels, 8u);
  EXPECT_EQ(d.log2_table_size, FieldConfig{}.log2_table_size);
}

TEST(FieldConfig, BadValuesNameTheKey) {
  try {
    FieldConfig::from_json(nlohmann::json{{"sh_degree", 7}});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sh_degree = 7"), std::string::npos) << e.what();
  }
  try {
    FieldConfig::from_json(nlohmann::json{{"levels", "many"}});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'levels'"), std::string::npos) << e.what();
  }
  FieldConfig c;
  c.finest_resolution = 8;  // below base 16
  EXPECT_THROW(c.param_count(), std::invalid_argument);
}

TEST(FieldConfig, DefaultLayoutMatchesInstantNgpShapes) {
  FieldConfig c;
  ParamLayout lay = make_layout(c);
  ASSERT_EQ(lay.levels.size(), 16u);
  EXPECT_EQ(lay.levels[0].resolution, 16u);
  EXPECT_EQ(lay.levels[15].resolution, 2048u);
  // (res + 1)^3 <= 2^19 exactly for res <= 79: levels 0..4 (16, 22, 30, 42, 58) are dense.
  for (int l = 0; l < 16; ++l) EXPECT_EQ(lay.levels[l].dense, l <= 4 ? 1u : 0u) << l;
  EXPECT_EQ(lay.levels[2].size, 31u * 31u * 31u);
  EXPECT_EQ(lay.levels[15].size, 1u << 19);
  // Density 32x64 + 64x16, colour 32x64 + 64x64 + 64x4 (RGB padded to 4 rows).
  EXPECT_EQ(lay.total - lay.mlp_offset, 2048u + 1024u + 2048u + 4096u + 256u);
  EXPECT_EQ(c.param_count(), lay.total);
  EXPECT_EQ(c.bytes(), 4 * lay.total);
  EXPECT_GT(lay.hash_count, 11u * 2u * (1u << 19));
}
