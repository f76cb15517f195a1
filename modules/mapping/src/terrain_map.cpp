#include <octomap/OcTree.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "rbcp/core/error.h"
#include "rbcp/mapping/terrain_map.h"

namespace rbcp::mapping {

namespace {

/// How much of a return's horizontal error counts as error of the height it reports (see
/// PointVariance).
constexpr double kHorizontalToVertical = 0.5;

/// The variance of the terrain height a return reports, for a unit ray direction `d`.
/// The range error sigma along the ray moves the point by sigma |d_z| vertically and by
/// sigma |d_xy| horizontally. On flat ground only the vertical part matters, but the terrain is not
/// flat: a point moved sideways lands in a neighbouring cell, whose height differs by the slope
/// times that shift, and on a block's side face a near-horizontal ray reports the height of a face
/// point, not of a cell's top. So a share of the horizontal error counts too; a horizontal ray
/// then never fuses as an exact height (its variance is at least (0.5 sigma)^2).
double PointVariance(const Eigen::Vector3d& d, double sigma, double min_variance) {
  const double dz2 = d.z() * d.z();
  const double dxy2 = std::max(0.0, 1.0 - dz2);
  const double k2 = kHorizontalToVertical * kHorizontalToVertical;
  return sigma * sigma * (dz2 + k2 * dxy2) + min_variance;
}


/// Makes `node` a leaf: its subtree's nodes are deleted. OctoMap deletes a node only when it has
/// no children array, and frees that array only in pruneNode (all eight children equal leaves), so
/// the children are completed and equalled first. (OcTree::deleteNode leaves an inner node with an
/// empty children array when it deletes its last child, and then deletes that node, which its
/// destructor refuses.)
void MakeLeaf(octomap::OcTree* tree, octomap::OcTreeNode* node) {
  for (unsigned i = 0; i < 8; ++i) {
    octomap::OcTreeNode* child =
        tree->nodeChildExists(node, i) ? tree->getNodeChild(node, i) : tree->createNodeChild(node, i);
    if (tree->nodeHasChildren(child)) MakeLeaf(tree, child);
    child->setLogOdds(0.0f);
  }
  tree->pruneNode(node);
}

/// Deletes the subtrees of `node` (at `key`, `depth`) that lie wholly outside the xy box [lo, hi];
/// returns true when nothing of `node` is left inside it (its parent deletes it then).
bool DropOutsideRecurs(octomap::OcTree* tree, octomap::OcTreeNode* node, const octomap::OcTreeKey& key,
                       unsigned depth, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  const octomap::point3d c = tree->keyToCoord(key, depth);
  const double half = 0.5 * tree->getNodeSize(depth);
  if (c.x() + half <= lo.x() || c.y() + half <= lo.y() || c.x() - half >= hi.x() || c.y() - half >= hi.y()) return true;
  if (c.x() - half >= lo.x() && c.y() - half >= lo.y() && c.x() + half <= hi.x() && c.y() + half <= hi.y()) return false;
  if (!tree->nodeHasChildren(node)) return false;  // a large leaf across the border stays
  const auto offset = static_cast<octomap::key_type>((1u << (tree->getTreeDepth() - 1)) >> (depth + 1));
  bool any_left = false;
  for (unsigned i = 0; i < 8; ++i) {
    if (!tree->nodeChildExists(node, i)) continue;
    octomap::OcTreeKey child_key;
    octomap::computeChildKey(i, offset, key, child_key);
    octomap::OcTreeNode* child = tree->getNodeChild(node, i);
    if (DropOutsideRecurs(tree, child, child_key, depth + 1, lo, hi)) {
      MakeLeaf(tree, child);
      tree->deleteNodeChild(node, i);
    } else {
      any_left = true;
    }
  }
  if (any_left) node->updateOccupancyChildren();
  return !any_left;
}

/// Deletes what the octree holds outside the xy box [lo, hi] (the window), whatever its height.
void DropOutside(octomap::OcTree* tree, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  octomap::OcTreeNode* root = tree->getRoot();
  if (root == nullptr) return;
  const auto centre = static_cast<octomap::key_type>(1u << (tree->getTreeDepth() - 1));
  if (DropOutsideRecurs(tree, root, octomap::OcTreeKey(centre, centre, centre), 0, lo, hi)) tree->clear();
}

}  // namespace

/// The occupancy octree and the scratch of one integration (kept here so that the header needs no
/// OctoMap).
struct TerrainMap::Occupancy {
  explicit Occupancy(double resolution) : tree(resolution) {}

  octomap::OcTree tree;
  octomap::Pointcloud scan;           ///< the current cloud's finite returns
  std::vector<std::uint32_t> stamp;   ///< per elevation cell: the last cloud that saw below its height
  std::vector<std::size_t> touched;   ///< the cells the current cloud saw below their height
  std::uint32_t cloud = 0;            ///< the current cloud's number
};

TerrainMap::TerrainMap(const MapperConfig& config)
    : config_((config.Validate(), config)),
      elevation_(config.elevation),
      occupancy_(std::make_unique<Occupancy>(config.occupancy.resolution_m)) {
  occupancy_->stamp.assign(static_cast<std::size_t>(elevation_.num_x()) * static_cast<std::size_t>(elevation_.num_y()),
                           0);
}

TerrainMap::~TerrainMap() = default;
TerrainMap::TerrainMap(TerrainMap&&) noexcept = default;
TerrainMap& TerrainMap::operator=(TerrainMap&&) noexcept = default;

void TerrainMap::Recenter(const Eigen::Vector2d& robot_xy) {
  const Eigen::Vector2d before = elevation_.origin();
  elevation_.Recenter(robot_xy);
  const Eigen::Vector2d lo = elevation_.origin();
  if (lo == before) return;
  // The window's cells changed: cell stamps refer to other cells now, and the octree keeps only
  // what lies over the window (its memory stays bounded however far the robot walks).
  std::fill(occupancy_->stamp.begin(), occupancy_->stamp.end(), 0);
  occupancy_->cloud = 0;
  const Eigen::Vector2d hi = lo + Eigen::Vector2d(elevation_.num_x(), elevation_.num_y()) * elevation_.resolution();
  DropOutside(&occupancy_->tree, lo, hi);
}

IntegrateReport TerrainMap::Integrate(const WorldCloud& cloud) {
  if (!cloud.origin.allFinite()) {
    throw InputError("TerrainMap::Integrate: expected a finite cloud origin, got a NaN or inf");
  }
  if (cloud.points.size() > static_cast<std::size_t>(config_.max_points_per_cloud)) {
    throw InputError("TerrainMap::Integrate: expected at most max_points_per_cloud = " +
                     std::to_string(config_.max_points_per_cloud) + " points, got " +
                     std::to_string(cloud.points.size()));
  }
  if (!std::isfinite(cloud.range_noise_std) || cloud.range_noise_std < 0.0) {
    throw InputError("TerrainMap::Integrate: expected a range_noise_std >= 0, got " +
                     std::to_string(cloud.range_noise_std));
  }
  IntegrateReport report;
  if (cloud.points.empty()) return report;
  if (!elevation_.placed()) Recenter(cloud.origin.head<2>());  // no window yet: it starts around the sensor
  Occupancy& occ = *occupancy_;
  if (++occ.cloud == 0) {  // the stamps wrapped around: start over
    std::fill(occ.stamp.begin(), occ.stamp.end(), 0);
    occ.cloud = 1;
  }
  occ.scan.clear();
  occ.scan.reserve(cloud.points.size());
  occ.touched.clear();
  const double max_range = config_.occupancy.max_range_m;
  const double min_var = config_.elevation.min_variance_m2;
  for (const Eigen::Vector3d& p : cloud.points) {
    if (!p.allFinite()) {
      ++report.points_invalid;
      continue;
    }
    // Every finite return goes to the octree, which frees its ray up to max_range_m.
    occ.scan.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
    const Eigen::Vector3d ray = p - cloud.origin;
    const double range = ray.norm();
    const auto index = elevation_.Index(p.head<2>());
    if (range > max_range || range <= 0.0 || !index) {
      ++report.points_outside;
      continue;
    }
    const double variance = PointVariance(ray / range, cloud.range_noise_std, min_var);
    const double offset = (p.head<2>() - elevation_.CellCentre(index->first, index->second)).norm();
    if (elevation_.FuseCell(index->first, index->second, p.z(), variance, offset) != ElevationMap::FuseOutcome::kGated) {
      ++report.points_fused;
      continue;
    }
    ++report.points_gated;
    // A return below the cell's height: the cell is a candidate for clearing (below).
    const std::size_t cell = static_cast<std::size_t>(index->second) * static_cast<std::size_t>(elevation_.num_x()) +
                             static_cast<std::size_t>(index->first);
    if (p.z() < elevation_.At(index->first, index->second)->height && occ.stamp[cell] != occ.cloud) {
      occ.stamp[cell] = occ.cloud;
      occ.touched.push_back(cell);
    }
  }
  if (occ.scan.size() == 0) return report;
  const octomap::point3d origin(static_cast<float>(cloud.origin.x()), static_cast<float>(cloud.origin.y()),
                                static_cast<float>(cloud.origin.z()));
  occ.tree.insertPointCloud(occ.scan, origin, max_range);

  // A cell's height that rays passed through is no longer there (a box taken away). Only cells
  // where this cloud saw a surface below the cell's height are checked (not those the rays merely
  // grazed, nor those seen again at their height), and only when the octree knows both voxels
  // within half a voxel of the height to be free: a surface lying near a voxel's face (the ground at
  // z = 0 with voxels on multiples of the resolution) keeps the occupied voxel next to it.
  const double half_voxel = 0.5 * config_.occupancy.resolution_m;
  const auto free_at = [&](double x, double y, double z) {
    const octomap::OcTreeNode* node = occ.tree.search(x, y, z);
    return node != nullptr && node->getOccupancy() <= config_.occupancy.clear_probability;
  };
  const int n = elevation_.num_x();
  for (const std::size_t cell : occ.touched) {
    const int ix = static_cast<int>(cell % static_cast<std::size_t>(n));
    const int iy = static_cast<int>(cell / static_cast<std::size_t>(n));
    const auto known = elevation_.At(ix, iy);
    if (!known) continue;
    const Eigen::Vector2d c = elevation_.CellCentre(ix, iy);
    if (free_at(c.x(), c.y(), known->height - half_voxel) && free_at(c.x(), c.y(), known->height + half_voxel)) {
      elevation_.Clear(ix, iy);
      ++report.cells_cleared;
    }
  }
  return report;
}

void TerrainMap::IntegrateContact(const Eigen::Vector3d& contact, double variance) {
  if (!contact.allFinite() || !std::isfinite(variance) || variance < 0.0) {
    throw InputError("TerrainMap::IntegrateContact: expected a finite contact and variance >= 0");
  }
  const auto centre = elevation_.Index(contact.head<2>());
  if (!centre) return;
  const double radius = config_.foot_patch_radius_m;
  const int reach = static_cast<int>(std::ceil(radius / elevation_.resolution()));
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const int ix = centre->first + dx, iy = centre->second + dy;
      // The cell under the contact always; its neighbours when their centre is under the sole.
      const double offset = (elevation_.CellCentre(ix, iy) - contact.head<2>()).norm();
      if ((dx != 0 || dy != 0) && offset > radius) continue;
      elevation_.FuseCell(ix, iy, contact.z(), variance, offset, /*gate=*/false);
    }
  }
}

void TerrainMap::InitializeFootprint(const std::vector<Eigen::Vector3d>& feet, double margin_m, double variance) {
  if (feet.size() < 3 || !std::isfinite(variance) || variance <= 0.0 || !(margin_m >= 0.0)) {
    throw InputError(
        "TerrainMap::InitializeFootprint: expected at least three feet, a margin >= 0 and a positive variance");
  }
  for (const Eigen::Vector3d& f : feet) {
    if (!f.allFinite()) throw InputError("TerrainMap::InitializeFootprint: a foot is not finite");
  }
  if (!elevation_.placed()) elevation_.Recenter(feet.front().head<2>());
  // The plane z = a x + b y + c through the feet, least squares.
  Eigen::MatrixXd A(static_cast<Eigen::Index>(feet.size()), 3);
  Eigen::VectorXd z(static_cast<Eigen::Index>(feet.size()));
  for (std::size_t i = 0; i < feet.size(); ++i) {
    A.row(static_cast<Eigen::Index>(i)) << feet[i].x(), feet[i].y(), 1.0;
    z(static_cast<Eigen::Index>(i)) = feet[i].z();
  }
  const Eigen::Vector3d plane = A.colPivHouseholderQr().solve(z);
  // The feet's polygon: their convex hull (gift wrapping; four points at most in practice).
  std::vector<Eigen::Vector2d> hull;
  std::vector<Eigen::Vector2d> pts;
  for (const Eigen::Vector3d& f : feet) pts.push_back(f.head<2>());
  std::size_t start = 0;
  for (std::size_t i = 1; i < pts.size(); ++i) {
    if (pts[i].x() < pts[start].x() || (pts[i].x() == pts[start].x() && pts[i].y() < pts[start].y())) start = i;
  }
  std::size_t p = start;
  do {
    hull.push_back(pts[p]);
    std::size_t q = (p + 1) % pts.size();
    for (std::size_t r = 0; r < pts.size(); ++r) {
      const Eigen::Vector2d a = pts[q] - pts[p], b = pts[r] - pts[p];
      if (a.x() * b.y() - a.y() * b.x() < 0.0) q = r;  // r lies clockwise of p->q: a tighter hull
    }
    p = q;
  } while (p != start && hull.size() <= pts.size());
  if (hull.size() < 3) return;  // the feet on a line: no area to fill
  // Inside the polygon, or within `margin_m` of it: the ground around each foot.
  const auto inside = [&](const Eigen::Vector2d& c) {
    bool in = true;
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < hull.size(); ++i) {
      const Eigen::Vector2d a = hull[(i + 1) % hull.size()] - hull[i], b = c - hull[i];
      if (a.x() * b.y() - a.y() * b.x() < 0.0) in = false;
      const double t = std::clamp(a.dot(b) / a.squaredNorm(), 0.0, 1.0);
      nearest = std::min(nearest, (b - t * a).norm());
    }
    return in || nearest <= margin_m;
  };
  for (int iy = 0; iy < elevation_.num_y(); ++iy) {
    for (int ix = 0; ix < elevation_.num_x(); ++ix) {
      const Eigen::Vector2d c = elevation_.CellCentre(ix, iy);
      if (elevation_.At(ix, iy) || !inside(c)) continue;
      elevation_.FuseCell(ix, iy, plane.x() * c.x() + plane.y() * c.y() + plane.z(), variance, 0.0, /*gate=*/false);
    }
  }
}

TriangleMesh TerrainMap::ToMesh() const {
  std::vector<float> heights = elevation_.MeshHeights();
  const octomap::OcTree& tree = occupancy_->tree;
  const double r = elevation_.resolution();
  const int n = elevation_.num_x();
  const Eigen::Vector2d origin = elevation_.origin();
  constexpr float kNone = std::numeric_limits<float>::quiet_NaN();
  // In the octree column through each known cell's centre: the lowest occupied voxel's centre and
  // the highest one's top.
  std::vector<float> bottom(heights.size(), kNone), top(heights.size(), kNone);
  // The cells whose centre lies in [lo, hi) along one axis.
  const auto centres_in = [&](double lo, double hi, double o) {
    const int first = static_cast<int>(std::ceil((lo - o) / r - 0.5));
    const int last = static_cast<int>(std::ceil((hi - o) / r - 0.5)) - 1;
    return std::make_pair(std::max(first, 0), std::min(last, n - 1));
  };
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const double half = 0.5 * it.getSize();
    const float z = static_cast<float>(it.getZ()), z_top = static_cast<float>(it.getZ() + half);
    const auto [x0, x1] = centres_in(it.getX() - half, it.getX() + half, origin.x());
    const auto [y0, y1] = centres_in(it.getY() - half, it.getY() + half, origin.y());
    for (int iy = y0; iy <= y1; ++iy) {
      for (int ix = x0; ix <= x1; ++ix) {
        const std::size_t i = static_cast<std::size_t>(iy) * static_cast<std::size_t>(n) + static_cast<std::size_t>(ix);
        if (std::isnan(heights[i])) continue;
        if (std::isnan(bottom[i]) || z < bottom[i]) bottom[i] = z;
        if (std::isnan(top[i]) || z_top > top[i]) top[i] = z_top;
      }
    }
  }
  // A column standing more than obstacle_rise_m above the cell's height or its own foot (a face
  // seen from the side) is an obstacle: the cell goes to its top, and higher when no ray ever
  // showed what is above that top. A column whose top was seen within a voxel of the cell's
  // height is that surface, not something standing on it: a voxel straddling a block's edge holds
  // the floor at the block's foot and the block's top, and its top is the top's returns rounded
  // up to the voxel (up to 5 cm above the top the elevation map measured).
  const float voxel = static_cast<float>(config_.occupancy.resolution_m);
  const float half_voxel = 0.5f * voxel;
  const float rise = static_cast<float>(config_.occupancy.obstacle_rise_m);
  for (int iy = 0; iy < n; ++iy) {
    for (int ix = 0; ix < n; ++ix) {
      const std::size_t i = static_cast<std::size_t>(iy) * static_cast<std::size_t>(n) + static_cast<std::size_t>(ix);
      if (std::isnan(top[i]) || top[i] - half_voxel - std::min(heights[i], bottom[i]) <= rise) continue;
      const Eigen::Vector2d c = elevation_.CellCentre(ix, iy);
      const bool top_seen = tree.search(c.x(), c.y(), top[i] + half_voxel) != nullptr;
      if (top_seen && top[i] - half_voxel - heights[i] <= voxel) continue;
      heights[i] = std::max(heights[i], top[i]) + (top_seen ? 0.0f : static_cast<float>(config_.occupancy.unseen_top_m));
    }
  }
  return elevation_.MeshOf(heights);
}

std::size_t TerrainMap::MemoryBytes() const {
  const Occupancy& occ = *occupancy_;
  return sizeof(*this) + elevation_.MemoryBytes() + sizeof(Occupancy) + occ.tree.memoryUsage() +
         occ.scan.size() * sizeof(octomap::point3d) + occ.stamp.capacity() * sizeof(std::uint32_t) +
         occ.touched.capacity() * sizeof(std::size_t);
}

std::size_t TerrainMap::OccupancyNodes() const { return occupancy_->tree.size(); }

}  // namespace rbcp::mapping
