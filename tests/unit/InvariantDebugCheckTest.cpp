// CLIPRAY_DCHECK where NDEBUG is not defined. Every preset defines it, so this file undefines it
// before its first include: the debug checks of this file alone are compiled in.

#undef NDEBUG

#include <gtest/gtest.h>

#include <string>

#include "clipray/util/Check.hpp"

namespace clipray {
namespace {

TEST(InvariantDebugCheck, ChecksWithoutNdebugAndNamesTheCondition) {
  int evaluated = 0;
  const auto fails = [&] {
    ++evaluated;
    return false;
  };
  int line = 0;
  try {
    line = __LINE__ + 1;
    CLIPRAY_DCHECK(fails(), "a debug check");
    FAIL() << "no exception";
  } catch (const InternalError& error) {
    EXPECT_EQ(std::string(error.what()), "tests/unit/InvariantDebugCheckTest.cpp:" +
                                             std::to_string(line) + ": fails(): a debug check");
  }
  EXPECT_EQ(evaluated, 1);
  EXPECT_NO_THROW(CLIPRAY_DCHECK(evaluated == 1, "held"));
}

}  // namespace
}  // namespace clipray
