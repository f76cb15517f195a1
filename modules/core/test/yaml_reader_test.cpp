#include "rbcp/core/yaml_reader.h"

#include <gtest/gtest.h>

#include <functional>

#include "rbcp/test_support/error_of.h"

namespace rbcp {
namespace {

using rbcp::test_support::ErrorOf;

TEST(YamlMap, ReadsTypedValues) {
  YamlMap m(YAML::Load("{a: 1.5, n: 3, b: true, s: hi, v: [1, 2, 3], sub: {x: 2}, l: [{y: 1}, {y: 2}]}"), "test");
  EXPECT_DOUBLE_EQ(m.Double("a"), 1.5);
  EXPECT_EQ(m.Int("n"), 3);
  EXPECT_TRUE(m.Bool("b"));
  EXPECT_EQ(m.String("s"), "hi");
  EXPECT_TRUE(m.Vector3("v").isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_DOUBLE_EQ(m.Map("sub").Double("x"), 2.0);
  auto list = m.MapList("l");
  ASSERT_EQ(list.size(), 2u);
  EXPECT_DOUBLE_EQ(list[1].Double("y"), 2.0);
  EXPECT_DOUBLE_EQ(m.Double("missing", 7.0), 7.0);
  EXPECT_NO_THROW(m.RejectUnknownKeys());
}

TEST(YamlMap, NumbersReadsListsOfAnyLength) {
  YamlMap m(YAML::Load("{empty: [], three: [1, -2.5, 3e-2]}"), "file.yaml");
  EXPECT_TRUE(m.Numbers("empty").empty());
  EXPECT_EQ(m.Numbers("three"), (std::vector<double>{1.0, -2.5, 0.03}));
}

TEST(YamlMap, StringsReadsListsOfStrings) {
  YamlMap m(YAML::Load("{empty: [], cmd: [/bin/prog, --flag, '2'], bad: [a, [b]], scalar: a}"), "file.yaml");
  EXPECT_TRUE(m.Strings("empty").empty());
  EXPECT_EQ(m.Strings("cmd"), (std::vector<std::string>{"/bin/prog", "--flag", "2"}));
  EXPECT_EQ(ErrorOf([&] { m.Strings("bad"); }), "file.yaml: 'bad': element 1: expected a string, got a list of 1");
  EXPECT_EQ(ErrorOf([&] { m.Strings("scalar"); }), "file.yaml: 'scalar': expected a list of strings, got 'a'");
}

TEST(YamlMap, ErrorsSayWhereAndWhat) {
  YamlMap m(YAML::Load("{a: x, v: [1, 2], w: [1, .nan, 3], extra: 1}"), "file.yaml");
  EXPECT_EQ(ErrorOf([&] { m.Double("a"); }), "file.yaml: 'a': expected a number, got 'x'");
  EXPECT_EQ(ErrorOf([&] { m.Vector3("v"); }), "file.yaml: 'v': expected a list of 3 numbers, got a list of 2");
  EXPECT_EQ(ErrorOf([&] { m.Vector3("w"); }), "file.yaml: 'w': element 1: expected a finite number, got .nan");
  EXPECT_EQ(ErrorOf([&] { m.Double("nope"); }), "file.yaml: 'nope': missing key");
  EXPECT_EQ(ErrorOf([&] { m.Numbers("a"); }), "file.yaml: 'a': expected a list of numbers, got 'x'");
  EXPECT_EQ(ErrorOf([&] { m.Numbers("w"); }), "file.yaml: 'w': element 1: expected a finite number, got .nan");
  EXPECT_EQ(ErrorOf([&] { m.RejectUnknownKeys(); }), "file.yaml: 'extra': unknown key");
  EXPECT_EQ(ErrorOf([] { YamlMap::LoadFile("/nonexistent/x.yaml"); }), "/nonexistent/x.yaml: cannot open file");
}

}  // namespace
}  // namespace rbcp
