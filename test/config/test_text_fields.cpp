// config::splitFields, config::parseInteger and config::parseFiniteNumber: the strict list and
// number reading shared by the tools' options, coral_sequence_demo's scan indices, the samples
// CSV, the Oxford ground truth and CARMEN's ROBOTLASER1 lines.
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

TEST(TextFields, ParseFiniteNumberTakesWholeFiniteNumbersOnly) {
  double x = 42.0;
  EXPECT_TRUE(parseFiniteNumber("0.5", &x));
  EXPECT_EQ(x, 0.5);
  EXPECT_TRUE(parseFiniteNumber("-2", &x));
  EXPECT_EQ(x, -2.0);
  EXPECT_TRUE(parseFiniteNumber("1e-4", &x));
  EXPECT_EQ(x, 1e-4);
  EXPECT_TRUE(parseFiniteNumber("81.83", &x));  // a CARMEN range
  EXPECT_EQ(x, 81.83);
  x = 42.0;
  for (const char* bad : {"", "-", "0.5x", "1,5", "nan", "-nan", "inf", "-inf", "1e999", "x1"})
    EXPECT_FALSE(parseFiniteNumber(bad, &x)) << "'" << bad << "'";
  EXPECT_EQ(x, 42.0);  // unchanged on refusal
}

}  // namespace
}  // namespace config
}  // namespace coral_introspection
