#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "rbcp/core/error.h"
#include "rbcp/scenario/scenario.h"

namespace rbcp {

TriangleMesh LoadMeshFile(const std::string& path, double scale) {
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    std::ostringstream os;
    os << path << ": expected a positive finite mesh scale, got " << scale;
    throw InputError(os.str());
  }
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".stl" && ext != ".obj" && ext != ".ply") {
    throw InputError(path + ": expected an .stl, .obj or .ply mesh file, got extension '" + ext + "'");
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": mesh file not found");

  Assimp::Importer importer;
  // Points and lines carry no surface: drop them instead of passing them on as triangles.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // Only positions matter; without the per-face normals of STL, vertices at one place are joined.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                                          aiComponent_COLORS | aiComponent_TEXCOORDS |
                                                          aiComponent_BONEWEIGHTS | aiComponent_ANIMATIONS |
                                                          aiComponent_TEXTURES | aiComponent_LIGHTS |
                                                          aiComponent_CAMERAS | aiComponent_MATERIALS);
  const aiScene* scene = importer.ReadFile(path, 0);
  if (scene == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0) {
    throw InputError(path + ": cannot read mesh: " + importer.GetErrorString());
  }
  bool has_polygons = false;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* in = scene->mMeshes[m];
    for (unsigned f = 0; f < in->mNumFaces; ++f) has_polygons |= in->mFaces[f].mNumIndices >= 3;
  }
  if (!has_polygons) throw InputError(path + ": degenerate mesh: mesh has no triangles");
  scene =
      importer.ApplyPostProcessing(aiProcess_RemoveComponent | aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                   aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (scene == nullptr) throw InputError(path + ": cannot read mesh: " + importer.GetErrorString());

  TriangleMesh mesh;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* in = scene->mMeshes[m];
    const int offset = static_cast<int>(mesh.vertices.size());
    for (unsigned v = 0; v < in->mNumVertices; ++v) {
      const aiVector3D& p = in->mVertices[v];
      mesh.vertices.emplace_back(scale * static_cast<double>(p.x), scale * static_cast<double>(p.y),
                                 scale * static_cast<double>(p.z));
    }
    for (unsigned f = 0; f < in->mNumFaces; ++f) {
      const aiFace& face = in->mFaces[f];
      if (face.mNumIndices != 3) continue;
      mesh.triangles.push_back({offset + static_cast<int>(face.mIndices[0]),
                                offset + static_cast<int>(face.mIndices[1]),
                                offset + static_cast<int>(face.mIndices[2])});
    }
  }
  const std::string problem = ValidateMesh(mesh);
  if (!problem.empty()) throw InputError(path + ": degenerate mesh: " + problem);
  return mesh;
}

}  // namespace rbcp
