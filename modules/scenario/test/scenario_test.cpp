#include "rbcp/scenario/scenario.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "rbcp/core/error.h"
#include "test_paths.h"

namespace rbcp {
namespace {

using test::DataPath;

void ExpectSameScenario(const Scenario& a, const Scenario& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_TRUE(a.terrain == b.terrain);
  EXPECT_TRUE(a.start == b.start);
  EXPECT_TRUE(a.goal == b.goal);
  EXPECT_EQ(a.terrain_mesh.triangles, b.terrain_mesh.triangles);
  EXPECT_EQ(a.terrain_mesh.vertices, b.terrain_mesh.vertices);
}

std::string LoadErrorMessage(const std::string& path) {
  try {
    LoadScenario(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(LoadScenario, MeshElementsInOrderWithResolvedPaths) {
  const Scenario s = LoadScenario(DataPath("with_meshes.yaml"));
  EXPECT_EQ(s.name, "mesh_terrain");
  EXPECT_EQ(s.path, DataPath("with_meshes.yaml"));
  ASSERT_EQ(s.terrain.size(), 4u);
  ASSERT_TRUE(std::holds_alternative<TerrainBox>(s.terrain[0]));
  const auto& box = std::get<TerrainBox>(s.terrain[0]);
  EXPECT_EQ(box.size, Eigen::Vector3d(6, 4, 0.5));
  EXPECT_EQ(box.position, Eigen::Vector3d(1, 0, -0.25));
  const std::vector<std::string> files = {"meshes/ramp.stl", "meshes/ramp.obj", "meshes/ramp.ply"};
  for (std::size_t i = 0; i < files.size(); ++i) {
    ASSERT_TRUE(std::holds_alternative<TerrainMeshFile>(s.terrain[i + 1]));
    const auto& mesh = std::get<TerrainMeshFile>(s.terrain[i + 1]);
    EXPECT_EQ(mesh.file, files[i]);
    EXPECT_EQ(mesh.resolved_path, std::filesystem::path(DataPath(files[i])).lexically_normal().string());
  }
  EXPECT_EQ(std::get<TerrainMeshFile>(s.terrain[2]).scale, 0.01);
  EXPECT_EQ(std::get<TerrainMeshFile>(s.terrain[2]).rpy, Eigen::Vector3d(0, 0, 1.570796));
  EXPECT_EQ(s.terrain_mesh.NumTriangles(), 12u + 3u * 8u);
  EXPECT_EQ(s.start.position, Eigen::Vector2d(-1, 0));
  EXPECT_EQ(s.start.yaw, 0.0);
  EXPECT_EQ(s.goal.position, Eigen::Vector2d(3, 0.5));
  EXPECT_EQ(s.goal.yaw, 1.5);
}

TEST(LoadScenario, MeshesArePlacedByScaleRotationAndPosition) {
  const Scenario s = LoadScenario(DataPath("with_meshes.yaml"));
  // STL ramp at (0, -1.5, 0): rises 0.2 m over x [0, 1].
  EXPECT_NEAR(*TerrainHeightAt(s.terrain_mesh, {0.5, -1.2}), 0.1, 1e-6);
  // OBJ ramp (cm, scale 0.01) turned +90 deg about z at (2, -0.5, 0): its x axis is world +y.
  EXPECT_NEAR(*TerrainHeightAt(s.terrain_mesh, {2.0 - 0.3, -0.5 + 0.75}), 0.15, 1e-5);
  EXPECT_NEAR(*TerrainHeightAt(s.terrain_mesh, {2.0 - 0.3, -0.5 + 0.25}), 0.05, 1e-5);
  // PLY ramp scaled 2 at (2.5, 1, 0.5): 2 m long, rising 0.4 m.
  EXPECT_NEAR(*TerrainHeightAt(s.terrain_mesh, {2.5 + 1.0, 1.0 + 0.6}), 0.5 + 0.2, 1e-6);
  // Beside the ramps: the floor.
  EXPECT_NEAR(*TerrainHeightAt(s.terrain_mesh, {-1.0, 1.5}), 0.0, 1e-12);
}

TEST(ScenarioToYaml, RoundTripGivesTheSameScenarioAndText) {
  const Scenario s = LoadScenario(DataPath("with_meshes.yaml"));
  const std::string text = ScenarioToYaml(s);
  const Scenario again = ParseScenario(text, s.path);
  ExpectSameScenario(again, s);
  EXPECT_EQ(ScenarioToYaml(again), text);
}

TEST(ScenarioToYaml, RoundTripThroughAFileElsewhere) {
  test::ScratchDir dir;
  Scenario s;
  s.name = "two_boxes";
  TerrainBox floor;
  floor.size = {3, 2, 0.5};
  floor.position = {0.5, 0, -0.25};
  TerrainBox block;
  block.size = {0.3, 0.21, 0.3};
  block.position = {0.25, -0.125, 0.061177};
  block.rpy = {0.261799, 0, -0.5};
  s.terrain = {floor, block};
  s.terrain_mesh = BuildTerrainMesh(s.terrain);
  s.start.position = {-0.5, 0.25};
  s.goal.position = {1.5, -0.5};
  s.goal.yaw = 3.0;
  const std::string path = (dir.path() / "two_boxes.yaml").string();
  std::ofstream(path) << ScenarioToYaml(s, {"a comment"});
  const Scenario loaded = LoadScenario(path);
  ExpectSameScenario(loaded, s);
  EXPECT_EQ(loaded.path, path);
}

TEST(ScenarioToYaml, CanonicalText) {
  Scenario s;
  s.name = "canonical";
  TerrainBox box;
  box.size = {1.0, 0.1 + 0.2, 2.5};
  box.position = {-0.0, 1e-9, -1234.5678904};
  box.rpy = {M_PI / 12.0, -0.0000004, 0.0000006};
  TerrainMeshFile mesh;
  mesh.file = "meshes/a b,c.stl";
  mesh.position = {1, 2, 3};
  mesh.rpy = {0, 0, 0};
  mesh.scale = 0.001;
  s.terrain = {box, mesh};
  s.start.position = {0.5, -0.25};
  s.start.yaw = -M_PI;
  s.goal.position = {10, 0};
  s.goal.yaw = 0.0;
  EXPECT_EQ(ScenarioToYaml(s, {"line one", "line two"}),
            "# line one\n"
            "# line two\n"
            "name: canonical\n"
            "terrain:\n"
            "  - box: {size: [1, 0.3, 2.5], position: [0, 0, -1234.56789], rpy: [0.261799, 0, 0.000001]}\n"
            "  - mesh: {file: \"meshes/a b,c.stl\", position: [1, 2, 3], rpy: [0, 0, 0], scale: 0.001}\n"
            "start: {position: [0.5, -0.25], yaw: -3.141593}\n"
            "goal: {position: [10, 0], yaw: 0}\n");
}

TEST(LoadScenario, BadFilesNameTheFileAndTheProblem) {
  struct Case {
    std::string file;
    std::vector<std::string> expected;  // parts the message must contain, besides the file path
  };
  const std::vector<Case> cases = {
      {"does_not_exist.yaml", {"cannot open scenario file"}},
      {"bad_yaml_syntax.yaml", {"invalid YAML"}},
      {"bad_missing_mesh.yaml", {"terrain[1]", DataPath("meshes/does_not_exist.stl"), "mesh file not found"}},
      {"bad_degenerate_mesh.yaml",
       {"terrain[1]", DataPath("meshes/degenerate.stl"), "degenerate mesh: triangle 1 is degenerate (area 0 m^2)"}},
      {"bad_empty_mesh.yaml",
       {"terrain[1]", DataPath("meshes/no_faces.obj"), "degenerate mesh: mesh has no triangles"}},
      {"bad_unreadable_mesh.yaml", {"terrain[1]", DataPath("meshes/garbage.stl"), "cannot read mesh"}},
      {"bad_mesh_format.yaml", {"terrain[1]", "expected an .stl, .obj or .ply mesh file, got extension '.dae'"}},
      {"bad_scale.yaml", {"terrain[1]: mesh: 'scale': expected a positive scale, got 0"}},
      {"bad_nan.yaml", {"terrain[1]: box: 'position': element 1: expected a finite number, got .nan"}},
      {"bad_inf.yaml", {"start: 'yaw': expected a finite number, got .inf"}},
      {"bad_unknown_key.yaml", {"terrain[1]: box: 'colour': unknown key"}},
      {"bad_unknown_top_key.yaml", {"'seed': unknown key"}},
      {"bad_element_type.yaml", {"terrain[1]: 'cylinder': unknown key (expected 'box' or 'mesh')"}},
      {"bad_missing_key.yaml", {"'goal': missing key"}},
      {"bad_list_length.yaml", {"terrain[1]: box: 'size': expected a list of 3 numbers, got a list of 2"}},
      {"bad_box_size.yaml", {"terrain[1]: box: 'size': expected three positive lengths [m], got [1, -0.5, 0.5]"}},
      {"bad_goal_off_terrain.yaml",
       {"'goal': expected terrain below the base position, got none at (5.000000, 0.000000)"}},
  };
  for (const Case& c : cases) {
    const std::string message = LoadErrorMessage(DataPath(c.file));
    EXPECT_EQ(message.rfind(DataPath(c.file) + ": ", 0), 0u) << c.file << " -> " << message;
    for (const std::string& part : c.expected) {
      EXPECT_NE(message.find(part), std::string::npos) << c.file << " -> " << message << "\n  lacks: " << part;
    }
  }
}

TEST(ParseScenario, MoreProblems) {
  const std::string floor = "terrain:\n  - box: {size: [4, 2, 0.5], position: [0, 0, -0.25], rpy: [0, 0, 0]}\n";
  const std::string poses = "start: {position: [-1, 0], yaw: 0}\ngoal: {position: [1, 0], yaw: 0}\n";
  struct Case {
    std::string text;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"name: a b\n" + floor + poses, "'name': expected letters, digits, '_' or '-', got 'a b'"},
      {"name: x\nterrain: []\n" + poses, "'terrain': expected at least one terrain element, got an empty list"},
      {"name: x\n" + floor + "  - {box: {size: [1, 1, 1], position: [0, 0, 0], rpy: [0, 0, 0]}, mesh: {}}\n" + poses,
       "terrain[1]: expected exactly one of 'box' or 'mesh' per element, got 2 keys"},
      {"name: x\n" + floor + "  - box: {size: [1e-7, 1e-7, 1], position: [0, 0, 0], rpy: [0, 0, 0]}\n" + poses,
       "terrain[1]: degenerate element mesh: triangle"},
      {"name: x\n" + floor + "start: {position: [-1, 0], yaw: 0, z: 0.5}\ngoal: {position: [1, 0], yaw: 0}\n",
       "start: 'z': unknown key"},
      {"name: x\n" + floor + "start: {position: [-1, 0, 0], yaw: 0}\ngoal: {position: [1, 0], yaw: 0}\n",
       "start: 'position': expected a list of 2 numbers, got a list of 3"},
      {"- just a list\n", "expected a map, got a list of 1"},
  };
  for (const Case& c : cases) {
    try {
      ParseScenario(c.text, "");
      ADD_FAILURE() << "accepted:\n" << c.text;
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind("<scenario text>", 0), 0u) << message;
      EXPECT_NE(message.find(c.expected), std::string::npos) << message << "\n  lacks: " << c.expected;
    }
  }
}

}  // namespace
}  // namespace rbcp
