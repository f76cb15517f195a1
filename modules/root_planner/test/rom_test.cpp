#include "rbcp/root_planner/rom.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "rbcp/core/error.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/test_support/error_of.h"

namespace rbcp {
namespace {

using test_support::ErrorOf;

const std::string kConfigDir = std::string(RBCP_SOURCE_DIR) + "/config";
const std::string kRomDir = kConfigDir + "/robots/anymal_b_roms";

const RobotModel& Robot() {
  static const RobotModel robot = RobotModel::LoadDefault(kConfigDir);
  return robot;
}

TEST(RomTest, CommittedShapesRegenerateIdentically) {
  const RomGenerationConfig config = RomGenerationConfig::LoadFile(kRomDir + "/rom_generation.yaml");
  const auto committed = LoadRoms(kRomDir);
  for (Leg leg : kAllLegs) {
    SCOPED_TRACE(std::string(LegName(leg)));
    const ConvexPolytope generated = GenerateRom(Robot(), leg, config);
    const ConvexPolytope& stored = committed[static_cast<std::size_t>(Index(leg))];
    ASSERT_EQ(generated.vertices.size(), stored.vertices.size());
    ASSERT_EQ(generated.triangles, stored.triangles);
    for (std::size_t i = 0; i < stored.vertices.size(); ++i) {
      EXPECT_LT((generated.vertices[i] - stored.vertices[i]).norm(), 1e-12) << i;
    }
    EXPECT_LE(static_cast<int>(stored.triangles.size()), config.max_triangles);
  }
}

TEST(RomTest, NominalStanceIsInsideEveryShape) {
  const auto roms = LoadRoms(kRomDir);
  for (Leg leg : kAllLegs) {
    const ConvexPolytope& rom = roms[static_cast<std::size_t>(Index(leg))];
    EXPECT_LT(rom.PlaneDistance(Robot().ReferenceFootPosition(leg)), -0.02) << LegName(leg);
    // Fore ROMs lie ahead of hind ones, left ones to the left of right ones.
    EXPECT_GT(ForeSign(leg) * rom.Centroid().x(), 0.1) << LegName(leg);
    EXPECT_GT(LeftSign(leg) * rom.Centroid().y(), 0.05) << LegName(leg);
    // The feet cannot reach above the hips by much nor much further than a stretched leg.
    const auto [lo, hi] = rom.Bounds();
    EXPECT_GT(lo.z(), -0.65);
    EXPECT_LT(hi.z(), 0.4);
  }
}

TEST(RomTest, TheShippedParametersHoldTheDefaultsAndHeadTheShapes) {
  const RomGenerationConfig config = RomGenerationConfig::LoadFile(kRomDir + "/rom_generation.yaml");
  EXPECT_EQ(DifferingFields(config, RomGenerationConfig()), std::vector<std::string>{});
  // generate_roms writes these lines into the header of every shape.
  std::ifstream obj(kRomDir + "/LF.obj");
  std::vector<std::string> header;
  for (std::string line; std::getline(obj, line) && line.rfind("# ", 0) == 0;) header.push_back(line.substr(2));
  ASSERT_GT(header.size(), 2u);
  EXPECT_EQ(std::vector<std::string>(header.begin() + 2, header.end()), config.Describe());
  RomGenerationConfig without_box = config;
  without_box.foot_box.reset();
  EXPECT_EQ(without_box.Describe().back(), "reject_self_collisions: true");
}

TEST(RomTest, ScaleCentreIsOneOfItsNames) {
  YAML::Node n = YAML::LoadFile(kRomDir + "/rom_generation.yaml");
  n["scale_center"] = "middle";
  EXPECT_EQ(ErrorOf([&] { RomGenerationConfig::Load(YamlMap(n, "roms")); }),
            "roms: 'scale_center': expected 'centroid' or 'hip', got 'middle'");
  n["scale_center"] = "hip";
  n.remove("foot_box");
  const RomGenerationConfig hip = RomGenerationConfig::Load(YamlMap(n, "roms"));
  EXPECT_EQ(hip.scale_center, RomGenerationConfig::ScaleCenter::kHip);
  EXPECT_FALSE(hip.foot_box.has_value());
}

TEST(RomTest, FootBoxKeysAreChecked) {
  YAML::Node n = YAML::Load(
      "{samples: 1000, seed: 1, max_triangles: 50, tolerance: 0.0, scale: 1.0, scale_center: centroid, "
      "reject_self_collisions: true, foot_box: {forward: 0.1, backward: 0.1, outward: 0.1, inward: 0.1, up: 0.1, "
      "down: 0.1}}");
  const RomGenerationConfig ok = RomGenerationConfig::Load(YamlMap(n, "roms"));
  ASSERT_TRUE(ok.foot_box.has_value());
  EXPECT_DOUBLE_EQ(ok.foot_box->inward, 0.1);
  n["foot_box"]["inward"] = -0.1;
  EXPECT_THROW(RomGenerationConfig::Load(YamlMap(n, "roms")), InputError);
  n["foot_box"]["inward"] = 0.1;
  n["foot_box"]["sideways"] = 0.1;
  EXPECT_THROW(RomGenerationConfig::Load(YamlMap(n, "roms")), InputError);
}

RomGenerationConfig SmallConfig() {
  RomGenerationConfig config;
  config.samples = 3000;
  config.seed = 7;
  config.max_triangles = 60;
  config.tolerance = 0.0;
  config.scale = 1.0;
  config.foot_box.reset();
  return config;
}

TEST(RomTest, FootBoxBoundsTheShapeAroundTheReferenceFoot) {
  RomGenerationConfig config = SmallConfig();
  const ConvexPolytope unbounded = GenerateRom(Robot(), Leg::kRF, config);
  config.foot_box = RomGenerationConfig::FootBox{0.15, 0.1, 0.12, 0.05, 0.2, 0.1};
  RomGenerationReport report;
  const ConvexPolytope boxed = GenerateRom(Robot(), Leg::kRF, config, &report);
  EXPECT_GT(report.outside_foot_box, 0);
  EXPECT_LT(boxed.Volume(), unbounded.Volume());
  // RF: outward is -y, inward +y.
  const Eigen::Vector3d ref = Robot().ReferenceFootPosition(Leg::kRF);
  for (const Eigen::Vector3d& v : boxed.vertices) {
    const Eigen::Vector3d d = v - ref;
    EXPECT_LE(d.x(), 0.15 + 1e-9);
    EXPECT_GE(d.x(), -0.1 - 1e-9);
    EXPECT_GE(d.y(), -0.12 - 1e-9);
    EXPECT_LE(d.y(), 0.05 + 1e-9);
    EXPECT_LE(d.z(), 0.2 + 1e-9);
    EXPECT_GE(d.z(), -0.1 - 1e-9);
  }
}

TEST(RomTest, SelfCollisionsAreRejected) {
  RomGenerationConfig config = SmallConfig();
  RomGenerationReport with_rejection;
  const auto feet = SampleFootPositions(Robot(), Leg::kLF, config, &with_rejection);
  EXPECT_GT(with_rejection.rejected_samples, 0);
  EXPECT_EQ(with_rejection.accepted_samples + with_rejection.rejected_samples, config.samples);
  // No accepted foot contact point lies inside the trunk's main body box (URDF: centre
  // (0, 0, 0.08), size 0.531 x 0.27 x 0.24); without the rejection some do.
  auto inside_body = [](const Eigen::Vector3d& p) {
    return std::abs(p.x()) < 0.2655 && std::abs(p.y()) < 0.135 && std::abs(p.z() - 0.08) < 0.12;
  };
  for (const auto& p : feet) EXPECT_FALSE(inside_body(p)) << p.transpose();
  config.reject_self_collisions = false;
  RomGenerationReport without;
  const auto all = SampleFootPositions(Robot(), Leg::kLF, config, &without);
  EXPECT_GT(std::count_if(all.begin(), all.end(), inside_body), 0);
  EXPECT_EQ(without.rejected_samples, 0);
  EXPECT_EQ(static_cast<int>(all.size()), config.samples);
}

TEST(RomTest, SeedAndScaleCentre) {
  RomGenerationConfig config = SmallConfig();
  RomGenerationReport report;
  const ConvexPolytope a = GenerateRom(Robot(), Leg::kRH, config, &report);
  const ConvexPolytope b = GenerateRom(Robot(), Leg::kRH, config);
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (std::size_t i = 0; i < a.vertices.size(); ++i) EXPECT_EQ(a.vertices[i], b.vertices[i]);
  EXPECT_NEAR(a.Volume(), report.simplified_volume, 1e-12);
  EXPECT_LE(report.simplified_volume, report.full_hull_volume);
  EXPECT_LE(static_cast<int>(a.triangles.size()), config.max_triangles);

  config.seed = 8;
  const ConvexPolytope other = GenerateRom(Robot(), Leg::kRH, config);
  EXPECT_NE(other.vertices.front(), a.vertices.front());

  config.seed = 7;
  config.scale = 0.85;
  config.scale_center = RomGenerationConfig::ScaleCenter::kCentroid;
  const ConvexPolytope about_centroid = GenerateRom(Robot(), Leg::kRH, config);
  EXPECT_NEAR(about_centroid.Volume(), 0.85 * 0.85 * 0.85 * a.Volume(), 1e-9);
  EXPECT_LT((about_centroid.Centroid() - a.Centroid()).norm(), 1e-9);
  config.scale_center = RomGenerationConfig::ScaleCenter::kHip;
  const ConvexPolytope about_hip = GenerateRom(Robot(), Leg::kRH, config);
  EXPECT_NEAR(about_hip.Volume(), 0.85 * 0.85 * 0.85 * a.Volume(), 1e-9);
  const Eigen::Vector3d hip = Robot().HipPosition(Leg::kRH);
  EXPECT_LT((about_hip.Centroid() - (hip + 0.85 * (a.Centroid() - hip))).norm(), 1e-9);
}

TEST(RomTest, ConfigIsStrict) {
  const std::string good =
      "samples: 1000\nseed: 3\nmax_triangles: 100\ntolerance: 0.001\nscale: 0.9\nscale_center: hip\n"
      "reject_self_collisions: false\n";
  const RomGenerationConfig config = RomGenerationConfig::Load(YamlMap(YAML::Load(good), "test"));
  EXPECT_EQ(config.samples, 1000);
  EXPECT_EQ(config.scale_center, RomGenerationConfig::ScaleCenter::kHip);
  EXPECT_FALSE(config.reject_self_collisions);
  EXPECT_THROW(RomGenerationConfig::Load(YamlMap(YAML::Load(good + "extra: 1\n"), "test")), InputError);
  std::string bad_center = good;
  bad_center.replace(bad_center.find("hip"), 3, "knee");
  EXPECT_THROW(RomGenerationConfig::Load(YamlMap(YAML::Load(bad_center), "test")), InputError);
  std::string bad_scale = good;
  bad_scale.replace(bad_scale.find("0.9"), 3, "1.5");
  EXPECT_THROW(RomGenerationConfig::Load(YamlMap(YAML::Load(bad_scale), "test")), InputError);
}

}  // namespace
}  // namespace rbcp
