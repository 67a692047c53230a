#include <gtest/gtest.h>
TEST(TraceCli, Placeholder) { EXPECT_TRUE(true); }
