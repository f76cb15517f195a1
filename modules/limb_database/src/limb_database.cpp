// Limb database generation (sampling, self-collision filter, offline score, octree index) and the
// read-only queries.

#include "rbcp/limb_database/limb_database.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <sstream>

#include "leg_self_collision.h"
#include "limb_database_impl.h"
#include "polygon_distance.h"
#include "rbcp/core/error.h"

namespace rbcp {
namespace limb_database_detail {

void CellTree::Insert(const octomap::OcTreeKey& key, std::uint32_t cell) {
  if (root == nullptr) {
    root = new CellNode(kNoCell);
    ++tree_size;
  }
  CellNode* node = root;
  for (int depth = static_cast<int>(tree_depth) - 1; depth >= 0; --depth) {
    const unsigned int child = octomap::computeChildIdx(key, depth);
    if (!nodeChildExists(node, child)) createNodeChild(node, child)->setValue(kNoCell);
    node = getNodeChild(node, child);
  }
  node->setValue(cell);
}

std::uint32_t CellTree::Find(const octomap::OcTreeKey& key) const {
  const CellNode* node = search(key);
  return node ? node->getValue() : kNoCell;
}

void LegData::Index(double resolution) {
  tree = std::make_unique<CellTree>(resolution);
  key_min = octomap::OcTreeKey(0xFFFF, 0xFFFF, 0xFFFF);
  key_max = octomap::OcTreeKey(0, 0, 0);
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const octomap::OcTreeKey key(cells[c].key[0], cells[c].key[1], cells[c].key[2]);
    tree->Insert(key, static_cast<std::uint32_t>(c));
    for (unsigned a = 0; a < 3; ++a) {
      key_min[a] = std::min(key_min[a], key[a]);
      key_max[a] = std::max(key_max[a], key[a]);
    }
  }
  columns_y = cells.empty() ? 0 : static_cast<std::size_t>(key_max[1] - key_min[1]) + 1;
  const std::size_t columns =
      cells.empty() ? 0 : (static_cast<std::size_t>(key_max[0] - key_min[0]) + 1) * columns_y;
  // Counting sort by column; `cells` is sorted by (x, y, z), so each column's cells are contiguous.
  column_begin.assign(columns + 1, 0);
  for (const CellRecord& c : cells) ++column_begin[Column(c.key[0], c.key[1]) + 1];
  for (std::size_t c = 0; c < columns; ++c) column_begin[c + 1] += column_begin[c];
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const std::size_t col = Column(cells[c].key[0], cells[c].key[1]);
    RBCP_CHECK(c >= column_begin[col] && c < column_begin[col + 1], "limb database cells out of key order");
  }
}

namespace {

/// Uniform double in [0, 1) from the top 53 bits (the same on every platform).
double Uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

/// Key of a coordinate [m] at the finest depth, exactly as octomap computes it, without range
/// limits (a double, so coordinates far outside the tree stay ordered).
double KeyCoordinate(double resolution, double x) { return std::floor((1.0 / resolution) * x) + 32768.0; }

LegData BuildLeg(const RobotModel& model, Leg leg, const LimbDatabaseConfig& config) {
  const LegSelfCollision filter(model, leg);
  const Eigen::Vector3d lo = model.LegLowerBounds(leg);
  const Eigen::Vector3d hi = model.LegUpperBounds(leg);
  const Eigen::Vector3d q_ref = LegJoints(model.ReferenceConfiguration(), leg);
  if (!model.WithinJointBounds(leg, q_ref)) {
    throw InputError("limb database: expected the reference configuration of leg " + std::string(LegName(leg)) +
                     " within its planning joint bounds");
  }
  const auto n = static_cast<std::size_t>(config.samples_per_leg);

  // Generation: the reference configuration, then uniform draws that pass the self-collision filter.
  std::seed_seq seed_seq{config.seed, static_cast<unsigned>(Index(leg)), 0x6c696d62u};
  std::mt19937_64 rng(seed_seq);
  std::vector<Eigen::Vector3d> qs;
  qs.reserve(n);
  qs.push_back(q_ref);
  std::int64_t draws = 0;
  const std::int64_t max_draws = 100 * static_cast<std::int64_t>(n) + 10000;
  while (qs.size() < n) {
    if (draws >= max_draws) {
      std::ostringstream os;
      os << "limb database: leg " << LegName(leg) << ": only " << qs.size() - 1 << " of " << draws
         << " configurations drawn within the joint bounds are free of self-collision; expected at least 1%";
      throw InputError(os.str());
    }
    ++draws;
    Eigen::Vector3d q;
    for (int j = 0; j < 3; ++j) q[j] = lo[j] + Uniform01(rng) * (hi[j] - lo[j]);
    if (!filter.InCollision(q)) qs.push_back(q);
  }

  // Offline score, min-max normalised.
  const Eigen::Vector3d w(config.weight_haa, config.weight_hfe, config.weight_kfe);
  std::vector<double> raw(n);
  for (std::size_t i = 0; i < n; ++i) {
    raw[i] = 100.0 - std::sqrt(w.dot((qs[i] - q_ref).cwiseAbs2()));
  }
  const auto [min_it, max_it] = std::minmax_element(raw.begin(), raw.end());
  const double raw_min = *min_it;
  const double raw_range = *max_it - raw_min;

  // Keys, then order by cell and by descending score inside a cell.
  CellTree keyer(config.octree_resolution);
  std::vector<Eigen::Vector3d> feet(n);
  std::vector<octomap::OcTreeKey> keys(n);
  std::vector<double> scores(n);
  for (std::size_t i = 0; i < n; ++i) {
    feet[i] = model.FootPosition(leg, qs[i]);
    RBCP_CHECK(keyer.coordToKeyChecked(feet[i].x(), feet[i].y(), feet[i].z(), keys[i]),
               "foot position outside the octree range");
    scores[i] = raw_range > 0.0 ? (raw[i] - raw_min) / raw_range : 1.0;
  }
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    for (unsigned k = 0; k < 3; ++k) {
      if (keys[a][k] != keys[b][k]) return keys[a][k] < keys[b][k];
    }
    if (scores[a] != scores[b]) return scores[a] > scores[b];
    return a < b;
  });

  LegData data;
  data.draws = draws;
  data.q.resize(3 * n);
  data.foot.resize(3 * n);
  data.score.resize(n);
  for (std::size_t r = 0; r < n; ++r) {
    const std::size_t i = order[r];
    for (int j = 0; j < 3; ++j) {
      data.q[3 * r + static_cast<std::size_t>(j)] = qs[i][j];
      data.foot[3 * r + static_cast<std::size_t>(j)] = feet[i][j];
    }
    data.score[r] = scores[i];
    const octomap::OcTreeKey& key = keys[i];
    if (r == 0 || keys[order[r - 1]] != key) {
      CellRecord cell;
      cell.key = {key[0], key[1], key[2]};
      cell.first_sample = static_cast<std::uint32_t>(r);
      data.cells.push_back(cell);
    }
    ++data.cells.back().num_samples;
  }
  data.Index(config.octree_resolution);
  return data;
}

/// Inclusive key range of the cells that can hold a point of the box [lo, hi] [m], intersected
/// with the leg's occupied keys. False when empty.
bool KeyRange(const LegData& d, double resolution, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
              octomap::OcTreeKey* key_lo, octomap::OcTreeKey* key_hi) {
  for (unsigned a = 0; a < 3; ++a) {
    const double k_lo = std::max(KeyCoordinate(resolution, lo[static_cast<int>(a)]), static_cast<double>(d.key_min[a]));
    const double k_hi = std::min(KeyCoordinate(resolution, hi[static_cast<int>(a)]), static_cast<double>(d.key_max[a]));
    if (!(k_lo <= k_hi)) return false;
    (*key_lo)[a] = static_cast<octomap::key_type>(k_lo);
    (*key_hi)[a] = static_cast<octomap::key_type>(k_hi);
  }
  return true;
}

}  // namespace
}  // namespace limb_database_detail

using limb_database_detail::CellRecord;
using limb_database_detail::LegData;

LimbDatabase::LimbDatabase(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
LimbDatabase::LimbDatabase(LimbDatabase&&) noexcept = default;
LimbDatabase& LimbDatabase::operator=(LimbDatabase&&) noexcept = default;
LimbDatabase::~LimbDatabase() = default;

LimbDatabase LimbDatabase::Build(const RobotModel& model, const LimbDatabaseConfig& config) {
  config.Validate();
  auto impl = std::make_unique<Impl>();
  impl->resolution = config.octree_resolution;
  for (Leg leg : kAllLegs) {
    impl->legs[static_cast<std::size_t>(Index(leg))] = limb_database_detail::BuildLeg(model, leg, config);
  }
  return LimbDatabase(std::move(impl));
}

int LimbDatabase::NumSamples(Leg leg) const { return impl_->Leg(leg).NumSamples(); }

LimbSample LimbDatabase::Sample(Leg leg, int i) const {
  const LegData& d = impl_->Leg(leg);
  if (i < 0 || i >= d.NumSamples()) {
    throw InputError("limb database: expected a sample index in [0, " + std::to_string(d.NumSamples()) + "), got " +
                     std::to_string(i));
  }
  const auto k = static_cast<std::size_t>(i);
  LimbSample s;
  s.q = Eigen::Vector3d(d.q[3 * k], d.q[3 * k + 1], d.q[3 * k + 2]);
  s.foot_B = d.Foot(k);
  s.score = d.score[k];
  return s;
}

std::int64_t LimbDatabase::Draws(Leg leg) const { return impl_->Leg(leg).draws; }

double LimbDatabase::Resolution() const { return impl_->resolution; }

int LimbDatabase::NumCells(Leg leg) const { return static_cast<int>(impl_->Leg(leg).cells.size()); }

LimbCell LimbDatabase::Cell(Leg leg, int i) const {
  const LegData& d = impl_->Leg(leg);
  if (i < 0 || i >= static_cast<int>(d.cells.size())) {
    throw InputError("limb database: expected a cell index in [0, " + std::to_string(d.cells.size()) + "), got " +
                     std::to_string(i));
  }
  const CellRecord& c = d.cells[static_cast<std::size_t>(i)];
  LimbCell cell;
  for (int a = 0; a < 3; ++a) cell.centre_B[a] = d.tree->keyToCoord(c.key[static_cast<std::size_t>(a)]);
  cell.first_sample = static_cast<int>(c.first_sample);
  cell.num_samples = static_cast<int>(c.num_samples);
  return cell;
}

int LimbDatabase::CellIndexAt(Leg leg, const Eigen::Vector3d& p_B) const {
  const LegData& d = impl_->Leg(leg);
  octomap::OcTreeKey key;
  if (!p_B.allFinite() || !d.tree->coordToKeyChecked(p_B.x(), p_B.y(), p_B.z(), key)) return -1;
  const std::uint32_t cell = d.tree->Find(key);
  return cell == limb_database_detail::kNoCell ? -1 : static_cast<int>(cell);
}

std::vector<FootholdCandidate> LimbDatabase::Candidates(Leg leg, const Eigen::Isometry3d& base_pose_W,
                                                        const ConvexSurface& surface, double max_distance) const {
  std::vector<FootholdCandidate> out;
  AppendCandidates(leg, base_pose_W, surface.vertices, surface.normal, max_distance, -1, &out);
  return out;
}

void LimbDatabase::AppendCandidates(Leg leg, const Eigen::Isometry3d& base_pose_W,
                                    const std::vector<Eigen::Vector3d>& vertices_W, const Eigen::Vector3d& normal_W,
                                    double max_distance, int surface_index,
                                    std::vector<FootholdCandidate>* out) const {
  RBCP_CHECK(out != nullptr, "AppendCandidates needs an output vector");
  VisitCandidates(leg, base_pose_W, vertices_W, normal_W, max_distance, surface_index,
                  [out](const FootholdCandidate& c) { out->push_back(c); });
}

void LimbDatabase::VisitCandidates(Leg leg, const Eigen::Isometry3d& base_pose_W,
                                   const std::vector<Eigen::Vector3d>& vertices_W, const Eigen::Vector3d& normal_W,
                                   double max_distance, int surface_index,
                                   const std::function<void(const FootholdCandidate&)>& visit_candidate) const {
  if (!(std::isfinite(max_distance) && max_distance >= 0.0)) {
    std::ostringstream os;
    os << "limb database query: expected a finite non-negative max_distance [m], got " << max_distance;
    throw InputError(os.str());
  }
  if (!base_pose_W.matrix().allFinite()) throw InputError("limb database query: expected a finite base pose");
  const Eigen::Isometry3d T_BW = base_pose_W.inverse();
  std::vector<Eigen::Vector3d> vertices_B;
  vertices_B.reserve(vertices_W.size());
  for (const Eigen::Vector3d& v : vertices_W) vertices_B.push_back(T_BW * v);
  const limb_database_detail::ConvexPolygonDistance polygon(std::move(vertices_B), T_BW.linear() * normal_W);
  if (polygon.Degenerate()) return;  // no area, no foothold

  const LegData& d = impl_->Leg(leg);
  const double res = impl_->resolution;
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(max_distance);
  octomap::OcTreeKey key_lo, key_hi;
  if (!limb_database_detail::KeyRange(d, res, polygon.Min() - margin, polygon.Max() + margin, &key_lo, &key_hi)) {
    return;
  }
  FootholdCandidate cand;
  cand.leg = leg;
  cand.surface = surface_index;
  // A sample within max_distance of the polygon lies within max_distance of its plane.
  const double sign = polygon.Normal().z() < 0.0 ? -1.0 : 1.0;  // n points up
  const Eigen::Vector3d n = sign * polygon.Normal();
  const double plane_offset = -sign * polygon.PlaneHeight(Eigen::Vector3d::Zero());  // n . p on the plane
  auto visit = [&](const CellRecord& cell) {
    for (std::uint32_t k = cell.first_sample; k < cell.first_sample + cell.num_samples; ++k) {
      const Eigen::Vector3d foot_B = d.Foot(k);
      if (std::abs(polygon.PlaneHeight(foot_B)) > max_distance) continue;
      Eigen::Vector3d closest_B;
      const double dist = polygon.Distance(foot_B, &closest_B);
      if (dist > max_distance) continue;
      cand.sample = static_cast<int>(k);
      cand.static_score = d.score[k];
      cand.distance = dist;
      cand.foot_W = base_pose_W * foot_B;
      cand.closest_W = base_pose_W * closest_B;
      visit_candidate(cand);
    }
  };
  // Column by column of (x, y) keys, the slab of the plane bounds the z keys: over a column's
  // square, n.p - offset stays within max_distance only for n_z z within
  // offset - n_x x_c - n_y y_c +- (max_distance + (|n_x| + |n_y|) res / 2).
  const bool bounded_z = n.z() > 1e-3;
  const double slack = max_distance + (std::abs(n.x()) + std::abs(n.y())) * 0.5 * res + 1e-9;
  for (unsigned kx = key_lo[0]; kx <= key_hi[0]; ++kx) {
    const double x = d.tree->keyToCoord(static_cast<octomap::key_type>(kx));
    for (unsigned ky = key_lo[1]; ky <= key_hi[1]; ++ky) {
      const std::size_t column = d.Column(kx, ky);
      const auto begin = d.cells.begin() + d.column_begin[column];
      const auto end = d.cells.begin() + d.column_begin[column + 1];
      if (begin == end) continue;
      double kz_lo = key_lo[2], kz_hi = key_hi[2];
      if (bounded_z) {
        const double s = plane_offset - n.x() * x - n.y() * d.tree->keyToCoord(static_cast<octomap::key_type>(ky));
        kz_lo = std::max(kz_lo, limb_database_detail::KeyCoordinate(res, (s - slack) / n.z()));
        kz_hi = std::min(kz_hi, limb_database_detail::KeyCoordinate(res, (s + slack) / n.z()));
        if (kz_lo > kz_hi) continue;
      }
      auto it = std::lower_bound(begin, end, kz_lo, [](const CellRecord& c, double z) { return c.key[2] < z; });
      for (; it != end && it->key[2] <= kz_hi; ++it) visit(*it);
    }
  }
}

std::vector<int> LimbDatabase::SamplesInBox(Leg leg, const Eigen::Vector3d& min_B, const Eigen::Vector3d& max_B) const {
  std::vector<int> out;
  if (!min_B.allFinite() || !max_B.allFinite()) throw InputError("limb database query: expected a finite box");
  const LegData& d = impl_->Leg(leg);
  octomap::OcTreeKey key_lo, key_hi;
  if (!limb_database_detail::KeyRange(d, impl_->resolution, min_B, max_B, &key_lo, &key_hi)) return out;
  auto everywhere = [](const Eigen::Vector3d&, double) { return true; };
  d.tree->VisitLeaves(key_lo, key_hi, everywhere, [&](std::uint32_t c) {
    const CellRecord& cell = d.cells[c];
    for (std::uint32_t k = cell.first_sample; k < cell.first_sample + cell.num_samples; ++k) {
      const Eigen::Vector3d p = d.Foot(k);
      if ((p.array() >= min_B.array()).all() && (p.array() <= max_B.array()).all()) out.push_back(static_cast<int>(k));
    }
  });
  std::sort(out.begin(), out.end());
  return out;
}

std::size_t LimbDatabase::MemoryBytes() const {
  std::size_t bytes = sizeof(Impl);
  for (const LegData& d : impl_->legs) {
    bytes += (d.q.capacity() + d.foot.capacity() + d.score.capacity()) * sizeof(double);
    bytes += d.cells.capacity() * sizeof(CellRecord);
    if (d.tree) bytes += d.tree->memoryUsage();
  }
  return bytes;
}

}  // namespace rbcp
