#pragma once
/// Contacts and their linearised friction cones.

#include <Eigen/Core>

namespace rbcp {

/// A point contact in the world frame.
struct ContactPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< p_W [m]
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();   ///< n_W, pointing out of the surface (normalised on use)
};

/// Unit tangent directions (t1, t2) of a contact with unit normal n, such that (t1, t2, n) is a
/// right-handed frame. t1 points up the slope: the projection of world +z onto the contact plane.
/// On (near-)horizontal surfaces (tilt below 1e-3 rad) t1 is world +x projected onto the plane.
void ContactTangents(const Eigen::Vector3d& n, Eigen::Vector3d* t1, Eigen::Vector3d* t2);

/// The edges of the pyramid inscribed in the friction cone {f : |f_t| <= mu f_n}: column j is
/// normalise(n + mu (cos(theta_j) t1 + sin(theta_j) t2)), theta_j = 2 pi j / count. With count 4
/// these are n + mu t1 (up the slope), n + mu t2, n - mu t1, n - mu t2.
///
/// The inscribed pyramid admits the full mu along its edges and mu cos(pi / count) half-way
/// between them. Putting an edge up the slope makes it exact in the direction in which gravity
/// loads a contact on an inclined surface. (The reference implementation turns the pyramid by
/// pi / count about n and takes t1 = n x y; on a slope rising along x with count 4 it then admits
/// only mu cos 45 deg up the slope and, e.g., rejects a 30 deg slope with mu = 0.7.)
/// Throws InputError if the normal is not finite and non-zero, mu <= 0 or count < 3.
Eigen::Matrix3Xd FrictionConeGenerators(const Eigen::Vector3d& normal, double mu, int count);

/// Converts a common lower bound b0 on the generator weights [N] into the robustness [N] of
/// EquilibriumResult: with every weight >= b0, each contact force is b0 * sum_j G_j (along the
/// normal, of length count * cos(atan mu)) plus a force inside the cone, so it stays inside the
/// Coulomb cone for any force error smaller than |sum_j G_j x G_0| * b0 = count mu / (1 + mu^2) * b0.
/// This is the conversion of the reference (hpp-centroidal-dynamics, "b0 to e_max").
double RobustnessPerGeneratorWeight(double mu, int count);

}  // namespace rbcp
