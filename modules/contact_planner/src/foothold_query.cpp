#include "foothold_query.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "path_track.h"
#include "rbcp/limb_database/limb_database.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp::contact_planner_detail {

std::vector<Candidate> RankedCandidates(const PlannerContext& ctx, Leg leg, const Eigen::Isometry3d& base_W,
                                        const Eigen::Vector3d& target_W, double target_yaw, double near_half) {
  const FootholdConfig& fc = ctx.config.foothold;
  // The workspace box (base frame, around the reference foot) seen from above: the rectangle in
  // the base's heading frame that holds its eight corners, widened by the query distance.
  const FootWorkspace& ws = ctx.config.workspace;
  const Eigen::Vector3d ref = ctx.robot.ReferenceFootPosition(leg);
  const double side = LeftSign(leg);
  const Eigen::Matrix3d& R = base_W.linear();
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  const Eigen::Vector2d axis_x(std::cos(yaw), std::sin(yaw));
  const Eigen::Vector2d axis_y(-axis_x.y(), axis_x.x());
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const double dx : {-ws.max_backward_m, ws.max_forward_m}) {
    for (const double dy : {-side * ws.max_inward_m, side * ws.max_outward_m}) {
      for (const double dz : {-ws.max_down_m, ws.max_up_m}) {
        const Eigen::Vector2d c = (base_W * (ref + Eigen::Vector3d(dx, dy, dz))).head<2>();
        const Eigen::Vector2d local(axis_x.dot(c), axis_y.dot(c));
        lo = lo.cwiseMin(local);
        hi = hi.cwiseMax(local);
      }
    }
  }
  lo.array() -= fc.query_distance_m;
  hi.array() += fc.query_distance_m;
  const Eigen::Vector2d mid = 0.5 * (lo + hi);
  const Eigen::Vector2d half_extent = 0.5 * (hi - lo);
  const Eigen::Vector2d centre = mid.x() * axis_x + mid.y() * axis_y;
  // World-axis bounds of the rectangle, to skip surfaces far from it.
  const Eigen::Vector2d reach(half_extent.x() * std::abs(axis_x.x()) + half_extent.y() * std::abs(axis_y.x()),
                              half_extent.x() * std::abs(axis_x.y()) + half_extent.y() * std::abs(axis_y.y()));
  // Each candidate is scored as the database hands it over, and only the best of each foothold
  // cell is kept (of the many samples near a surface, most project into a cell already seen).
  const Eigen::Matrix3d R_tW = Yaw(target_yaw).transpose();
  std::vector<Candidate> unique;
  int raw = 0;
  const auto better = [](const Candidate& a, const Candidate& b) {
    if (a.score != b.score) return a.score > b.score;
    if (a.surface != b.surface) return a.surface < b.surface;
    return a.sample < b.sample;
  };
  // The best candidate of each foothold cell (FootholdCell) of the surface being queried: a dense
  // grid over the clipped polygon's bounds (its projected footholds lie in the polygon), a map
  // for any that rounding puts outside. A slot holds an index into `unique` + 1, 0 for none.
  const double cell = fc.dedup_cell_m;
  std::vector<std::size_t> grid;
  Eigen::Matrix<long long, 2, 1> grid_lo, grid_size;
  std::unordered_map<long long, std::size_t> outside;
  const auto take = [&](const FootholdCandidate& c) {
    ++raw;
    Candidate k;
    k.surface = c.surface;
    k.sample = c.sample;
    // The clipped polygon lies inside the surface, so its closest point is a valid foothold.
    k.foothold = c.closest_W;
    const Eigen::Vector3d d = R_tW * (k.foothold - target_W);
    k.score = fc.static_weight * c.static_score -
              (fc.weight_x * d.x() * d.x() + fc.weight_y * d.y() * d.y() + fc.weight_z * d.z() * d.z());
    const Eigen::Matrix<long long, 2, 1> i = FootholdCellXy(k.foothold, cell) - grid_lo;
    const bool in_grid = (i.array() >= 0).all() && (i.array() < grid_size.array()).all();
    std::size_t& slot = in_grid ? grid[static_cast<std::size_t>(i.x() * grid_size.y() + i.y())]
                                : outside[FootholdCell(k, cell)];
    if (slot == 0) {
      unique.push_back(k);
      slot = unique.size();
    } else if (better(k, unique[slot - 1])) {
      unique[slot - 1] = k;
    }
  };
  for (std::size_t s = 0; s < ctx.surfaces.size(); ++s) {
    // Many surfaces (thousands of overlapping ones) make this query long: it ends with the budget.
    if (ctx.budget.Exhausted()) break;
    const ConvexPolygon3d& surface = ctx.surfaces[s];
    if ((surface.MinXy().array() > (centre + reach).array()).any() ||
        (surface.MaxXy().array() < (centre - reach).array()).any()) {
      continue;
    }
    std::vector<Eigen::Vector3d> clipped = surface.ClipToRectangle(centre, axis_x, half_extent.x(), half_extent.y());
    if (clipped.size() < 3) continue;
    if (near_half > 0.0) {
      clipped = ConvexPolygon3d(clipped, surface.Normal()).ClipToSquare(target_W.head<2>(), near_half);
      if (clipped.size() < 3) continue;
    }
    Eigen::Vector3d lo_xy = clipped.front(), hi_xy = lo_xy;
    for (const Eigen::Vector3d& v : clipped) {
      lo_xy = lo_xy.cwiseMin(v);
      hi_xy = hi_xy.cwiseMax(v);
    }
    grid_lo = FootholdCellXy(lo_xy, cell);
    grid_size = FootholdCellXy(hi_xy, cell) - grid_lo + Eigen::Matrix<long long, 2, 1>::Ones();
    grid.assign(static_cast<std::size_t>(grid_size.prod()), 0);
    ctx.db.VisitCandidates(leg, base_W, clipped, surface.Normal(), fc.query_distance_m, static_cast<int>(s), take);
  }
  ctx.stats.candidates += raw;
  std::sort(unique.begin(), unique.end(), better);
  return unique;
}

Eigen::Matrix<long long, 2, 1> FootholdCellXy(const Eigen::Vector3d& foothold, double cell) {
  return {static_cast<long long>(std::floor(foothold.x() / cell)), static_cast<long long>(std::floor(foothold.y() / cell))};
}

long long FootholdCell(const Candidate& c, double cell) {
  const Eigen::Matrix<long long, 2, 1> i = FootholdCellXy(c.foothold, cell);
  return ((i.x() & 0xFFFFFF) << 36) ^ ((i.y() & 0xFFFFFF) << 12) ^ static_cast<long long>(c.surface);
}

bool FarEnoughFromFeet(const PlannerContext& ctx, const std::array<FootContact, kNumLegs>& feet,
                       const std::array<bool, kNumLegs>& among, const Eigen::Vector3d& p) {
  for (std::size_t i = 0; i < feet.size(); ++i) {
    if (among[i] && (feet[i].position - p).head<2>().norm() < ctx.config.foothold.min_foot_separation_m) return false;
  }
  return true;
}

bool FarEnoughFromFeet(const PlannerContext& ctx, const std::array<FootContact, kNumLegs>& feet, int skip,
                       const Eigen::Vector3d& p) {
  std::array<bool, kNumLegs> among;
  among.fill(true);
  if (skip >= 0) among[static_cast<std::size_t>(skip)] = false;
  return FarEnoughFromFeet(ctx, feet, among, p);
}

}  // namespace rbcp::contact_planner_detail
