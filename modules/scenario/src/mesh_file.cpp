#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "rbcp/core/error.h"
#include "rbcp/scenario/scenario.h"

namespace rbcp {
namespace {

/// The file system as the importer sees it: nothing but the mesh's bytes, which the importer reads
/// from memory. An OBJ's mtllib line, for one, may name any file; a missing material leaves the
/// default one.
class NoFiles : public Assimp::IOSystem {
 public:
  bool Exists(const char*) const override { return false; }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char*, const char*) override { return nullptr; }
  void Close(Assimp::IOStream* stream) override { delete stream; }
};

/// Bytes of one value of a PLY scalar type, 0 for an unknown type.
std::uint64_t PlyTypeBytes(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" || type == "float32") {
    return 4;
  }
  if (type == "double" || type == "float64") return 8;
  return 0;
}

/// A name of a PLY element or property: letters, digits, _ - ., starting with a letter or _.
bool PlyName(const std::string& name) {
  if (name.empty() || !(std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_')) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  });
}

/// An integer PLY type, as a list's count must be.
bool PlyIntegerType(const std::string& type) {
  return PlyTypeBytes(type) > 0 && type != "float" && type != "float32" && type != "double" && type != "float64";
}

bool PlySignedType(const std::string& type) {
  return type == "char" || type == "int8" || type == "short" || type == "int16" || type == "int" || type == "int32";
}

/// One property of a PLY element: a scalar of `type`, or a list whose count is of `type` and whose
/// values take `value_bytes` each (binary).
struct PlyProperty {
  bool list = false;
  std::string type;
  std::uint64_t value_bytes = 0;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::uint64_t min_bytes = 0;
  std::vector<PlyProperty> properties;
};

/// Throws InputError unless the binary body holds every element the header declares, each list
/// with as many values as its count says (the importer reserves a list's count before reading it).
void CheckPlyBinaryBody(const std::string& path, const std::string& bytes, std::uint64_t at,
                        const std::vector<PlyElement>& elements, bool big_endian) {
  const std::uint64_t size = bytes.size();
  at = std::min(at, size);
  const auto short_of = [&](const PlyElement& e, std::uint64_t i) {
    throw InputError(path + ": the PLY body ends inside " + e.name + " element " + std::to_string(i) + " of " +
                     std::to_string(e.count) + " the header declares");
  };
  for (const PlyElement& e : elements) {
    for (std::uint64_t i = 0; i < e.count; ++i) {
      for (const PlyProperty& p : e.properties) {
        const std::uint64_t n = PlyTypeBytes(p.type);
        if (size - at < n) short_of(e, i);
        if (!p.list) {
          at += n;
          continue;
        }
        std::uint64_t count = 0;
        for (std::uint64_t b = 0; b < n; ++b) {
          const auto byte = static_cast<unsigned char>(bytes[at + (big_endian ? b : n - 1 - b)]);
          count = (count << 8) | byte;
        }
        at += n;
        if (PlySignedType(p.type) && (count >> (8 * n - 1)) != 0) {
          throw InputError(path + ": " + e.name + " element " + std::to_string(i) + " has a list of negative length");
        }
        if (count > (size - at) / p.value_bytes) {
          throw InputError(path + ": " + e.name + " element " + std::to_string(i) + " has a list of " +
                           std::to_string(count) + " values, more than the file's remaining " +
                           std::to_string(size - at) + " bytes hold");
        }
        at += count * p.value_bytes;
      }
    }
  }
}

/// Throws InputError unless the ASCII body is printable text holding every element the header
/// declares, one instance a line, each line exactly the values its properties take (a list: its
/// count, then that many values).
void CheckPlyAsciiBody(const std::string& path, const std::string& bytes, std::uint64_t at,
                       const std::vector<PlyElement>& elements) {
  std::uint64_t line_number = 0;
  std::vector<std::string> words;
  // The next non-blank line's words; false at the end of the body.
  const auto next_line = [&]() {
    while (at < bytes.size()) {
      const std::size_t end = std::min(bytes.find('\n', at), bytes.size());
      ++line_number;
      words.clear();
      std::string word;
      for (std::size_t k = at; k < end; ++k) {
        const auto c = static_cast<unsigned char>(bytes[k]);
        if (c == ' ' || c == '\t' || c == '\r') {
          if (!word.empty()) words.push_back(std::move(word));
          word.clear();
        } else if (c < 0x20 || c > 0x7e) {
          throw InputError(path + ": the PLY body's line " + std::to_string(line_number) + " holds the byte " +
                           std::to_string(c) + ", expected printable text");
        } else {
          word.push_back(static_cast<char>(c));
        }
      }
      if (!word.empty()) words.push_back(std::move(word));
      at = end + 1;
      if (!words.empty()) return true;
    }
    return false;
  };
  for (const PlyElement& e : elements) {
    for (std::uint64_t i = 0; i < e.count; ++i) {
      const auto bad = [&](const std::string& what) {
        throw InputError(path + ": the PLY body's line " + std::to_string(line_number) + " (" + e.name +
                         " element " + std::to_string(i) + "): " + what);
      };
      if (!next_line()) {
        throw InputError(path + ": the PLY body ends after " + std::to_string(i) + " of the " +
                         std::to_string(e.count) + " " + e.name + " elements the header declares");
      }
      std::size_t w = 0;
      for (const PlyProperty& p : e.properties) {
        if (w >= words.size()) bad("fewer values than the element's properties");
        if (!p.list) {
          ++w;
          continue;
        }
        const std::string& count = words[w++];
        if (count.empty() || count.size() > 18 || count.find_first_not_of("0123456789") != std::string::npos) {
          bad("a list count '" + count + "', expected a number of values");
        }
        if (std::stoull(count) > words.size() - w) {
          bad("a list of " + count + " values holds " + std::to_string(words.size() - w));
        }
        w += std::stoull(count);
      }
      if (w != words.size()) bad(std::to_string(words.size()) + " values, the element's properties take " + std::to_string(w));
    }
  }
}

/// Vertices of one polygon at most: the triangulation takes time quadratic in them.
constexpr unsigned kMaxFaceVertices = 1000;

/// Bytes of a PLY header at most.
constexpr std::uint64_t kMaxPlyHeaderBytes = 65536;

/// A PLY header as read: its format ("ascii", "binary_little_endian" or "binary_big_endian"), its
/// elements in order, and its length in bytes (the line end_header included).
struct PlyHeader {
  std::string format;
  std::vector<PlyElement> elements;
  std::uint64_t bytes = 0;
};

/// Adds header line `number` (after its first) to `header`. Throws InputError unless it is a
/// complete line of the PLY format: assimp's reader skips what it does not know, and some such
/// headers sent it growing its memory for ever.
void ReadPlyHeaderLine(const std::string& path, int number, const std::string& line, PlyHeader& header) {
  const auto malformed = [&](const std::string& expected) {
    throw InputError(path + ": the PLY header's line " + std::to_string(number) + " '" + line + "': expected " +
                     expected);
  };
  std::istringstream words(line);
  std::vector<std::string> w;
  for (std::string word; words >> word;) w.push_back(word);
  const std::string keyword = w.empty() ? "" : w[0];
  if (number == 1) {
    if (line != "ply") malformed("'ply'");
  } else if (keyword == "comment" || keyword == "obj_info") {
    // free text
  } else if (keyword == "format") {
    if (w.size() != 3 || (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian")) {
      malformed("'format ascii|binary_little_endian|binary_big_endian VERSION'");
    }
    header.format = w[1];
  } else if (keyword == "element") {
    // assimp reads a name that starts with a digit as the count.
    if (w.size() != 3 || !PlyName(w[1]) || w[2].find_first_not_of("0123456789") != std::string::npos ||
        w[2].size() > 18) {
      malformed("'element NAME COUNT' (a name of letters, digits, _ - ., not starting with a digit)");
    }
    header.elements.push_back({w[1], std::stoull(w[2]), 0, {}});
  } else if (keyword == "property") {
    const bool list = w.size() == 5 && w[1] == "list" && PlyIntegerType(w[2]) && PlyTypeBytes(w[3]) > 0 &&
                      PlyName(w[4]);
    if (header.elements.empty() || header.format.empty() ||
        !(list || (w.size() == 3 && PlyTypeBytes(w[1]) > 0 && PlyName(w[2])))) {
      malformed("'property TYPE NAME' or 'property list INTEGER_TYPE TYPE NAME' of an element, after the format");
    }
    PlyElement& element = header.elements.back();
    element.properties.push_back(list ? PlyProperty{true, w[2], PlyTypeBytes(w[3])}
                                      : PlyProperty{false, w[1], PlyTypeBytes(w[1])});
    element.min_bytes += header.format == "ascii" ? 2 : PlyTypeBytes(list ? w[2] : w[1]);
  } else {
    malformed("a line of the PLY header (format, element, property, comment, end_header)");
  }
}

/// The header at the start of `bytes`. Throws InputError unless it is printable lines of the
/// format ending with a line "end_header" within kMaxPlyHeaderBytes (the importer reads a header
/// without one for ever).
PlyHeader ReadPlyHeader(const std::string& path, const std::string& bytes) {
  std::istringstream in(bytes);
  PlyHeader header;
  std::string line;
  for (int number = 1; header.bytes < kMaxPlyHeaderBytes && std::getline(in, line); ++number) {
    header.bytes += line.size() + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    for (const unsigned char c : line) {
      if ((c < 0x20 && c != '\t') || c > 0x7e) {
        throw InputError(path + ": the PLY header's line " + std::to_string(number) + " holds the byte " +
                         std::to_string(c) + ", expected printable text");
      }
    }
    if (line == "end_header") return header;
    ReadPlyHeaderLine(path, number, line, header);
  }
  throw InputError(path + ": the PLY header has no line 'end_header' in its first " +
                   std::to_string(kMaxPlyHeaderBytes) + " bytes");
}

/// Throws InputError when the element counts the header declares need more bytes than the file
/// holds after it (the importer would allocate them first): every element instance takes at
/// least its properties' sizes (binary; an empty list its count) or two characters a property
/// (ASCII).
void CheckPlyElementCounts(const std::string& path, std::uint64_t file_size, const PlyHeader& header) {
  const std::uint64_t body = file_size > header.bytes ? file_size - header.bytes : 0;
  std::uint64_t needed = 0;
  for (const PlyElement& e : header.elements) {
    if (e.properties.empty()) {
      if (e.count == 0) continue;
      throw InputError(path + ": the PLY header declares " + std::to_string(e.count) + " " + e.name +
                       " elements without a property");
    }
    if (e.count > (body - std::min(needed, body)) / e.min_bytes) {
      throw InputError(path + ": the PLY header declares " + std::to_string(e.count) + " " + e.name +
                       " elements, more than the file's " + std::to_string(body) + " bytes after the header hold");
    }
    needed += e.count * e.min_bytes;
  }
}

/// Throws InputError when the PLY file is not a header of the format (ReadPlyHeader) whose
/// element counts the file can hold (CheckPlyElementCounts), followed by a body that holds them.
void CheckPlyFile(const std::string& path, const std::string& bytes) {
  const PlyHeader header = ReadPlyHeader(path, bytes);
  CheckPlyElementCounts(path, bytes.size(), header);
  if (header.format == "ascii") {
    CheckPlyAsciiBody(path, bytes, header.bytes, header.elements);
  } else {
    CheckPlyBinaryBody(path, bytes, header.bytes, header.elements, header.format == "binary_big_endian");
  }
}

/// Throws InputError when a binary STL declares more triangles than the file holds (50 bytes
/// each after the 84-byte header).
void CheckStlCount(const std::string& path, const std::string& bytes) {
  const std::uint64_t file_size = bytes.size();
  if (file_size < 84) return;  // too short for binary: ASCII or invalid
  char head[84] = {};
  std::memcpy(head, bytes.data(), sizeof(head));
  if (std::strncmp(head, "solid", 5) == 0) {
    // "solid" starts an ASCII STL, but also some binary headers: binary only if the size matches.
    std::uint32_t n = 0;
    std::memcpy(&n, head + 80, sizeof(n));
    if (84 + 50 * static_cast<std::uint64_t>(n) != file_size) return;
  }
  std::uint32_t count = 0;
  std::memcpy(&count, head + 80, sizeof(count));  // little-endian, as STL is
  const std::uint64_t needed = 84 + 50 * static_cast<std::uint64_t>(count);
  if (needed > file_size) {
    throw InputError(path + ": the binary STL declares " + std::to_string(count) + " triangles (" +
                     std::to_string(needed) + " bytes), the file has " + std::to_string(file_size));
  }
}

/// The extension of `path` in lower case, after checking that it names a format the loader reads.
std::string MeshFormat(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".stl" && ext != ".obj" && ext != ".ply") {
    throw InputError(path + ": expected an .stl, .obj or .ply mesh file, got extension '" + ext + "'");
  }
  return ext;
}

void CheckScale(const std::string& path, double scale) {
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    std::ostringstream os;
    os << path << ": expected a positive finite mesh scale, got " << scale;
    throw InputError(os.str());
  }
}

}  // namespace

TriangleMesh LoadMeshFile(const std::string& path, double scale) {
  CheckScale(path, scale);
  MeshFormat(path);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": mesh file not found");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the mesh file");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (in.bad()) throw InputError(path + ": cannot read the mesh file");
  return ParseMeshFile(bytes.str(), path, scale);
}

TriangleMesh ParseMeshFile(const std::string& bytes, const std::string& path, double scale) {
  CheckScale(path, scale);
  const std::string ext = MeshFormat(path);
  if (ext == ".ply") CheckPlyFile(path, bytes);
  if (ext == ".stl") CheckStlCount(path, bytes);

  Assimp::Importer importer;
  importer.SetIOHandler(new NoFiles);  // the importer owns it
  // Points and lines carry no surface: drop them instead of passing them on as triangles.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // Only positions matter; without the per-face normals of STL, vertices at one place are joined.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                                          aiComponent_COLORS | aiComponent_TEXCOORDS |
                                                          aiComponent_BONEWEIGHTS | aiComponent_ANIMATIONS |
                                                          aiComponent_TEXTURES | aiComponent_LIGHTS |
                                                          aiComponent_CAMERAS | aiComponent_MATERIALS);
  // The format hint is the extension: the importer reads the bytes as that format only.
  const aiScene* scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), 0, ext.c_str() + 1);
  if (scene == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0) {
    throw InputError(path + ": cannot read mesh: " + importer.GetErrorString());
  }
  // The importers pass on what the file says, and the post-processing trusts it: a face of a PLY
  // may name a vertex the file does not have, have no vertex or tens of thousands (a list count
  // the file holds no indices for), and a mesh's primitive types (which decide what is
  // triangulated) may disagree with its faces.
  bool has_polygons = false;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    aiMesh* in = scene->mMeshes[m];  // the importer's scene, which the post-processing changes too
    unsigned types = 0;
    for (unsigned f = 0; f < in->mNumFaces; ++f) {
      const aiFace& face = in->mFaces[f];
      if (face.mNumIndices == 0) throw InputError(path + ": face " + std::to_string(f) + " has no vertex");
      if (face.mNumIndices > kMaxFaceVertices) {
        throw InputError(path + ": face " + std::to_string(f) + " has " + std::to_string(face.mNumIndices) +
                         " vertices, more than the " + std::to_string(kMaxFaceVertices) + " a face may have");
      }
      has_polygons |= face.mNumIndices >= 3;
      types |= face.mNumIndices == 1   ? aiPrimitiveType_POINT
               : face.mNumIndices == 2 ? aiPrimitiveType_LINE
               : face.mNumIndices == 3 ? aiPrimitiveType_TRIANGLE
                                       : aiPrimitiveType_POLYGON;
      for (unsigned k = 0; k < face.mNumIndices; ++k) {
        if (face.mIndices[k] >= in->mNumVertices) {
          throw InputError(path + ": face " + std::to_string(f) + " refers to vertex " +
                           std::to_string(face.mIndices[k]) + ", the mesh has " + std::to_string(in->mNumVertices));
        }
      }
    }
    in->mPrimitiveTypes = types;
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
