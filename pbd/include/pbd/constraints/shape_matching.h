// Shape matching of tets (solidSimulationMethod 5; PBD), Müller, Heidelberger, Teschner, Gross
// 2005, "Meshless deformations based on shape matching": one cluster per tet, i.e. each cluster
// is the tet's four particles, pulled towards the best-fit rigid motion of its rest shape.
//
// Weights m_i = 1/(w_i + 10⁻⁶) (w the inverse mass; the seed's: a static particle weighs 10⁶).
// Rest (once, from the positions at t = 0): c₀ = Σ m_i X_i / Σ m_i, q_i = X_i − c₀.
// Each projection, at the current x:
//   c = Σ m_i x_i / Σ m_i,  p_i = x_i − c,  A = Σ m_i p_i q_iᵀ,
//   R = the rotation of the polar decomposition A = R S (by SVD A = U Σ Vᵀ, R = U Vᵀ, the sign
//       of U's last column, that of the smallest singular value, flipped when det(U Vᵀ) < 0, so
//       R is a proper rotation even for an inverted cluster; R maximises Σ m_i p_i · R q_i over
//       rotations: the Kabsch/Horn fit),
//   g_i = c + R q_i (the goal: the rest shape rigidly moved),
//   Δx_i = k (g_i − x_i) / n_i for dynamic particles (w_i > 0), 0 for static ones,
// k = solid_stiffness (solidStiffnessFor: 1 unless set), n_i the number of clusters (tets) the
// particle belongs to. Σ m_i (g_i − x_i) = 0 (Σ m_i q_i = 0), so with equal n_i and no static
// particle the corrections conserve Σ m_i x_i, the momentum up to the 10⁻⁶ in the weights.
// No stretch is allowed (the seed's allowStretch is false). The clusters are solved
// Gauss–Seidel, each from the positions the previous ones corrected (as the seed).
// Static particles (docs/seed.md#static-particles-in-shape-matching, seed issue #8): they are not
// moved, so a cluster holding one cannot reach its goal, and its heavy weight pins the centre c
// near it; the maintainer warns of artefacts. Kept as the seed does it.
// Pure functions (positions in, corrections out); nothing allocates (a fixed-size 3 × 3 SVD).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "pbd/math/types.h"
#include "pbd/model/body_states.h"

namespace pbd {

struct Scene;

/// The seed's regularisation of the shape-matching weights, m = 1/(w + 10⁻⁶).
inline constexpr Real kShapeMatchingWeightEpsilon = Real(1e-6);

struct ShapeMatchingConstraint {
  std::array<int, 4> particles{-1, -1, -1, -1};
  std::array<Vector3, 4> restOffsets{Vector3::Zero(), Vector3::Zero(), Vector3::Zero(),
                                     Vector3::Zero()};  ///< q_i = X_i − c₀
  std::array<Real, 4> clusterCounts{1, 1, 1, 1};        ///< n_i ≥ 1
  Real stiffness = 1;                                   ///< k
};

/// m_i = 1/(w_i + 10⁻⁶).
Real shapeMatchingWeight(Real inverseMass);

/// q_i = X_i − c₀ of a rest cluster with inverse masses w.
std::array<Vector3, 4> shapeMatchingRestOffsets(const std::array<Vector3, 4>& rest,
                                                const std::array<Real, 4>& inverseMasses);

/// The rotation R of the polar decomposition of A (a proper rotation, det R = +1).
Matrix3 shapeMatchingRotation(const Matrix3& a);

/// The corrections Δx_i of one cluster at x (static particles, w_i = 0, get none).
std::array<Vector3, 4> shapeMatchingPbd(const std::array<Vector3, 4>& x,
                                        const std::array<Real, 4>& inverseMasses,
                                        const ShapeMatchingConstraint& c);

/// One cluster per tet of every tet model when solidSimulationMethod is 5, with
/// k = solidStiffnessFor and n_i counted over the clusters made; in the models' tet order;
/// none for tets of four static particles or degenerate rest tets (as in strain_tet.h).
std::vector<ShapeMatchingConstraint> shapeMatchingConstraints(const Scene& scene);

/// One Gauss–Seidel sweep over `constraints` in order.
void solveShapeMatching(const std::vector<ShapeMatchingConstraint>& constraints,
                        ParticleStates& particles, std::size_t begin = 0,
                        std::size_t end = SIZE_MAX);

}  // namespace pbd
