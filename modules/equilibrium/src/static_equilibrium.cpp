#include "rbcp/equilibrium/static_equilibrium.h"

#include <ClpFactorization.hpp>
#include <ClpSimplex.hpp>
#include <CoinFinite.hpp>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <sstream>

#include "rbcp/core/error.h"

namespace rbcp {
namespace {

// Both LPs are written in units of the robot's weight m g: generator weights, forces and b0 are
// divided by it, so the data are O(1) whatever the mass.
constexpr double kWeightTol = 1e-9;  // [m g] a margin this close to zero counts as zero
const double kInf = COIN_DBL_MAX;

std::string Fmt(double v) {
  std::ostringstream os;
  os.precision(4);
  os << v;
  return os.str();
}

std::string FmtVec(const Eigen::Vector3d& v) {
  return "(" + Fmt(v.x()) + ", " + Fmt(v.y()) + ", " + Fmt(v.z()) + ")";
}

void Setup(ClpSimplex* lp) {
  lp->setLogLevel(0);
  lp->messageHandler()->setLogLevel(0);
  // The data are already O(1) (weight units, lever arms about the contacts' centroid). CLP's
  // automatic scaling was seen to stop at points that are optimal only for the scaled problem
  // (secondary status 3), with robustness values off by several Newtons.
  lp->scaling(0);
  // Dense LU for these few-row bases: the default sparse factorization allocates ~160 kB per
  // factorization, which glibc trims and regrows on every solve (3x the solve time).
  lp->factorization()->forceOtherFactorization(1);
}

// True when CLP reports optimal and the solution has no primal or dual infeasibilities left.
bool CleanOptimal(const ClpSimplex& lp) { return lp.status() == 0 && lp.secondaryStatus() == 0; }

// Finishes a solve: an optimum with leftover infeasibilities is cleaned up by primal simplex.
void Polish(ClpSimplex* lp) {
  if (lp->status() == 0 && lp->secondaryStatus() != 0) lp->primal();
}

// Solves from the all-slack basis so the result depends on the data only.
void SolveCold(ClpSimplex* lp) {
  lp->allSlackBasis(true);
  lp->dual();
  if (lp->status() != 0 && lp->status() != 1 && lp->status() != 2) {
    lp->allSlackBasis(true);
    lp->primal();
  }
  Polish(lp);
}

std::string ClpStatusText(const ClpSimplex& lp) {
  return "CLP status " + std::to_string(lp.status()) + ", secondary status " + std::to_string(lp.secondaryStatus());
}

}  // namespace

const char* ToString(EquilibriumStatus status) {
  switch (status) {
    case EquilibriumStatus::kBalanced: return "balanced";
    case EquilibriumStatus::kOutsideCones: return "outside friction cones";
    case EquilibriumStatus::kNoBalance: return "no balance";
    case EquilibriumStatus::kUnboundedMargin: return "unbounded margin";
    case EquilibriumStatus::kSolverFailure: return "solver failure";
  }
  return "unknown";
}

struct StaticEquilibrium::Workspace {
  double mass_kg = 0.0;
  double weight_N = 0.0;
  double e_per_b0 = 0.0;  // RobustnessPerGeneratorWeight
  EquilibriumConfig config;

  std::vector<ContactPoint> contacts;
  Eigen::Matrix3Xd generators;                // 3 x m, unit columns
  Eigen::Matrix<double, 6, Eigen::Dynamic> A;  // 6 x m: force and moment about `origin` per unit weight
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();

  // Robustness: columns b (m) >= 0 and b0 free; rows G (b + b0 1) = w (6 equalities).
  ClpSimplex robust_lp;
  bool robust_ready = false;
  // Force distribution: generator weights b + b0 with columns b (m) >= 0, t >= 0, b0 >= 0;
  // rows G (b + b0 1) = w (6 equalities) and n_i . f_i - t <= 0 (one per contact).
  ClpSimplex force_lp;
  bool force_ready = false;

  int NumGenerators() const { return static_cast<int>(generators.cols()); }

  // Scaled gravito-inertial wrench: [z; (c - origin) x z].
  Eigen::Matrix<double, 6, 1> GravityWrench(const Eigen::Vector3d& com_W) const {
    Eigen::Matrix<double, 6, 1> w;
    w.head<3>() = Eigen::Vector3d::UnitZ();
    w.tail<3>() = (com_W - origin).cross(Eigen::Vector3d::UnitZ());
    return w;
  }

  void BuildRobustLp();
  void BuildForceLp();
};

void StaticEquilibrium::Workspace::BuildRobustLp() {
  const int m = NumGenerators();
  std::vector<CoinBigIndex> start;
  std::vector<int> index;
  std::vector<double> value;
  start.reserve(static_cast<std::size_t>(m) + 2);
  const Eigen::Matrix<double, 6, 1> sum = A.rowwise().sum();
  for (int k = 0; k <= m; ++k) {
    start.push_back(static_cast<CoinBigIndex>(index.size()));
    for (int r = 0; r < 6; ++r) {
      const double v = k < m ? A(r, k) : sum(r);
      if (v != 0.0) {
        index.push_back(r);
        value.push_back(v);
      }
    }
  }
  start.push_back(static_cast<CoinBigIndex>(index.size()));
  std::vector<double> col_lb(static_cast<std::size_t>(m) + 1, 0.0), col_ub(static_cast<std::size_t>(m) + 1, kInf);
  std::vector<double> obj(static_cast<std::size_t>(m) + 1, 0.0);
  col_lb[static_cast<std::size_t>(m)] = -kInf;
  obj[static_cast<std::size_t>(m)] = -1.0;  // maximise b0
  std::vector<double> row_b(6, 0.0);
  robust_lp.loadProblem(m + 1, 6, start.data(), index.data(), value.data(), col_lb.data(), col_ub.data(),
                        obj.data(), row_b.data(), row_b.data());
  Setup(&robust_lp);
  robust_ready = true;
}

void StaticEquilibrium::Workspace::BuildForceLp() {
  const int m = NumGenerators();
  const int nc = static_cast<int>(contacts.size());
  const int cg = config.generators_per_contact;
  const int rows = 6 + nc;  // wrench equalities, then one normal-force row per contact
  std::vector<CoinBigIndex> start;
  std::vector<int> index;
  std::vector<double> value;
  auto add_column = [&](const Eigen::Matrix<double, 6, 1>& wrench, const Eigen::VectorXd& normal_rows) {
    start.push_back(static_cast<CoinBigIndex>(index.size()));
    for (int r = 0; r < 6; ++r) {
      if (wrench(r) != 0.0) {
        index.push_back(r);
        value.push_back(wrench(r));
      }
    }
    for (int i = 0; i < nc; ++i) {
      if (normal_rows(i) != 0.0) {
        index.push_back(6 + i);
        value.push_back(normal_rows(i));
      }
    }
  };
  Eigen::VectorXd normal_rows(nc);
  Eigen::VectorXd b0_normal_rows = Eigen::VectorXd::Zero(nc);
  for (int k = 0; k < m; ++k) {
    const int i = k / cg;
    normal_rows.setZero();
    normal_rows(i) = contacts[static_cast<std::size_t>(i)].normal.dot(generators.col(k));
    b0_normal_rows(i) += normal_rows(i);
    add_column(A.col(k), normal_rows);
  }
  add_column(Eigen::Matrix<double, 6, 1>::Zero(), -Eigen::VectorXd::Ones(nc));  // t
  add_column(A.rowwise().sum(), b0_normal_rows);                               // b0
  start.push_back(static_cast<CoinBigIndex>(index.size()));

  std::vector<double> col_lb(static_cast<std::size_t>(m) + 2, 0.0), col_ub(static_cast<std::size_t>(m) + 2, kInf);
  std::vector<double> obj(static_cast<std::size_t>(m) + 2, 0.0);
  std::vector<double> row_lb(static_cast<std::size_t>(rows), 0.0), row_ub(static_cast<std::size_t>(rows), 0.0);
  for (int i = 0; i < nc; ++i) row_lb[static_cast<std::size_t>(6 + i)] = -kInf;
  force_lp.loadProblem(m + 2, rows, start.data(), index.data(), value.data(), col_lb.data(), col_ub.data(),
                       obj.data(), row_lb.data(), row_ub.data());
  Setup(&force_lp);
  force_ready = true;
}

StaticEquilibrium::StaticEquilibrium(double mass_kg, const EquilibriumConfig& config)
    : ws_(std::make_unique<Workspace>()) {
  if (!(std::isfinite(mass_kg) && mass_kg > 0.0)) {
    throw InputError("static equilibrium: expected a positive mass [kg], got " + Fmt(mass_kg));
  }
  config.Validate();
  ws_->mass_kg = mass_kg;
  ws_->weight_N = mass_kg * kGravity;
  ws_->config = config;
  ws_->e_per_b0 = RobustnessPerGeneratorWeight(config.friction, config.generators_per_contact);
  SetContacts({});
}

StaticEquilibrium::~StaticEquilibrium() = default;
StaticEquilibrium::StaticEquilibrium(StaticEquilibrium&&) noexcept = default;
StaticEquilibrium& StaticEquilibrium::operator=(StaticEquilibrium&&) noexcept = default;

void StaticEquilibrium::SetContacts(const std::vector<ContactPoint>& contacts) {
  Workspace& ws = *ws_;
  const int cg = ws.config.generators_per_contact;
  const int nc = static_cast<int>(contacts.size());
  for (int i = 0; i < nc; ++i) {
    const ContactPoint& c = contacts[static_cast<std::size_t>(i)];
    if (!c.position.allFinite()) {
      throw InputError("contact " + std::to_string(i) + ": expected a finite position, got " + FmtVec(c.position));
    }
    if (!c.normal.allFinite() || !(c.normal.norm() > 1e-9)) {
      throw InputError("contact " + std::to_string(i) + ": expected a finite non-zero normal, got " + FmtVec(c.normal));
    }
  }
  ws.contacts = contacts;
  ws.origin.setZero();
  for (auto& c : ws.contacts) {
    c.normal.normalize();
    ws.origin += c.position / nc;
  }
  ws.generators.resize(3, nc * cg);
  ws.A.resize(6, nc * cg);
  for (int i = 0; i < nc; ++i) {
    const ContactPoint& c = ws.contacts[static_cast<std::size_t>(i)];
    const Eigen::Matrix3Xd g = FrictionConeGenerators(c.normal, ws.config.friction, cg);
    ws.generators.middleCols(i * cg, cg) = g;
    for (int j = 0; j < cg; ++j) {
      ws.A.block<3, 1>(0, i * cg + j) = g.col(j);
      ws.A.block<3, 1>(3, i * cg + j) = (c.position - ws.origin).cross(g.col(j));
    }
  }
  ws.robust_ready = false;
  ws.force_ready = false;
}

const std::vector<ContactPoint>& StaticEquilibrium::Contacts() const { return ws_->contacts; }
const Eigen::Matrix3Xd& StaticEquilibrium::Generators() const { return ws_->generators; }
double StaticEquilibrium::MassKg() const { return ws_->mass_kg; }
const EquilibriumConfig& StaticEquilibrium::Config() const { return ws_->config; }

EquilibriumResult StaticEquilibrium::Robustness(const std::vector<ContactPoint>& contacts,
                                                const Eigen::Vector3d& com_W) {
  SetContacts(contacts);
  return Robustness(com_W);
}

EquilibriumResult StaticEquilibrium::Robustness(const Eigen::Vector3d& com_W) {
  Workspace& ws = *ws_;
  EquilibriumResult out;
  if (!com_W.allFinite()) throw InputError("static equilibrium: expected a finite CoM, got " + FmtVec(com_W));
  if (ws.contacts.empty()) {
    out.status = EquilibriumStatus::kNoBalance;
    out.robustness_N = -std::numeric_limits<double>::infinity();
    out.reason = "no contacts";
    return out;
  }
  if (!ws.robust_ready) ws.BuildRobustLp();
  ClpSimplex& lp = ws.robust_lp;
  const Eigen::Matrix<double, 6, 1> w = ws.GravityWrench(com_W);
  for (int r = 0; r < 6; ++r) {
    lp.setRowLower(r, w(r));
    lp.setRowUpper(r, w(r));
  }
  SolveCold(&lp);
  if (CleanOptimal(lp)) {
    double b0 = lp.getColSolution()[ws.NumGenerators()];
    if (b0 < 0.0 && b0 > -kWeightTol) b0 = 0.0;
    out.robustness_N = b0 * ws.weight_N * ws.e_per_b0;
    out.feasible = b0 >= 0.0;
    if (out.feasible) {
      out.status = EquilibriumStatus::kBalanced;
    } else {
      out.status = EquilibriumStatus::kOutsideCones;
      out.reason = "balancing gravity with the CoM at " + FmtVec(com_W) + " needs forces " +
                   Fmt(-out.robustness_N) + " N outside the friction cones";
    }
  } else if (lp.isProvenPrimalInfeasible()) {
    out.status = EquilibriumStatus::kNoBalance;
    out.robustness_N = -std::numeric_limits<double>::infinity();
    out.reason = "no forces at the " + std::to_string(ws.contacts.size()) +
                 " contacts balance gravity with the CoM at " + FmtVec(com_W);
  } else if (lp.isProvenDualInfeasible()) {
    out.status = EquilibriumStatus::kUnboundedMargin;
    out.feasible = true;
    out.robustness_N = std::numeric_limits<double>::infinity();
  } else {
    out.status = EquilibriumStatus::kSolverFailure;
    out.robustness_N = -std::numeric_limits<double>::infinity();
    out.reason = "robustness LP not solved: " + ClpStatusText(lp);
  }
  return out;
}

bool StaticEquilibrium::MeetsThreshold(const EquilibriumResult& result) const {
  return result.feasible && result.robustness_N >= ws_->config.robustness_threshold_N;
}

ContactForces StaticEquilibrium::DistributeForces(const Eigen::Vector3d& com_W) {
  Workspace& ws = *ws_;
  ContactForces out;
  if (!com_W.allFinite()) throw InputError("static equilibrium: expected a finite CoM, got " + FmtVec(com_W));
  if (ws.contacts.empty()) {
    out.status = EquilibriumStatus::kNoBalance;
    out.reason = "no contacts";
    return out;
  }
  if (!ws.force_ready) ws.BuildForceLp();
  ClpSimplex& lp = ws.force_lp;
  const int m = ws.NumGenerators();
  const int col_t = m, col_b0 = m + 1;
  const Eigen::Matrix<double, 6, 1> w = ws.GravityWrench(com_W);
  for (int r = 0; r < 6; ++r) {
    lp.setRowLower(r, w(r));
    lp.setRowUpper(r, w(r));
  }
  // Phase 1: minimise the largest normal force t, with b0 held at 0.
  lp.setColumnBounds(col_b0, 0.0, 0.0);
  lp.setColumnUpper(col_t, kInf);
  lp.setObjectiveCoefficient(col_t, 1.0);
  lp.setObjectiveCoefficient(col_b0, 0.0);
  SolveCold(&lp);
  if (!CleanOptimal(lp)) {
    if (lp.isProvenPrimalInfeasible()) {
      // Rare: classify (outside the cones, or no balance at all) with the robustness LP.
      const EquilibriumResult r = Robustness(com_W);
      if (r.status == EquilibriumStatus::kOutsideCones || r.status == EquilibriumStatus::kNoBalance) {
        out.status = r.status;
        out.reason = r.reason;
      } else {
        out.status = EquilibriumStatus::kSolverFailure;
        out.reason = "force LP infeasible although the robustness LP reports " + std::string(ToString(r.status));
      }
    } else {
      out.status = EquilibriumStatus::kSolverFailure;
      out.reason = "force LP (normal forces) not solved: " + ClpStatusText(lp);
    }
    return out;
  }
  const double t_min = lp.getColSolution()[col_t];
  // Phase 2: keep the largest normal force within the slack, maximise the common weight b0.
  lp.setColumnUpper(col_t, t_min * (1.0 + ws.config.normal_force_slack) + kWeightTol);
  lp.setColumnBounds(col_b0, 0.0, kInf);
  lp.setObjectiveCoefficient(col_t, 0.0);
  lp.setObjectiveCoefficient(col_b0, -1.0);
  lp.primal();
  Polish(&lp);
  if (!CleanOptimal(lp)) {
    out.status = EquilibriumStatus::kSolverFailure;
    out.reason = "force LP (friction margin) not solved: " + ClpStatusText(lp);
    return out;
  }
  const double* x = lp.getColSolution();
  const double b0 = std::max(x[col_b0], 0.0);
  const int cg = ws.config.generators_per_contact;
  out.forces_N.resize(ws.contacts.size());
  out.max_normal_force_N = 0.0;
  for (std::size_t i = 0; i < ws.contacts.size(); ++i) {
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    for (int j = 0; j < cg; ++j) {
      const int k = static_cast<int>(i) * cg + j;
      f += (std::max(x[k], 0.0) + b0) * ws.generators.col(k);
    }
    out.forces_N[i] = f * ws.weight_N;
    out.max_normal_force_N = std::max(out.max_normal_force_N, ws.contacts[i].normal.dot(out.forces_N[i]));
  }
  out.friction_margin_N = b0 * ws.weight_N * ws.e_per_b0;
  out.feasible = true;
  out.status = EquilibriumStatus::kBalanced;
  return out;
}

}  // namespace rbcp
