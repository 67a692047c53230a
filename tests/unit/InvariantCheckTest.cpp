// CLIPRAY_CHECK and CLIPRAY_DCHECK (util/Check.hpp): a broken invariant throws InternalError
// naming the file (relative to the source tree), the line, the condition and the message.

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "clipray/InputError.hpp"
#include "clipray/util/Check.hpp"

namespace clipray {
namespace {

// The text a failed check throws, with the line it failed on.
std::string failureText(int value, int& line) {
  try {
    line = __LINE__ + 1;
    CLIPRAY_CHECK(value > 1 && value < 10, "value " + std::to_string(value) + " out of range");
  } catch (const InternalError& error) {
    return error.what();
  }
  return "no exception";
}

TEST(InvariantCheck, AHeldCheckDoesNothing) {
  int line = 0;
  EXPECT_EQ(failureText(5, line), "no exception");
}

TEST(InvariantCheck, AFailedCheckNamesFileLineConditionAndMessage) {
  int line = 0;
  const std::string what = failureText(12, line);
  EXPECT_EQ(what, "tests/unit/InvariantCheckTest.cpp:" + std::to_string(line) +
                      ": value > 1 && value < 10: value 12 out of range");
}

TEST(InvariantCheck, AnEmptyMessageLeavesTheConditionLast) {
  int line = 0;
  try {
    line = __LINE__ + 1;
    CLIPRAY_CHECK(1 + 1 == 3, "");
    FAIL() << "no exception";
  } catch (const InternalError& error) {
    EXPECT_EQ(std::string(error.what()),
              "tests/unit/InvariantCheckTest.cpp:" + std::to_string(line) + ": 1 + 1 == 3");
  }
}

TEST(InvariantCheck, InternalErrorIsALogicErrorNotAnInputError) {
  bool caughtAsInput = false, caughtAsLogic = false;
  try {
    CLIPRAY_CHECK(false, "a bug");
  } catch (const InputError&) {
    caughtAsInput = true;
  } catch (const std::logic_error&) {
    caughtAsLogic = true;
  }
  EXPECT_FALSE(caughtAsInput);
  EXPECT_TRUE(caughtAsLogic);
}

TEST(InvariantCheck, TheMessageIsBuiltOnlyOnFailure) {
  int built = 0;
  const auto message = [&] {
    ++built;
    return std::string("built");
  };
  CLIPRAY_CHECK(true, message());
  EXPECT_EQ(built, 0);
  EXPECT_THROW(CLIPRAY_CHECK(false, message()), InternalError);
  EXPECT_EQ(built, 1);
}

TEST(InvariantCheck, DebugChecksRunOnlyWithoutNdebug) {
  int evaluated = 0;
  const auto fails = [&] {
    ++evaluated;
    return false;
  };
#ifdef NDEBUG
  EXPECT_NO_THROW(CLIPRAY_DCHECK(fails(), "not checked"));
  EXPECT_EQ(evaluated, 0);
#else
  EXPECT_THROW(CLIPRAY_DCHECK(fails(), "checked"), InternalError);
  EXPECT_EQ(evaluated, 1);
#endif
}

}  // namespace
}  // namespace clipray
