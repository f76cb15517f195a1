#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "rbcp/core/error.h"
#include "rbcp/robot/robot_model.h"
#include "robot_test_util.h"

namespace rbcp {
namespace {

namespace fs = std::filesystem;

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Copies of the shipped robot files, edited per test, in a private temporary folder.
class RobotLoadTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("rbcp_robot_" + std::to_string(::getpid()) + "_" + info->name());
    fs::create_directories(dir_);
    urdf_text_ = ReadText(test::ConfigDir() + "/robots/anymal_b.urdf");
    yaml_text_ = ReadText(test::ConfigDir() + "/robots/anymal_b.yaml");
    ASSERT_FALSE(urdf_text_.empty());
    ASSERT_FALSE(yaml_text_.empty());
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Writes the (edited) texts and loads them; returns the InputError message, or "" on success.
  std::string LoadError() {
    std::ofstream(UrdfPath()) << urdf_text_;
    std::ofstream(YamlPath()) << yaml_text_;
    try {
      RobotModel::Load(UrdfPath(), YamlPath());
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  static void Replace(std::string& text, const std::string& from, const std::string& to, std::size_t start = 0) {
    const std::size_t at = text.find(from, start);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }

  /// Replaces the first `from` in the URDF after the start of `element`, e.g. "<joint name=\"LF_HFE\"".
  void EditUrdfAfter(const std::string& element, const std::string& from, const std::string& to) {
    const std::size_t at = urdf_text_.find(element);
    ASSERT_NE(at, std::string::npos) << element;
    Replace(urdf_text_, from, to, at);
  }

  std::string UrdfPath() const { return (dir_ / "robot.urdf").string(); }
  std::string YamlPath() const { return (dir_ / "robot.yaml").string(); }

  fs::path dir_;
  std::string urdf_text_;
  std::string yaml_text_;
};

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST_F(RobotLoadTest, UneditedCopiesLoad) { EXPECT_EQ(LoadError(), ""); }

TEST_F(RobotLoadTest, MissingFilesAreNamed) {
  std::ofstream(YamlPath()) << yaml_text_;
  try {
    RobotModel::Load((dir_ / "absent.urdf").string(), YamlPath());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_TRUE(Contains(e.what(), "absent.urdf: cannot open file")) << e.what();
  }
  std::ofstream(UrdfPath()) << urdf_text_;
  try {
    RobotModel::Load(UrdfPath(), (dir_ / "absent.yaml").string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_TRUE(Contains(e.what(), "absent.yaml: cannot open file")) << e.what();
  }
}

TEST_F(RobotLoadTest, MalformedUrdfNamesTheFile) {
  urdf_text_ = urdf_text_.substr(0, urdf_text_.size() / 2);
  const std::string error = LoadError();
  EXPECT_TRUE(Contains(error, UrdfPath() + ": invalid URDF")) << error;
}

TEST_F(RobotLoadTest, MissingJointNamesTheFileAndJoint) {
  Replace(urdf_text_, "<joint name=\"LF_KFE\"", "<joint name=\"LF_KNEE\"");
  const std::string error = LoadError();
  EXPECT_EQ(error, UrdfPath() + ": missing joint 'LF_KFE'");
}

TEST_F(RobotLoadTest, WrongAxisIsRejected) {
  EditUrdfAfter("<joint name=\"RH_HFE\"", "<axis xyz=\"0 1 0\"/>", "<axis xyz=\"0 0 1\"/>");
  const std::string error = LoadError();
  EXPECT_EQ(error, UrdfPath() + ": joint 'RH_HFE': expected axis (0 1 0), got (0 0 1)");
}

TEST_F(RobotLoadTest, RotatedJointOriginIsRejected) {
  EditUrdfAfter("<joint name=\"LH_KFE\"", "rpy=\"0 0 0\"", "rpy=\"0 0 0.1\"");
  const std::string error = LoadError();
  EXPECT_TRUE(Contains(error, UrdfPath() + ": joint 'LH_KFE': expected an origin without rotation")) << error;
}

TEST_F(RobotLoadTest, ExtraMovableJointIsRejected) {
  Replace(urdf_text_, "<joint name=\"LF_SHANK_TO_ADAPTER\" type=\"fixed\">",
          "<joint name=\"LF_SHANK_TO_ADAPTER\" type=\"continuous\">");
  const std::string error = LoadError();
  EXPECT_TRUE(Contains(error, "joint 'LF_SHANK_TO_ADAPTER': unexpected movable joint")) << error;
}

TEST_F(RobotLoadTest, LinkWithoutInertiaIsRejected) {
  const std::size_t link = urdf_text_.find("<link name=\"RF_FOOT\">");
  ASSERT_NE(link, std::string::npos);
  const std::size_t begin = urdf_text_.find("<inertial>", link);
  const std::size_t end = urdf_text_.find("</inertial>", link) + std::string("</inertial>").size();
  urdf_text_.erase(begin, end - begin);
  const std::string error = LoadError();
  EXPECT_EQ(error, UrdfPath() + ": link 'RF_FOOT': missing <inertial> (every link needs a mass)");
}

TEST_F(RobotLoadTest, LinkWithoutPositiveMassIsRejected) {
  EditUrdfAfter("<link name=\"LH_FOOT\">", "<mass value=\"0.001\"/>", "<mass value=\"0\"/>");
  const std::string error = LoadError();
  EXPECT_EQ(error, UrdfPath() + ": link 'LH_FOOT': expected a positive mass, got 0");
}

TEST_F(RobotLoadTest, InertiaNotPositiveDefiniteIsRejected) {
  EditUrdfAfter("<link name=\"RF_FOOT\">", "izz=\"4.9e-07\"", "izz=\"0.0\"");
  const std::string error = LoadError();
  EXPECT_TRUE(Contains(error, UrdfPath() + ": link 'RF_FOOT': expected a positive definite inertia")) << error;
}

TEST_F(RobotLoadTest, UnorderedJointLimitsAreRejected) {
  EditUrdfAfter("<joint name=\"RF_HFE\"", "lower=\"-9.42\" upper=\"9.42\"", "lower=\"1.0\" upper=\"-1.0\"");
  const std::string error = LoadError();
  EXPECT_EQ(error, UrdfPath() + ": joint 'RF_HFE': expected lower < upper limit, got [1, -1]");
}

TEST_F(RobotLoadTest, EmptyCollisionGeometryIsRejected) {
  EditUrdfAfter("<collision name=\"LF_foot\">", "<sphere radius=\"0.031\"/>", "<sphere radius=\"0\"/>");
  const std::string error = LoadError();
  EXPECT_EQ(error, UrdfPath() + ": link 'LF_FOOT': expected a sphere of positive radius");
}

TEST_F(RobotLoadTest, UnknownYamlKeyNamesTheFileAndKey) {
  yaml_text_ += "max_step_height: 0.2\n";
  const std::string error = LoadError();
  EXPECT_EQ(error, YamlPath() + ": 'max_step_height': unknown key");
}

TEST_F(RobotLoadTest, UnknownNestedYamlKeyIsRejected) {
  Replace(yaml_text_, "  radius: 0.031", "  radius: 0.031\n  width: 0.02");
  const std::string error = LoadError();
  EXPECT_EQ(error, YamlPath() + ": foot: 'width': unknown key");
}

TEST_F(RobotLoadTest, MissingYamlKeyIsRejected) {
  Replace(yaml_text_, "torque_limit: 80.0", "");
  const std::string error = LoadError();
  EXPECT_EQ(error, YamlPath() + ": 'torque_limit': missing key");
}

TEST_F(RobotLoadTest, KneeBoundsMustKeepTheXConfiguration) {
  Replace(yaml_text_, "KFE: [-2.35, 0.0]}", "KFE: [-2.35, 0.5]}");
  const std::string error = LoadError();
  EXPECT_TRUE(Contains(error, YamlPath() + ": joint_bounds: LF: 'KFE': expected a fore knee upper bound <= 0"))
      << error;
}

TEST_F(RobotLoadTest, InvertedBoundsAreRejected) {
  Replace(yaml_text_, "LH: {HAA: [-1.0, 1.0]", "LH: {HAA: [1.0, -1.0]");
  const std::string error = LoadError();
  EXPECT_EQ(error, YamlPath() + ": joint_bounds: LH: 'HAA': expected lower < upper, got [1, -1]");
}

TEST_F(RobotLoadTest, ReferenceOutsideTheBoundsIsRejected) {
  Replace(yaml_text_, "RF: [-0.04, 0.74, -1.08]", "RF: [-0.04, 2.5, -1.08]");
  const std::string error = LoadError();
  EXPECT_TRUE(Contains(error, YamlPath() + ": reference_configuration: 'RF': expected a configuration within "
                                           "joint_bounds: RF_HFE = 2.5000 rad"))
      << error;
}

TEST_F(RobotLoadTest, NonPositiveParametersAreRejected) {
  Replace(yaml_text_, "radius: 0.031", "radius: -0.031");
  const std::string error = LoadError();
  EXPECT_EQ(error, YamlPath() + ": foot: 'radius': expected a positive radius, got -0.031");
}

TEST_F(RobotLoadTest, KinematicMarginsAreReadAndChecked) {
  const RobotModel m = RobotModel::LoadDefault(test::ConfigDir());
  EXPECT_EQ(m.Margins().max_stance_hip_distance_m, 0.545);
  EXPECT_EQ(m.Margins().max_lift_off_hip_distance_m, 0.565);
  EXPECT_EQ(m.Margins().min_knee_bend_rad, 0.2);
  Replace(yaml_text_, "max_lift_off_hip_distance: 0.565", "max_lift_off_hip_distance: 0.5");
  const std::string error = LoadError();
  EXPECT_TRUE(Contains(error, YamlPath() + ": kinematic_margins: 'max_lift_off_hip_distance': expected at least "
                                           "max_stance_hip_distance"))
      << error;
}

TEST(RobotMarginsTest, AStretchedLegIsOutsideTheMargins) {
  const RobotModel m = RobotModel::LoadDefault(test::ConfigDir());
  const Eigen::Vector3d q_ref = LegJoints(m.ReferenceConfiguration(), Leg::kLF);
  const Eigen::Vector3d p_ref = m.FootPosition(Leg::kLF, q_ref);
  EXPECT_TRUE(m.WithinMargins(Leg::kLF, p_ref, q_ref, m.Margins().max_stance_hip_distance_m));
  // The leg nearly straight: knee at 0.1 rad, foot far from the hip.
  const Eigen::Vector3d q_straight(0.0, 0.3, -0.1);
  const Eigen::Vector3d p_straight = m.FootPosition(Leg::kLF, q_straight);
  const double reference_distance = (p_ref - m.HipPosition(Leg::kLF)).norm();
  const double straight_distance = (p_straight - m.HipPosition(Leg::kLF)).norm();
  EXPECT_GT(straight_distance, reference_distance + 0.05);
  EXPECT_FALSE(m.WithinMargins(Leg::kLF, p_straight, q_straight, m.Margins().max_lift_off_hip_distance_m));
  EXPECT_FALSE(m.WithinMargins(Leg::kLF, p_straight, LegJoints(m.ReferenceConfiguration(), Leg::kLF),
                               0.5 * (reference_distance + straight_distance)));  // the distance alone
  EXPECT_FALSE(m.WithinMargins(Leg::kLF, p_ref, q_straight, 10.0));  // the knee alone
}

}  // namespace
}  // namespace rbcp
