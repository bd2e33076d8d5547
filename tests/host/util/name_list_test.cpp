// Names in messages (host/util/name_list.h): all of a short list, the first few of a long one with
// the count of the rest, nothing for none.
#include "host/util/name_list.h"

#include <gtest/gtest.h>

namespace lorgnette {
namespace {

TEST(NameList, ShortListsWhole) {
  EXPECT_EQ(name_list({}), "");
  EXPECT_EQ(name_list({"a.png"}), "'a.png'");
  EXPECT_EQ(name_list({"a", "b", "c", "d", "e"}), "'a', 'b', 'c', 'd', 'e'");
}

TEST(NameList, LongListsTheFirstFewAndHowManyMore) {
  EXPECT_EQ(name_list({"a", "b", "c", "d", "e", "f", "g"}), "'a', 'b', 'c', 'd', 'e' and 2 more");
  EXPECT_EQ(name_list({"a", "b", "c"}, 1), "'a' and 2 more");
  EXPECT_EQ(name_list({"a", "b"}, 0), " and 2 more");
}

}  // namespace
}  // namespace lorgnette
