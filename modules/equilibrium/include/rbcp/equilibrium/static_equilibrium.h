#pragma once
/// Static equilibrium of a rigid robot on point contacts with linearised friction cones
/// (Del Prete, Tonneau, Mansard, ICRA 2016), solved as linear programs with CLP.
///
/// Gravity is (0, 0, -kGravity) [m/s^2] in the world frame. Contact forces are the forces the
/// ground exerts on the feet, world frame, [N]. Each force is a non-negative combination of its
/// contact's cone generators (FrictionConeGenerators).

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "rbcp/equilibrium/config.h"
#include "rbcp/equilibrium/friction_cone.h"

namespace rbcp {

inline constexpr double kGravity = 9.81;  ///< [m/s^2]

enum class EquilibriumStatus {
  kBalanced,         ///< gravity is balanced by forces inside the linearised cones (robustness >= 0)
  kOutsideCones,     ///< balancing gravity needs forces outside the cones; robustness < 0 says by how much
  kNoBalance,        ///< no contact forces at all balance gravity (e.g. fewer than 3 non-collinear
                     ///< contacts and the CoM not above them); robustness is -infinity
  kUnboundedMargin,  ///< opposing contacts can squeeze without limit; robustness is +infinity
  kSolverFailure,    ///< CLP stopped without a proof (should not happen; reason says how)
};

const char* ToString(EquilibriumStatus status);

/// Outcome of a robustness query.
struct EquilibriumResult {
  /// True when gravity can be balanced by forces inside the linearised cones (robustness >= 0).
  bool feasible = false;
  /// Robustness [N]: the largest force error that every contact force can absorb, in any
  /// direction, without leaving its Coulomb cone, for the best force distribution. Negative
  /// values measure how far outside the cones the least-bad distribution must reach. On flat
  /// ground it equals sin(atan mu) times the smallest normal force of the most even distribution.
  double robustness_N = 0.0;
  EquilibriumStatus status = EquilibriumStatus::kSolverFailure;
  /// Why the stance is not balanced (empty when status is kBalanced).
  std::string reason;
};

/// A force distribution for a statically balanced stance.
struct ContactForces {
  bool feasible = false;
  EquilibriumStatus status = EquilibriumStatus::kSolverFailure;
  std::string reason;
  /// One force per contact, in the order given [N], world frame, exerted by the ground on the foot.
  std::vector<Eigen::Vector3d> forces_N;
  /// Largest normal force of the distribution [N] (the distribution minimises it first).
  double max_normal_force_N = 0.0;
  /// Robustness [N] of this distribution, as in EquilibriumResult (maximised second).
  double friction_margin_N = 0.0;
};

/// Static-equilibrium queries for one robot: a fixed mass and configuration, a settable contact
/// set and a CoM per query. Holds the LP models between calls; the contacts' geometry is built
/// once in SetContacts and each query only changes the gravity wrench. Not thread-safe: use one
/// instance per thread. Results depend only on the contacts, CoM, mass and configuration, never
/// on earlier queries.
class StaticEquilibrium {
 public:
  /// Throws InputError for a non-positive mass [kg] or an invalid configuration.
  StaticEquilibrium(double mass_kg, const EquilibriumConfig& config);
  ~StaticEquilibrium();
  StaticEquilibrium(StaticEquilibrium&&) noexcept;
  StaticEquilibrium& operator=(StaticEquilibrium&&) noexcept;
  StaticEquilibrium(const StaticEquilibrium&) = delete;
  StaticEquilibrium& operator=(const StaticEquilibrium&) = delete;

  /// Sets the contacts for the following queries. Normals are normalised. Throws InputError for
  /// a non-finite position or a zero or non-finite normal.
  void SetContacts(const std::vector<ContactPoint>& contacts);
  const std::vector<ContactPoint>& Contacts() const;

  /// Robustness of static equilibrium with the CoM at com_W [m] (reference §5.2, LP2 form:
  /// max b0 s.t. G (b + b0 1) = w_gravity, b >= 0, converted to Newtons).
  EquilibriumResult Robustness(const Eigen::Vector3d& com_W);
  /// SetContacts followed by Robustness.
  EquilibriumResult Robustness(const std::vector<ContactPoint>& contacts, const Eigen::Vector3d& com_W);

  /// True when the result is balanced with at least the configured robustness threshold.
  bool MeetsThreshold(const EquilibriumResult& result) const;

  /// Contact forces balancing gravity inside the linearised cones: first the largest normal
  /// force is minimised, then, allowing it to grow by config.normal_force_slack, the friction
  /// margin is maximised. Not feasible when Robustness(com_W) is negative.
  ContactForces DistributeForces(const Eigen::Vector3d& com_W);

  /// Generators of every contact side by side (generators_per_contact columns per contact).
  const Eigen::Matrix3Xd& Generators() const;
  double MassKg() const;
  const EquilibriumConfig& Config() const;

 private:
  struct Workspace;
  std::unique_ptr<Workspace> ws_;
};

}  // namespace rbcp
