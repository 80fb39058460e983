// Mass properties of rigid bodies: polyhedral volume integration for closed triangle meshes
// and closed forms for the primitives (sphere, box, cylinder).
//
// Volume integration: the mesh is split into signed tetrahedra (origin, a, b, c). For one
// tetrahedron with edge matrix A = [a b c], volume V = det(A)/6 and second moment
//   ∫ x xᵀ dV = det(A) · A · C · Aᵀ,  C = (1/120) [[2,1,1],[1,2,1],[1,1,2]]
// (the covariance of the canonical tetrahedron). Summing over all faces gives the moments of
// the enclosed solid (exact for closed, consistently oriented meshes); the inertia about the
// centre of mass c is I = tr(Σ) 𝟙 − Σ with Σ = ρ(∫ x xᵀ dV) − m c cᵀ.
// Reference: Tonon, "Explicit exact formulas for the 3-D tetrahedron inertia tensor", J. Math.
// Stat. 1(1), 2004; Blow & Binstock, "How to find the inertia tensor (or other mass properties)
// of a 3D solid body represented by a triangle mesh", 2004.
#pragma once

#include <vector>

#include "pbd/math/types.h"
#include "pbd/model/mesh.h"

namespace pbd {

/// Mass, centre of mass and full inertia tensor (about the centre of mass) in the frame the
/// geometry is given in.
struct SolidMoments {
  Real volume = 0;
  Real mass = 0;
  Vector3 centerOfMass = Vector3::Zero();
  Matrix3 inertia = Matrix3::Zero();
};

/// Mass properties in principal form: the principal moments and the rotation from the
/// principal frame into the geometry (scene) frame.
struct MassProperties {
  Real mass = 0;
  Vector3 principalInertia = Vector3::Zero();
  Vector3 centerOfMass = Vector3::Zero();                 ///< in the scene frame
  Quaternion principalRotation = Quaternion::Identity();  ///< principal → scene frame
};

/// Moments of the solid enclosed by a closed triangle mesh with uniform density.
/// Returns a negative volume when the mesh is oriented inwards (callers reject it).
SolidMoments integrateSolid(const TriangleMesh& mesh, Real density);

/// Moments of the analytic solids, each centred at the origin of its frame.
SolidMoments sphereMoments(Real radius, Real density);
SolidMoments boxMoments(const Vector3& fullExtents, Real density);
/// Cylinder with its axis along y (the seed's convention): `height` along y.
SolidMoments cylinderMoments(Real radius, Real height, Real density);

/// Diagonalises the inertia tensor. The principal frame is chosen as close to the input frame
/// as possible (columns permuted and signed to match the input axes, right-handed), and is
/// exactly the identity when the tensor is already diagonal to round-off, so that
/// axis-aligned bodies keep their frame.
MassProperties toPrincipal(const SolidMoments& moments);

/// Lumped particle masses of a deformable model: each triangle's mass ρ A (ρ in kg/m²) or each
/// tet's ρ |V| (ρ in kg/m³) split equally among its vertices, so the model's mass is ρ times its
/// area or volume whatever the refinement (the seed gives every vertex mass 1 instead). A vertex
/// in no element gets 0.
std::vector<Real> lumpedMasses(const TriangleMesh& mesh, Real arealDensity);
std::vector<Real> lumpedMasses(const TetMesh& mesh, Real density);

}  // namespace pbd
