#include "rbcp/core/config_fields.h"

#include <gtest/gtest.h>

#include "rbcp/test_support/error_of.h"

namespace rbcp {
namespace {

using rbcp::test_support::ErrorOf;

struct Inner {
  int count = 3;
  std::vector<double> offsets = {0.1, -0.1};

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("count", &count, "", bounds::Closed(1, 5), "how many");
    v->Visit("offsets", &offsets, "m", bounds::Any().AtLeast(-0.2).AtMost(0.2), "where");
  }
};

struct Outer {
  double step_s = 0.02;
  double resolution_s = 0.002;
  bool enabled = true;
  std::string name = "x";
  Eigen::Vector3d gains = Eigen::Vector3d(1, 2, 3);
  std::array<double, 2> range = {-1.0, 1.0};
  Inner inner;
  double speed = 0.3;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("step_s", &step_s, "s", bounds::Positive(), "the step");
    v->Visit("resolution_s", &resolution_s, "s", bounds::Positive().AtMost(step_s, "step_s"), "the resolution");
    v->Visit("enabled", &enabled, "on or off");
    v->Visit("name", &name, "a name");
    v->Visit("gains", &gains, "N/m", bounds::NonNegative(), "gains | per axis");
    v->Visit("range", &range, "m", bounds::Any(), "a range");
    v->Rule("range", range[0] <= range[1], "[min, max] with min <= max", ConfigNumber(range[0]));
    v->Visit("inner", &inner, "a nested map");
    v->Map("limits", "a map laid out here", [this](auto* m) {
      m->Visit("speed", &speed, "m/s", bounds::Positive(), "a speed");
    });
  }
};

const char* kValid =
    "{step_s: 0.05, resolution_s: 0.01, enabled: false, name: y, gains: [4, 5, 6], range: [-2, 2],"
    " inner: {count: 5, offsets: [0.2]}, limits: {speed: 0.5}}";

Outer Load(const std::string& yaml) { return LoadConfig<Outer>(YamlMap(YAML::Load(yaml), "f.yaml")); }

std::string LoadError(const std::string& key_path, const std::string& value) {
  YAML::Node node = YAML::Load(kValid);
  const auto dot = key_path.find('.');
  if (dot == std::string::npos) {
    node[key_path] = YAML::Load(value);
  } else {
    node[key_path.substr(0, dot)][key_path.substr(dot + 1)] = YAML::Load(value);
  }
  return ErrorOf([&] { LoadConfig<Outer>(YamlMap(node, "f.yaml")); });
}

TEST(ConfigFields, LoadsEveryField) {
  const Outer c = Load(kValid);
  EXPECT_EQ(c.step_s, 0.05);
  EXPECT_EQ(c.resolution_s, 0.01);
  EXPECT_FALSE(c.enabled);
  EXPECT_EQ(c.name, "y");
  EXPECT_EQ(c.gains, Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(c.range[0], -2.0);
  EXPECT_EQ(c.inner.count, 5);
  EXPECT_EQ(c.inner.offsets, std::vector<double>{0.2});
  EXPECT_EQ(c.speed, 0.5);
}

TEST(ConfigFields, RejectsMissingAndUnknownKeysAtAnyDepth) {
  EXPECT_EQ(ErrorOf([] { Load("{step_s: 0.05}"); }), "f.yaml: 'resolution_s': missing key");
  EXPECT_EQ(LoadError("surprise", "1"), "f.yaml: 'surprise': unknown key");
  EXPECT_EQ(LoadError("inner.surprise", "1"), "f.yaml: inner: 'surprise': unknown key");
  EXPECT_EQ(LoadError("limits.surprise", "1"), "f.yaml: limits: 'surprise': unknown key");
  YAML::Node node = YAML::Load(kValid);
  node["inner"].remove("count");
  EXPECT_EQ(ErrorOf([&] { LoadConfig<Outer>(YamlMap(node, "f.yaml")); }), "f.yaml: inner: 'count': missing key");
}

TEST(ConfigFields, RejectsValuesOutOfBoundsNamingFileMapAndKey) {
  EXPECT_EQ(LoadError("step_s", "0"), "f.yaml: 'step_s': expected a positive number [s], got 0");
  EXPECT_EQ(LoadError("step_s", "x"), "f.yaml: 'step_s': expected a number, got 'x'");
  EXPECT_EQ(LoadError("resolution_s", "0.1"),
            "f.yaml: 'resolution_s': expected a number in (0, step_s] [s] (step_s = 0.05), got 0.1");
  EXPECT_EQ(LoadError("gains", "[1, -1, 1]"), "f.yaml: 'gains[1]': expected a non-negative number [N/m], got -1");
  EXPECT_EQ(LoadError("gains", "[1, 1]"), "f.yaml: 'gains': expected a list of 3 numbers, got a list of 2");
  EXPECT_EQ(LoadError("range", "[1, -1]"), "f.yaml: 'range': expected [min, max] with min <= max, got 1");
  EXPECT_EQ(LoadError("inner.count", "6"), "f.yaml: inner: 'count': expected an integer in [1, 5], got 6");
  EXPECT_EQ(LoadError("inner.offsets", "[0, 0.3]"),
            "f.yaml: inner: 'offsets[1]': expected a number in [-0.2, 0.2] [m], got 0.3");
  EXPECT_EQ(LoadError("limits.speed", "-1"), "f.yaml: limits: 'speed': expected a positive number [m/s], got -1");
  EXPECT_EQ(LoadError("enabled", "maybe"), "f.yaml: 'enabled': expected true or false, got 'maybe'");
}

TEST(ConfigFields, ValidatesAConfigBuiltInCode) {
  Outer c;
  EXPECT_NO_THROW(ValidateConfig(c, "Outer"));
  c.inner.count = 0;
  EXPECT_EQ(ErrorOf([&] { ValidateConfig(c, "Outer"); }), "Outer: inner: 'count': expected an integer in [1, 5], got 0");
}

TEST(ConfigFields, DescribesEveryFieldWithItsValue) {
  const ConfigDescription d = DescribeConfig(Outer());
  ASSERT_EQ(d.fields.size(), 11u);
  EXPECT_EQ(d.fields[1].key, "resolution_s");
  EXPECT_EQ(d.fields[1].unit, "s");
  EXPECT_EQ(d.fields[1].bounds, "(0, step_s]");
  EXPECT_EQ(d.fields[1].value, "0.002");
  EXPECT_EQ(d.fields[2].bounds, "true or false");
  EXPECT_EQ(d.fields[4].bounds, "3 numbers, each >= 0");
  EXPECT_EQ(d.fields[4].value, "[1, 2, 3]");
  EXPECT_EQ(d.fields[6].key, "inner");
  EXPECT_EQ(d.fields[6].bounds, "map");
  EXPECT_EQ(d.fields[7].key, "inner.count");
  EXPECT_EQ(d.fields[7].bounds, "integer in [1, 5]");
  EXPECT_EQ(d.fields[7].unit, "-");
  EXPECT_EQ(d.fields[8].bounds, "list of numbers, each in [-0.2, 0.2]");
  EXPECT_EQ(d.fields[10].key, "limits.speed");
  ASSERT_EQ(d.rules.size(), 1u);
  EXPECT_EQ(d.rules[0].key, "range");
  const std::string table = ConfigTable(d);
  EXPECT_NE(table.find("| `resolution_s` | s | (0, step_s] | `0.002` | the resolution |"), std::string::npos) << table;
  EXPECT_NE(table.find("gains \\| per axis"), std::string::npos) << table;
  EXPECT_NE(table.find("- `range`: [min, max] with min <= max"), std::string::npos) << table;
}

TEST(ConfigFields, DifferingFieldsNamesEveryDifference) {
  Outer a;
  Outer b;
  EXPECT_TRUE(DifferingFields(a, b).empty());
  b.step_s = 0.0200000001;
  b.inner.offsets.push_back(0.0);
  EXPECT_EQ(DifferingFields(a, b),
            (std::vector<std::string>{"step_s: 0.02 vs 0.0200000001", "inner.offsets: [0.1, -0.1] vs [0.1, -0.1, 0]"}));
}

enum class Shape { kBox, kBall };

struct WithChoices {
  Shape shape = Shape::kBall;
  std::uint64_t seed = 2019;
  std::optional<Inner> extra = Inner();

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("shape", &shape, EnumNames<Shape>{{Shape::kBox, "box"}, {Shape::kBall, "ball"}}, "a shape");
    v->Visit("seed", &seed, "", bounds::NonNegative(), "a seed");
    v->Visit("extra", &extra, "a map that may be left out");
  }
};

TEST(ConfigFields, EnumsAreOneOfTheirNames) {
  const auto load = [](const std::string& yaml) { return LoadConfig<WithChoices>(YamlMap(YAML::Load(yaml), "c")); };
  EXPECT_EQ(load("{shape: box, seed: 3}").shape, Shape::kBox);
  EXPECT_EQ(ErrorOf([&] { load("{shape: cube, seed: 3}"); }), "c: 'shape': expected 'box' or 'ball', got 'cube'");
  EXPECT_EQ(ErrorOf([&] { load("{shape: box, seed: -3}"); }), "c: 'seed': expected a non-negative integer, got -3");
  const ConfigDescription d = DescribeConfig(WithChoices());
  EXPECT_EQ(d.fields[0].bounds, "'box' or 'ball'");
  EXPECT_EQ(d.fields[0].value, "ball");
  EXPECT_EQ(d.fields[1].value, "2019");
}

TEST(ConfigFields, AnOptionalMapMayBeLeftOut) {
  const auto load = [](const std::string& yaml) { return LoadConfig<WithChoices>(YamlMap(YAML::Load(yaml), "c")); };
  EXPECT_FALSE(load("{shape: box, seed: 3}").extra.has_value());
  const WithChoices with = load("{shape: box, seed: 3, extra: {count: 2, offsets: []}}");
  ASSERT_TRUE(with.extra.has_value());
  EXPECT_EQ(with.extra->count, 2);
  EXPECT_EQ(ErrorOf([&] { load("{shape: box, seed: 3, extra: {count: 9, offsets: []}}"); }),
            "c: extra: 'count': expected an integer in [1, 5], got 9");
  EXPECT_EQ(ErrorOf([&] { load("{shape: box, seed: 3, extra: {count: 2}}"); }), "c: extra: 'offsets': missing key");
  const ConfigDescription d = DescribeConfig(with);
  EXPECT_EQ(d.fields[2].key, "extra");
  EXPECT_EQ(d.fields[2].bounds, "map, may be left out");
  EXPECT_EQ(d.fields[3].key, "extra.count");
  EXPECT_EQ(d.fields[3].value, "2");
  WithChoices without = with;
  without.extra.reset();
  EXPECT_EQ(DescribeConfig(without).fields[2].value, "(left out)");
  EXPECT_EQ(DifferingFields(with, without).front(), "extra:  vs (left out)");
}

}  // namespace
}  // namespace rbcp
