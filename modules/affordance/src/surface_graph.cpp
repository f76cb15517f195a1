#include "rbcp/affordance/surface_graph.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "rbcp/core/segment_distance.h"

namespace rbcp {
namespace {

/// The point's projection onto the polygon's plane lies inside the polygon.
bool ProjectsInside(const Eigen::Vector3d& p, const AffordanceSurface& s) {
  const std::size_t n = s.vertices.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& a = s.vertices[i];
    const Eigen::Vector3d& b = s.vertices[(i + 1) % n];
    if ((b - a).cross(p - a).dot(s.normal) < 0.0) return false;
  }
  return true;
}

}  // namespace

double PointPolygonDistance(const Eigen::Vector3d& p, const AffordanceSurface& s) {
  if (s.vertices.empty()) return std::numeric_limits<double>::infinity();
  if (s.vertices.size() >= 3 && ProjectsInside(p, s)) return std::abs((p - s.vertices[0]).dot(s.normal));
  double best = std::numeric_limits<double>::infinity();
  const std::size_t n = s.vertices.size();
  for (std::size_t i = 0; i < n; ++i) best = std::min(best, PointSegmentDistance(p, s.vertices[i], s.vertices[(i + 1) % n]));
  return best;
}

double PolygonDistance(const AffordanceSurface& a, const AffordanceSurface& b) {
  // Convex polygons: the closest pair is an edge pair, or a vertex of one over the other's face.
  double best = std::numeric_limits<double>::infinity();
  const std::size_t na = a.vertices.size(), nb = b.vertices.size();
  for (std::size_t i = 0; i < na; ++i) {
    for (std::size_t j = 0; j < nb; ++j) {
      best = std::min(best, SegmentSegmentDistance(a.vertices[i], a.vertices[(i + 1) % na], b.vertices[j], b.vertices[(j + 1) % nb]));
    }
  }
  for (const Eigen::Vector3d& v : a.vertices) best = std::min(best, PointPolygonDistance(v, b));
  for (const Eigen::Vector3d& v : b.vertices) best = std::min(best, PointPolygonDistance(v, a));
  return best;
}

SurfaceGraph::SurfaceGraph(const std::vector<AffordanceSurface>& surfaces, double max_gap_m) : surfaces_(surfaces) {
  const std::size_t n = surfaces_.size();
  lo_.assign(n, Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()));
  hi_.assign(n, Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity()));
  for (std::size_t i = 0; i < n; ++i) {
    for (const Eigen::Vector3d& v : surfaces_[i].vertices) {
      lo_[i] = lo_[i].cwiseMin(v);
      hi_[i] = hi_[i].cwiseMax(v);
    }
  }
  // Union-find over the joined pairs.
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int x) {
    while (parent[static_cast<std::size_t>(x)] != x) {
      parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
      x = parent[static_cast<std::size_t>(x)];
    }
    return x;
  };
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const Eigen::Vector3d gap = (lo_[j] - hi_[i]).cwiseMax(lo_[i] - hi_[j]).cwiseMax(0.0);
      if (gap.norm() > max_gap_m) continue;
      const int ri = find(static_cast<int>(i)), rj = find(static_cast<int>(j));
      if (ri == rj) continue;
      if (PolygonDistance(surfaces_[i], surfaces_[j]) <= max_gap_m) parent[static_cast<std::size_t>(ri)] = rj;
    }
  }
  component_.assign(n, -1);
  std::vector<int> label(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t root = static_cast<std::size_t>(find(static_cast<int>(i)));
    if (label[root] < 0) label[root] = components_++;
    component_[i] = label[root];
  }
}

std::vector<int> SurfaceGraph::SurfacesNear(const Eigen::Vector3d& point, double radius_m) const {
  std::vector<int> out;
  for (std::size_t i = 0; i < surfaces_.size(); ++i) {
    const Eigen::Vector3d gap = (lo_[i] - point).cwiseMax(point - hi_[i]).cwiseMax(0.0);
    if (gap.norm() > radius_m) continue;
    if (PointPolygonDistance(point, surfaces_[i]) <= radius_m) out.push_back(static_cast<int>(i));
  }
  return out;
}

bool SurfaceGraph::Joined(const std::vector<int>& from, const std::vector<int>& to) const {
  for (int a : from) {
    for (int b : to) {
      if (component_.at(static_cast<std::size_t>(a)) == component_.at(static_cast<std::size_t>(b))) return true;
    }
  }
  return false;
}

}  // namespace rbcp
