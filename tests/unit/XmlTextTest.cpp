// The one escaping of the report's markup files (JUnit XML, index.html).

#include <gtest/gtest.h>

#include "clipray/io/XmlText.hpp"

namespace clipray {
namespace {

TEST(XmlText, EscapesWhatXmlReservesAndDropsWhatItForbids) {
  EXPECT_EQ(xmlEscaped("a&b<c>d\"e'f"), "a&amp;b&lt;c&gt;d&quot;e&apos;f");
  EXPECT_EQ(xmlEscaped(std::string("t\tn\nr\rx\x01y\x1f", 10)), "t\tn\nr\rx?y?");
  EXPECT_EQ(xmlEscaped("caf\xc3\xa9"), "caf\xc3\xa9");  // UTF-8 passes through
  EXPECT_EQ(xmlEscaped(""), "");
}

}  // namespace
}  // namespace clipray
