// config::splitFields and config::parseInteger: the strict list and integer reading shared by
// the tools' options, coral_sequence_demo's scan indices and the samples CSV.
#include <gtest/gtest.h>

#include "coral_introspection/config/text_fields.hpp"

namespace coral_introspection {
namespace config {
namespace {

using Fields = std::vector<std::string>;

TEST(TextFields, SplitKeepsEveryEmptyField) {
  EXPECT_EQ(splitFields("1,2,3", ','), (Fields{"1", "2", "3"}));
  EXPECT_EQ(splitFields("1,,2", ','), (Fields{"1", "", "2"}));
  EXPECT_EQ(splitFields("1,2,", ','), (Fields{"1", "2", ""}));  // std::getline: {"1", "2"}
  EXPECT_EQ(splitFields(",1", ','), (Fields{"", "1"}));
  EXPECT_EQ(splitFields(",", ','), (Fields{"", ""}));
  EXPECT_EQ(splitFields("", ','), (Fields{""}));  // std::getline: {}
  EXPECT_EQ(splitFields("a b;c", ';'), (Fields{"a b", "c"}));
}

TEST(TextFields, ParseIntegerTakesWholeDecimalIntegersInRangeOnly) {
  long n = 42;
  EXPECT_TRUE(parseInteger("0", 0, 10, &n));
  EXPECT_EQ(n, 0);
  EXPECT_TRUE(parseInteger("-7", -10, 10, &n));
  EXPECT_EQ(n, -7);
  EXPECT_TRUE(parseInteger("10", 0, 10, &n));
  EXPECT_EQ(n, 10);
  n = 42;
  for (const char* bad : {"", "-", " 5", "5 ", "+5", "5x", "2.5", "1e3", "0x10", "--1"})
    EXPECT_FALSE(parseInteger(bad, -100, 100, &n)) << "'" << bad << "'";
  EXPECT_FALSE(parseInteger("11", 0, 10, &n));
  EXPECT_FALSE(parseInteger("-1", 0, 10, &n));
  EXPECT_FALSE(parseInteger("99999999999999999999", 0, 1000000000, &n));  // ERANGE
  EXPECT_EQ(n, 42);                                                       // unchanged on refusal
}

}  // namespace
}  // namespace config
}  // namespace coral_introspection
