// The points of a rigid body that are tested against other bodies' signed distance functions
// (the seed's vertex side), in the body's scene frame.
//
// A body with a geometry file uses its mesh vertices, as the seed does. A primitive without a
// geometry file (an extension) uses the vertices of the corresponding model of cases/models
// (scripts/make-models), scaled to its size, so that it collides exactly like the same body
// given with that mesh:
//   box       the 8 corners (cube.obj);
//   sphere    the icosahedron subdivided 3 times, projected onto the sphere: 642 points about
//             0.12 r apart, one at each pole (sphere.obj);
//   cylinder  two rims of 32 points and the two cap centres: 66 points (cylinder.obj).
// Denser samplings were tried and rejected: sample points on a large face (a ground) act as
// bumps for a body sliding over it inside the contact tolerance shell, since each one, near
// the slider's side face, gets that face's horizontal normal.
// Other types without a geometry file have no samples (they act only through their SDF).
#pragma once

#include <vector>

#include "pbd/model/scene.h"

namespace pbd {

std::vector<Vector3> surfaceSamples(const RigidBodyDesc& body);

/// The unit models (cases/models): cube [−½, ½]³, unit icosphere, cylinder of radius 1 and
/// height 1 along y.
std::vector<Vector3> unitCubeVertices();
std::vector<Vector3> unitIcosphereVertices(int subdivisions = 3);
std::vector<Vector3> unitCylinderVertices(int segments = 32);

}  // namespace pbd
