// The exit status and the stderr line of a command that failed with an exception
// (util/ExitStatus.hpp): bugs 3 with "internal error, please report", everything else 2.

#include <gtest/gtest.h>

#include <future>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>

#include "clipray/InputError.hpp"
#include "clipray/util/Check.hpp"
#include "clipray/util/ExitStatus.hpp"

namespace clipray {
namespace {

struct Reported {
  int status;
  std::string line;
};

Reported reported(const std::exception& error, std::string_view program = "clipray") {
  std::ostringstream err;
  const int status = reportFailure(error, err, program);
  return {status, err.str()};
}

TEST(ExitStatus, InputErrorIsUnusableInput) {
  const Reported r = reported(InputError("scenes/a.json", "/cameras/0/near", "expected a number"));
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.line, "clipray: scenes/a.json: /cameras/0/near: expected a number\n");
}

TEST(ExitStatus, RuntimeErrorsOfTheEnvironmentAreStatus2) {
  const Reported r = reported(std::runtime_error("cannot write out/report.json: No space left"));
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.line, "clipray: cannot write out/report.json: No space left\n");
  const std::system_error system(std::make_error_code(std::errc::permission_denied), "fork");
  EXPECT_EQ(reported(system).status, 2);
}

TEST(ExitStatus, InternalErrorIsStatus3WithTheCondition) {
  int line = 0;
  try {
    line = __LINE__ + 1;
    CLIPRAY_CHECK(2 < 1, "two runs share a key");
    FAIL() << "no exception";
  } catch (const InternalError& error) {
    const Reported r = reported(error);
    EXPECT_EQ(r.status, 3);
    EXPECT_EQ(r.line, "clipray: internal error, please report: tests/unit/ExitStatusTest.cpp:" +
                          std::to_string(line) + ": 2 < 1: two runs share a key\n");
  }
}

TEST(ExitStatus, LogicErrorsAreBugsToo) {
  const Reported r = reported(std::logic_error("ImageEncoder: run 7 of 3"));
  EXPECT_EQ(r.status, 3);
  EXPECT_EQ(r.line, "clipray: internal error, please report: ImageEncoder: run 7 of 3\n");
  EXPECT_EQ(reported(std::invalid_argument("x")).status, 3);
  EXPECT_EQ(reported(std::out_of_range("x")).status, 3);
  EXPECT_EQ(reported(std::future_error(std::future_errc::no_state)).status, 3);
}

TEST(ExitStatus, TheProgramNamesTheLine) {
  EXPECT_EQ(reported(std::runtime_error("no display"), "clipray-pick").line,
            "clipray-pick: no display\n");
  EXPECT_EQ(reported(std::logic_error("bug"), "clipray-pick").line,
            "clipray-pick: internal error, please report: bug\n");
}

}  // namespace
}  // namespace clipray
