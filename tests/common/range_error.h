// The text of the OutOfRange a call throws ("" when it throws none), and EXPECT_HAS for a part of
// it: the bounds tests check that each refusal names the flag, the Python argument and the range.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "host/util/bounds.h"

#define EXPECT_HAS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

namespace lorgnette::testing {

template <class F>
std::string range_error(F&& f) {
  try {
    f();
  } catch (const OutOfRange& e) {
    return e.what();
  }
  return "";
}

}  // namespace lorgnette::testing
