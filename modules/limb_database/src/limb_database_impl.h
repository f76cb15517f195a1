#pragma once
// Storage of the limb database, shared by the builder, the queries and the cache reader/writer.

#include <octomap/OcTreeBase.h>
#include <octomap/OcTreeDataNode.h>
#include <octomap/OcTreeKey.h>

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "rbcp/limb_database/limb_database.h"

namespace rbcp {
namespace limb_database_detail {

/// Octree node holding the index of its cell in LegData::cells (leaves) or kNoCell (inner nodes).
using CellNode = octomap::OcTreeDataNode<std::uint32_t>;
inline constexpr std::uint32_t kNoCell = 0xFFFFFFFFu;

/// Octree of one leg's occupied cells; every leaf lies at the full depth and maps its key to a
/// cell index.
class CellTree : public octomap::OcTreeBase<CellNode> {
 public:
  explicit CellTree(double resolution) : octomap::OcTreeBase<CellNode>(resolution) {}
  /// Creates the leaf of `key` (and its ancestors) and stores `cell` in it.
  void Insert(const octomap::OcTreeKey& key, std::uint32_t cell);
  /// Cell index stored at `key`, or kNoCell.
  std::uint32_t Find(const octomap::OcTreeKey& key) const;

  /// Depth-first walk over the nodes whose keys intersect [lo, hi] (inclusive, finest depth).
  /// A node (inner or leaf) is entered only when near(centre, half_edge) holds for its cube
  /// (centre [m], half edge [m]); visit(cell) is called for every leaf entered.
  template <typename Near, typename Visit>
  void VisitLeaves(const octomap::OcTreeKey& lo, const octomap::OcTreeKey& hi, const Near& near,
                   const Visit& visit) const {
    if (root == nullptr) return;
    const auto top = static_cast<octomap::key_type>(tree_max_val);
    Walk(root, 0, octomap::OcTreeKey(top, top, top), lo, hi, near, visit);
  }

 private:
  template <typename Near, typename Visit>
  void Walk(const CellNode* node, unsigned depth, const octomap::OcTreeKey& key, const octomap::OcTreeKey& lo,
            const octomap::OcTreeKey& hi, const Near& near, const Visit& visit) const {
    if (depth == tree_depth) {
      visit(node->getValue());
      return;
    }
    // Children at depth + 1 span [k - offset, k + offset - 1] (a single key at the finest depth).
    const auto offset = static_cast<octomap::key_type>(tree_max_val >> (depth + 1));
    const double half_edge = offset > 0 ? offset * resolution : 0.5 * resolution;
    for (unsigned int i = 0; i < 8; ++i) {
      if (!nodeChildExists(node, i)) continue;
      octomap::OcTreeKey child;
      octomap::computeChildKey(i, offset, key, child);
      bool inside = true;
      Eigen::Vector3d centre;
      for (unsigned a = 0; a < 3 && inside; ++a) {
        const int first = static_cast<int>(child[a]) - offset;
        const int last = offset > 0 ? static_cast<int>(child[a]) + offset - 1 : static_cast<int>(child[a]);
        inside = first <= static_cast<int>(hi[a]) && last >= static_cast<int>(lo[a]);
        centre[a] = (static_cast<int>(child[a]) - static_cast<int>(tree_max_val) + (offset > 0 ? 0.0 : 0.5)) * resolution;
      }
      if (inside && near(centre, half_edge)) Walk(getNodeChild(node, i), depth + 1, child, lo, hi, near, visit);
    }
  }
};

/// One occupied cell as stored in memory and in the cache file (16 bytes, no padding issues).
struct CellRecord {
  std::array<std::uint16_t, 3> key;  ///< octree key (x, y, z)
  std::uint16_t unused = 0;
  std::uint32_t first_sample = 0;
  std::uint32_t num_samples = 0;
};
static_assert(sizeof(CellRecord) == 16, "CellRecord is written to the cache as raw bytes");

struct LegData {
  std::vector<double> q;       ///< 3 per sample (HAA, HFE, KFE) [rad]
  std::vector<double> foot;    ///< 3 per sample, base frame [m]
  std::vector<double> score;   ///< 1 per sample, [0, 1]
  std::vector<CellRecord> cells;  ///< sorted by key (x, then y, then z)
  std::int64_t draws = 0;
  std::unique_ptr<CellTree> tree;
  octomap::OcTreeKey key_min;  ///< bounds of the occupied keys
  octomap::OcTreeKey key_max;
  /// The cells by (x, y) key column, for queries that bound the z keys of each column: column
  /// c = (x - key_min.x) * columns_y + (y - key_min.y) holds cells[column_begin[c],
  /// column_begin[c + 1]), by ascending z key (as `cells` is sorted).
  std::vector<std::uint32_t> column_begin;
  std::size_t columns_y = 0;

  int NumSamples() const { return static_cast<int>(score.size()); }
  Eigen::Vector3d Foot(std::size_t i) const { return Eigen::Vector3d(foot[3 * i], foot[3 * i + 1], foot[3 * i + 2]); }
  /// The column holding the cells of the (x, y) key, which must lie within [key_min, key_max].
  std::size_t Column(unsigned x, unsigned y) const { return (x - key_min[0]) * columns_y + (y - key_min[1]); }
  /// Builds the octree, the key bounds and the columns from `cells` (sorted by key).
  void Index(double resolution);
};

}  // namespace limb_database_detail

struct LimbDatabase::Impl {
  double resolution = 0.01;
  std::array<limb_database_detail::LegData, kNumLegs> legs;

  const limb_database_detail::LegData& Leg(rbcp::Leg leg) const { return legs[static_cast<std::size_t>(Index(leg))]; }
};

}  // namespace rbcp
