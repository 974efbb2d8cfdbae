// Tests of sim/scene/reader: pointers, message text, bounds, typed readers, object members and
// named choices — the pieces every scene error message is made of.
#include "sim/scene/reader.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

namespace brisance::scene {
namespace {

TEST(Reader, PointerTokensAreEscapedPerRfc6901) {
  EXPECT_EQ(escape_token("a/b~c"), "a~1b~0c");
  EXPECT_EQ(escape_token("~1"), "~01");
  EXPECT_EQ(child("", "x/y"), "/x~1y");
  EXPECT_EQ(child("/objects", std::size_t{3}), "/objects/3");
}

TEST(Reader, EditDistanceAndDidYouMean) {
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("mass", "mass"), 0u);
  EXPECT_EQ(did_you_mean("desnity", {"mass", "density"}), "did you mean 'density'? ");
  // Three edits or more is no longer a likely typo.
  EXPECT_EQ(did_you_mean("volume", {"mass", "density"}), "");
}

TEST(Reader, DescribeNamesTheValueAndCutsLongOnesShort) {
  EXPECT_EQ(describe(json(nullptr)), "null");
  EXPECT_EQ(describe(json(true)), "true");
  EXPECT_EQ(describe(json::array({1, 2, 3})), "an array of 3");
  EXPECT_EQ(describe(json::object()), "an object");
  EXPECT_EQ(describe(json(2.5)), "2.5");
  EXPECT_EQ(describe(json("box")), "the string \"box\"");
  const std::string long_text = describe(json(std::string(100, 'a')));
  EXPECT_EQ(long_text, "the string \"" + std::string(39, 'a') + "...\"");
}

TEST(Reader, BoundsCheckAndDescribeTheirRange) {
  EXPECT_EQ(range(0.0, true, 1.0, false, "m").text(), "a number in (0, 1] (m)");
  EXPECT_EQ(positive("kg").text(), "a number > 0 (kg)");
  EXPECT_EQ(non_negative().text(), "a number >= 0");
  EXPECT_EQ(any_number("m").text(), "a number (m)");
  EXPECT_EQ(range(0.0, true, 600.0, false, "s", "max_duration_s").text(),
            "a number in (0, 600] (s), the limit max_duration_s");
  EXPECT_FALSE(positive().contains(0.0));
  EXPECT_TRUE(non_negative().contains(0.0));
  EXPECT_TRUE(range(0.0, true, 1.0, false).contains(1.0));
  EXPECT_FALSE(range(0.0, true, 1.0, true).contains(1.0));
  EXPECT_FALSE(any_number().contains(std::nan("")));
}

TEST(Reader, NumbersIntegersAndBooleansAreTyped) {
  Errors errors;
  EXPECT_EQ(read_number(json(2), "/a", "a", positive(), errors), 2.0);
  EXPECT_FALSE(read_number(json(true), "/b", "b", any_number(), errors));
  EXPECT_FALSE(
      read_number(json(std::numeric_limits<double>::infinity()), "/c", "c", any_number(), errors));
  EXPECT_EQ(read_integer(json(3.0), "/d", "d", 0, 10, errors), 3);
  EXPECT_FALSE(read_integer(json(3.5), "/e", "e", 0, 10, errors));
  EXPECT_FALSE(read_integer(json(9.2233720368547758e18), "/f", "f", 0,
                            std::numeric_limits<std::int64_t>::max(), errors));
  EXPECT_FALSE(read_bool(json(1), "/g", "g", errors));
  const std::vector<ValidationError> list = errors.take();
  ASSERT_EQ(list.size(), 5u);
  EXPECT_EQ(list[0].pointer, "/b");
  EXPECT_EQ(list[0].message, "'b' must be a number; got true");
  EXPECT_EQ(list[2].message, "'e' must be an integer in [0, 10]; got 3.5");
  EXPECT_EQ(list[4].message, "'g' must be true or false; got 1");
}

TEST(Reader, Vec3ElementsAreReportedAtTheirIndex) {
  Errors errors;
  EXPECT_EQ(read_vec3(json::array({1, 2, 3}), "/p", "p", any_number(), errors), Vec3(1, 2, 3));
  EXPECT_FALSE(read_vec3(json::array({1, -2, 3}), "/size", "size", positive("m"), errors));
  const std::vector<ValidationError> list = errors.take();
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].pointer, "/size/1");
  EXPECT_EQ(list[0].message, "'size[1]' must be a number > 0 (m); got -2");
}

enum class Colour { red, green };
constexpr std::array<Choice<Colour>, 2> kColours = {
    {{"red", Colour::red}, {"green", Colour::green}}};

TEST(Reader, ChoicesMapNamesToEnumsAndSuggest) {
  Errors errors;
  EXPECT_EQ(read_enum(json("green"), "/c", "colour", kColours, errors), Colour::green);
  EXPECT_FALSE(read_enum(json("gren"), "/c", "colour", kColours, errors));
  EXPECT_FALSE(read_enum(json(1), "/c", "colour", kColours, errors));
  const std::vector<ValidationError> list = errors.take();
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].message,
            "'colour' must be one of red, green; did you mean 'green'? got the string \"gren\"");
  EXPECT_EQ(list[1].message, "'colour' must be one of the strings red, green; got 1");
}

TEST(Reader, FieldsReportUnknownMembersAndDefaultInvalidOnes) {
  Errors errors;
  const json object = {{"mass", -1}, {"colour", "red"}, {"frictoin", 0.3}};
  const Fields fields(object, "/objects/0", errors, "an object", {"mass", "colour", "friction"});
  EXPECT_EQ(fields.number("mass", 7.0, positive("kg")), 7.0);  // invalid: the default
  EXPECT_EQ(fields.number("friction", 0.5, non_negative()), 0.5);
  EXPECT_EQ(fields.choice("colour", Colour::green, kColours), Colour::red);
  EXPECT_FALSE(fields.required_name("name"));
  const ErrorScope scope(errors);
  EXPECT_TRUE(scope.ok());
  EXPECT_EQ(fields.choice("missing", Colour::green, kColours), Colour::green);
  EXPECT_TRUE(scope.ok());
  const std::vector<ValidationError> list = errors.take();
  ASSERT_EQ(list.size(), 3u);
  EXPECT_EQ(list[0].pointer, "/objects/0/frictoin");
  EXPECT_EQ(list[0].message,
            "unknown field 'frictoin' in an object; did you mean 'friction'? known fields: mass, "
            "colour, friction");
  EXPECT_EQ(list[1].pointer, "/objects/0/mass");
  EXPECT_EQ(list[2].pointer, "/objects/0/name");
  EXPECT_EQ(list[2].message, "'name' is required: a non-empty string");
}

TEST(Reader, ErrorScopeSeesOnlyItsOwnErrors) {
  Errors errors;
  errors.add("/a", "before");
  const ErrorScope scope(errors);
  EXPECT_TRUE(scope.ok());
  errors.add("/b", "inside");
  EXPECT_FALSE(scope.ok());
  EXPECT_EQ(errors.count(), 2u);
}

}  // namespace
}  // namespace brisance::scene
