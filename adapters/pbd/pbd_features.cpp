// How the PBD library maps every scene feature (adapters/features.h): it implements the seed's
// scene format, so nearly every feature is its own; the exceptions are declared here, once.
#include "adapters/pbd/pbd_engine.h"

namespace pbdval {

FeatureTable pbdFeatures() {
  const Support N = Support::Native, U = Support::Unsupported;
  return {{
      {"shape", N, "analytic SDFs; type 5 a cubic grid SDF of the mesh (cached)"},
      {"joint", N, "the seed's joint constraints (docs/methods.md)"},
      {"body", N, "the scene's values"},
      {"contact", N, "the seed's contacts, Scene::pairMaterial per pair (docs/contacts.md)"},
      {"particle", N, "the scene's particle velocities"},
      {"cloth", N, "the seed's constraints for the method"},
      {"cloth.method.other", U,
       "not implemented; 1 (distance, PBD), 2 (FEM triangles, PBD), 3 (strain-based triangles, "
       "PBD) and 4 (distance, XPBD) are, 0 leaves free particles"},
      {"cloth.bending.other", U,
       "not implemented; 1 (dihedral), 2 (isometric, PBD) and 3 (isometric, XPBD) are, 0 bends "
       "freely"},
      {"solid", N, "the seed's constraints for the method"},
      {"solid.method.other", U,
       "not implemented; 1 (distance and volume, PBD), 2 (FEM, PBD), 3 (FEM, XPBD), 4 "
       "(strain-based, PBD), 5 (shape matching, PBD) and 6 (distance and volume, XPBD) are, 0 "
       "leaves free particles"},
      {"solid.femPoissonOutOfRange", U, "the seed's FEM solve returns false for such a ν"},
      {"rod", N, "Cosserat rods (constraints/cosserat_rod.h)"},
      {"fluid", N, "position-based fluids"},
  }};
}

}  // namespace pbdval
