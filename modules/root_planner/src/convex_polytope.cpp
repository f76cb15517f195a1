#include "rbcp/root_planner/convex_polytope.h"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

Eigen::Vector3d FaceNormal(const ConvexPolytope& poly, const std::array<int, 3>& tri) {
  const Eigen::Vector3d& a = poly.vertices[static_cast<std::size_t>(tri[0])];
  const Eigen::Vector3d& b = poly.vertices[static_cast<std::size_t>(tri[1])];
  const Eigen::Vector3d& c = poly.vertices[static_cast<std::size_t>(tri[2])];
  return (b - a).cross(c - a);
}

// Face planes (unit normal, offset) with n.x <= offset inside.
std::vector<std::pair<Eigen::Vector3d, double>> FacePlanes(const ConvexPolytope& poly) {
  std::vector<std::pair<Eigen::Vector3d, double>> planes;
  planes.reserve(poly.triangles.size());
  for (const auto& tri : poly.triangles) {
    Eigen::Vector3d n = FaceNormal(poly, tri);
    const double norm = n.norm();
    if (norm <= 0.0) continue;
    n /= norm;
    planes.emplace_back(n, n.dot(poly.vertices[static_cast<std::size_t>(tri[0])]));
  }
  return planes;
}

// RAII owner of a Qhull run and of the stream receiving its messages.
class QhullRun {
 public:
  explicit QhullRun(std::vector<double>& coordinates) {
    err_ = open_memstream(&err_text_, &err_size_);
    qh_zero(&qh_, err_);
    const int n = static_cast<int>(coordinates.size() / 3);
    char options[] = "qhull Qt";
    exit_code_ = qh_new_qhull(&qh_, 3, n, coordinates.data(), False, options, nullptr, err_);
  }
  ~QhullRun() {
    qh_freeqhull(&qh_, !qh_ALL);
    int curlong = 0;
    int totlong = 0;
    qh_memfreeshort(&qh_, &curlong, &totlong);
    if (err_ != nullptr) std::fclose(err_);
    std::free(err_text_);
  }
  QhullRun(const QhullRun&) = delete;
  QhullRun& operator=(const QhullRun&) = delete;

  bool Ok() const { return exit_code_ == 0; }
  std::string Errors() {
    std::fflush(err_);
    return err_text_ != nullptr ? std::string(err_text_, err_size_) : std::string();
  }
  qhT* Qh() { return &qh_; }

 private:
  qhT qh_{};
  FILE* err_ = nullptr;
  char* err_text_ = nullptr;
  std::size_t err_size_ = 0;
  int exit_code_ = 0;
};

}  // namespace

double ConvexPolytope::Volume() const {
  double six_volume = 0.0;
  for (const auto& tri : triangles) {
    six_volume += vertices[static_cast<std::size_t>(tri[0])].dot(
        vertices[static_cast<std::size_t>(tri[1])].cross(vertices[static_cast<std::size_t>(tri[2])]));
  }
  return six_volume / 6.0;
}

Eigen::Vector3d ConvexPolytope::Centroid() const {
  // Sum of tetrahedra (origin, triangle) weighted by signed volume.
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
  double six_volume = 0.0;
  for (const auto& tri : triangles) {
    const Eigen::Vector3d& a = vertices[static_cast<std::size_t>(tri[0])];
    const Eigen::Vector3d& b = vertices[static_cast<std::size_t>(tri[1])];
    const Eigen::Vector3d& c = vertices[static_cast<std::size_t>(tri[2])];
    const double v = a.dot(b.cross(c));
    weighted += v * (a + b + c) / 4.0;
    six_volume += v;
  }
  RBCP_CHECK(six_volume > 0.0, "centroid of a polytope without volume");
  return weighted / six_volume;
}

double ConvexPolytope::PlaneDistance(const Eigen::Vector3d& p) const {
  double d = -std::numeric_limits<double>::infinity();
  for (const auto& [n, offset] : FacePlanes(*this)) d = std::max(d, n.dot(p) - offset);
  return d;
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> ConvexPolytope::Bounds() const {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& v : vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  return {lo, hi};
}

ConvexPolytope ConvexPolytope::Scaled(double factor, const Eigen::Vector3d& center) const {
  RBCP_CHECK(factor > 0.0, "scale factor must be positive");
  ConvexPolytope scaled = *this;
  for (auto& v : scaled.vertices) v = center + factor * (v - center);
  return scaled;
}

TriangleMesh ConvexPolytope::ToMesh() const {
  TriangleMesh mesh;
  mesh.vertices = vertices;
  mesh.triangles = triangles;
  return mesh;
}

PolytopeTriangleTest::PolytopeTriangleTest(const ConvexPolytope& polytope) : vertices_(polytope.vertices) {
  // Directions equal up to this (1 - cosine) are one axis.
  constexpr double kSame = 1e-9;
  const auto known = [](const std::vector<Eigen::Vector3d>& axes, const Eigen::Vector3d& d, bool up_to_sign) {
    return std::any_of(axes.begin(), axes.end(), [&](const Eigen::Vector3d& a) {
      const double c = a.dot(d);
      return (up_to_sign ? std::abs(c) : c) > 1.0 - kSame;
    });
  };
  for (const auto& [n, offset] : FacePlanes(polytope)) {
    if (known(face_normals_, n, /*up_to_sign=*/false)) continue;
    face_normals_.push_back(n);
    face_offsets_.push_back(offset);
  }
  for (const auto& tri : polytope.triangles) {
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d d = polytope.vertices[static_cast<std::size_t>(tri[(k + 1) % 3])] -
                          polytope.vertices[static_cast<std::size_t>(tri[k])];
      const double norm = d.norm();
      if (norm <= 0.0) continue;
      d /= norm;
      if (!known(edge_directions_, d, /*up_to_sign=*/true)) edge_directions_.push_back(d);
    }
  }
}

bool PolytopeTriangleTest::Overlaps(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) const {
  // Separated along `axis` when the triangle's and the polytope's projections do not meet.
  const auto separated = [&](const Eigen::Vector3d& axis) {
    const double pa = axis.dot(a), pb = axis.dot(b), pc = axis.dot(c);
    const double t_lo = std::min({pa, pb, pc});
    const double t_hi = std::max({pa, pb, pc});
    double p_lo = std::numeric_limits<double>::infinity();
    double p_hi = -p_lo;
    for (const Eigen::Vector3d& v : vertices_) {
      const double pv = axis.dot(v);
      p_lo = std::min(p_lo, pv);
      p_hi = std::max(p_hi, pv);
    }
    return t_lo > p_hi || t_hi < p_lo;
  };
  for (std::size_t f = 0; f < face_normals_.size(); ++f) {
    const Eigen::Vector3d& n = face_normals_[f];
    if (std::min({n.dot(a), n.dot(b), n.dot(c)}) > face_offsets_[f]) return false;
  }
  // Axes shorter than this carry no direction: parallel edges, or a degenerate triangle.
  constexpr double kTiny = 1e-12;
  const std::array<Eigen::Vector3d, 3> edges = {b - a, c - b, a - c};
  const Eigen::Vector3d normal = edges[0].cross(-edges[2]);
  if (normal.squaredNorm() > kTiny * kTiny && separated(normal)) return false;
  for (const Eigen::Vector3d& e : edge_directions_) {
    for (const Eigen::Vector3d& f : edges) {
      const Eigen::Vector3d axis = e.cross(f);
      if (axis.squaredNorm() > kTiny * kTiny && separated(axis)) return false;
    }
  }
  // A degenerate triangle needs no more axes: a segment is separated (if at all) along a face
  // normal or an edge cross product, a point along a face normal.
  return true;
}

ConvexPolytope ConvexHull(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 4) {
    throw InputError("convex hull: expected at least 4 points, got " + std::to_string(points.size()));
  }
  std::vector<double> coordinates;
  coordinates.reserve(3 * points.size());
  for (const auto& p : points) {
    if (!p.allFinite()) throw InputError("convex hull: expected finite points, got a non-finite coordinate");
    coordinates.insert(coordinates.end(), {p.x(), p.y(), p.z()});
  }
  QhullRun run(coordinates);
  if (!run.Ok()) {
    throw InputError("convex hull: expected points spanning a volume, Qhull failed: " + run.Errors());
  }
  qhT* qh = run.Qh();
  ConvexPolytope hull;
  std::map<int, int> index_of_point;  // input point id -> hull vertex index (ordered: deterministic)
  facetT* facet = nullptr;
  vertexT* vertex = nullptr;
  vertexT** vertexp = nullptr;
  FORALLfacets {
    std::array<int, 3> tri{};
    int k = 0;
    FOREACHvertex_(facet->vertices) {
      if (k < 3) tri[static_cast<std::size_t>(k)] = qh_pointid(qh, vertex->point);
      ++k;
    }
    RBCP_CHECK(k == 3, "Qhull returned a non-triangular facet");
    for (int& id : tri) {
      auto [it, inserted] = index_of_point.emplace(id, 0);
      if (inserted) {
        it->second = static_cast<int>(hull.vertices.size());
        hull.vertices.push_back(points[static_cast<std::size_t>(id)]);
      }
      id = it->second;
    }
    const Eigen::Vector3d normal(facet->normal[0], facet->normal[1], facet->normal[2]);
    const Eigen::Vector3d& a = hull.vertices[static_cast<std::size_t>(tri[0])];
    const Eigen::Vector3d& b = hull.vertices[static_cast<std::size_t>(tri[1])];
    const Eigen::Vector3d& c = hull.vertices[static_cast<std::size_t>(tri[2])];
    if ((b - a).cross(c - a).dot(normal) < 0.0) std::swap(tri[1], tri[2]);
    hull.triangles.push_back(tri);
  }
  return hull;
}

ConvexPolytope SimplifiedConvexHull(const std::vector<Eigen::Vector3d>& points, int max_triangles, double tolerance) {
  RBCP_CHECK(max_triangles >= 4, "a polytope needs at least 4 triangles");
  const ConvexPolytope full = ConvexHull(points);
  if (static_cast<int>(full.triangles.size()) <= max_triangles) return full;
  const std::vector<Eigen::Vector3d>& candidates = full.vertices;
  const std::size_t n = candidates.size();
  std::vector<bool> chosen(n, false);
  std::vector<Eigen::Vector3d> subset;
  auto choose = [&](std::size_t i) {
    chosen[i] = true;
    subset.push_back(candidates[i]);
  };
  // Seed with a large tetrahedron: the farthest pair from the first vertex, then the farthest
  // point from their line, then from their plane.
  auto argmax = [&](auto&& score) {
    std::size_t best = 0;
    double best_score = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; ++i) {
      if (chosen[i]) continue;
      const double s = score(candidates[i]);
      if (s > best_score) {
        best_score = s;
        best = i;
      }
    }
    return best;
  };
  const std::size_t a = argmax([&](const Eigen::Vector3d& p) { return (p - candidates[0]).squaredNorm(); });
  choose(a);
  const std::size_t b = argmax([&](const Eigen::Vector3d& p) { return (p - subset[0]).squaredNorm(); });
  choose(b);
  const Eigen::Vector3d axis = (subset[1] - subset[0]).normalized();
  const std::size_t c = argmax([&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d d = p - subset[0];
    return (d - d.dot(axis) * axis).squaredNorm();
  });
  choose(c);
  const Eigen::Vector3d plane_normal = (subset[1] - subset[0]).cross(subset[2] - subset[0]).normalized();
  const std::size_t d = argmax([&](const Eigen::Vector3d& p) { return std::abs((p - subset[0]).dot(plane_normal)); });
  choose(d);

  ConvexPolytope current = ConvexHull(subset);
  while (true) {
    const auto planes = FacePlanes(current);
    std::size_t best = n;
    double best_distance = tolerance;
    for (std::size_t i = 0; i < n; ++i) {
      if (chosen[i]) continue;
      double dist = -std::numeric_limits<double>::infinity();
      for (const auto& [normal, offset] : planes) dist = std::max(dist, normal.dot(candidates[i]) - offset);
      if (dist > best_distance) {
        best_distance = dist;
        best = i;
      }
    }
    if (best == n) break;
    std::vector<Eigen::Vector3d> grown = subset;
    grown.push_back(candidates[best]);
    ConvexPolytope next = ConvexHull(grown);
    if (static_cast<int>(next.triangles.size()) > max_triangles) break;
    choose(best);
    current = std::move(next);
  }
  return current;
}

void SaveObj(const ConvexPolytope& polytope, const std::string& path, const std::vector<std::string>& comments) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": expected a writable file, could not open it");
  for (const auto& line : comments) out << "# " << line << "\n";
  out << std::setprecision(17);
  for (const auto& v : polytope.vertices) out << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const auto& t : polytope.triangles) out << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
  if (!out) throw InputError(path + ": writing failed");
}

ConvexPolytope LoadConvexObj(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": expected a readable OBJ file, could not open it");
  ConvexPolytope poly;
  std::string line;
  int line_number = 0;
  std::vector<std::array<long, 3>> faces;
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream ls(line);
    std::string tag;
    if (!(ls >> tag) || tag[0] == '#') continue;
    const std::string where = path + ":" + std::to_string(line_number);
    if (tag == "v") {
      Eigen::Vector3d v;
      if (!(ls >> v.x() >> v.y() >> v.z()) || !v.allFinite()) {
        throw InputError(where + ": expected 'v x y z' with three finite numbers, got '" + line + "'");
      }
      poly.vertices.push_back(v);
    } else if (tag == "f") {
      std::array<long, 3> f{};
      std::string extra;
      for (auto& index : f) {
        std::string token;
        if (!(ls >> token)) throw InputError(where + ": expected a triangle 'f i j k', got '" + line + "'");
        index = std::strtol(token.c_str(), nullptr, 10);  // "i/t/n" forms keep the vertex index
      }
      if (ls >> extra) throw InputError(where + ": expected a triangle 'f i j k', got a polygon '" + line + "'");
      faces.push_back(f);
    }
  }
  const long nv = static_cast<long>(poly.vertices.size());
  for (std::size_t i = 0; i < faces.size(); ++i) {
    std::array<int, 3> tri{};
    for (std::size_t k = 0; k < 3; ++k) {
      const long index = faces[i][k];
      if (index < 1 || index > nv) {
        throw InputError(path + ": face " + std::to_string(i + 1) + ": expected vertex indices in [1, " +
                         std::to_string(nv) + "], got " + std::to_string(index));
      }
      tri[k] = static_cast<int>(index - 1);
    }
    poly.triangles.push_back(tri);
  }
  if (poly.triangles.size() < 4) {
    throw InputError(path + ": expected a closed convex polytope, got " + std::to_string(poly.triangles.size()) +
                     " triangles");
  }
  for (const auto& [normal, offset] : FacePlanes(poly)) {
    for (const auto& v : poly.vertices) {
      if (normal.dot(v) - offset > 1e-6) {
        throw InputError(path + ": expected a convex polytope with outward faces, got a vertex " +
                         std::to_string(normal.dot(v) - offset) + " m outside a face plane");
      }
    }
  }
  if (poly.Volume() <= 0.0) throw InputError(path + ": expected a polytope with a positive volume");
  return poly;
}

}  // namespace rbcp
