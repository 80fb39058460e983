// Measurements of particle models (cloth and solids) from the states read back and the Scene:
// the elastic energy the scene's XPBD particle constraints define, and how far the models are
// from their rest shapes. Formulas: docs/metrics.md §Particle models.
//
//   elastic energy  Σ ½ k (ℓ − ℓ₀)² over XPBD distance constraints (clothSimulationMethod 4,
//                   solidSimulationMethod 6), + Σ ½ k (V − V₀)² over XPBD tet volumes (solid 6),
//                   + Σ ½ k C² over XPBD isometric bending (clothBendingMethod 3, C its energy)
//                   + Σ V₀ ψ(F) over XPBD FEM tets (solidSimulationMethod 3: C = √(2U/E) with
//                   compliance 1/E, so ½ E C² = U), ψ the St. Venant–Kirchhoff energy density
//                   μ ε:ε + ½ λ (tr ε)², ε = ½ (FᵀF − 𝟙), F = D_s D_m⁻¹ of the state's tet
//                   (the true F, also for an inverted tet).
//                   PBD constraints (k a fraction per iteration) define no energy.
//                   Cosserat rods: PBD ones define none; the XPBD ones' is not measured (it
//                   needs the segment orientations, which State does not hold).
//   stretch         |ℓ/ℓ₀ − 1| of every edge (rod segments too) of every model (not both ends
//                   static), whatever the method: the same measurement for every engine.
//   tet volume      |V/V₀ − 1| of every tet (signed volumes: an inverted tet counts ≥ 1);
//   solid volume    |ΣV/ΣV₀ − 1| of each tet model.
#pragma once

#include <array>
#include <vector>

#include "adapters/engine.h"
#include "pbd/math/types.h"

namespace pbdval {

/// The elastic energy of a Scene's particle models, its constraints collected once.
class ElasticEnergy {
 public:
  explicit ElasticEnergy(const pbd::Scene& scene);
  /// J; 0 when the state holds no particles. Throws std::invalid_argument when it holds fewer
  /// than the constraints need.
  double of(const State& state) const;
  /// Whether any XPBD particle constraint contributes.
  bool defined() const {
    return !springs_.empty() || !volumes_.empty() || !bending_.empty() || !femTets_.empty();
  }
  /// Whether the scene has PBD particle constraints, which define no energy.
  bool hasPbdConstraints() const { return hasPbdConstraints_; }
  /// Whether the scene has XPBD Cosserat rods, whose elastic energy is not measured (it needs
  /// the segment orientations, which State does not hold).
  bool hasUnmeasuredRods() const { return hasUnmeasuredRods_; }

 private:
  struct Spring {
    int a, b;
    double restLength, stiffness;
  };
  struct Volume {
    std::array<int, 4> particles;
    double restVolume, stiffness;
  };
  struct Bending {
    std::array<int, 4> particles;
    std::array<double, 4> weights;
    double scale, stiffness;
  };
  struct FemTet {
    std::array<int, 4> particles;
    pbd::Matrix3 inverseRestMatrix;
    double restVolume, mu, lambda;
  };
  std::vector<Spring> springs_;
  std::vector<FemTet> femTets_;
  std::vector<Volume> volumes_;
  std::vector<Bending> bending_;
  bool hasPbdConstraints_ = false;
  bool hasUnmeasuredRods_ = false;
  std::size_t particlesNeeded_ = 0;
};

/// The rest geometry of the models' edges and tets, for the deformation measures.
class RestShape {
 public:
  explicit RestShape(const pbd::Scene& scene);
  bool empty() const { return edges_.empty() && tets_.empty(); }
  bool hasTets() const { return !tets_.empty(); }

  struct Measures {
    double stretchMax = 0;          ///< max |ℓ/ℓ₀ − 1|
    double stretchSumOfSquares = 0;  ///< Σ (ℓ/ℓ₀ − 1)² over the edges
    std::size_t edges = 0;
    double tetVolumeErrorMax = 0;    ///< max |V/V₀ − 1|
    double solidVolumeErrorMax = 0;  ///< max over tet models of |ΣV/ΣV₀ − 1|
  };
  /// Throws std::invalid_argument when the state holds fewer particles than the models need.
  Measures measure(const State& state) const;

 private:
  struct Edge {
    int a, b;
    double restLength;
  };
  struct Tet {
    std::array<int, 4> particles;
    double restVolume;
    std::size_t model;
  };
  std::vector<Edge> edges_;
  std::vector<Tet> tets_;
  std::vector<double> modelRestVolumes_;
  std::size_t particlesNeeded_ = 0;
};

/// Signed volume of the tet (x₁ − x₀)·((x₂ − x₀) × (x₃ − x₀)) / 6.
double signedTetVolume(const Vector3& x0, const Vector3& x1, const Vector3& x2, const Vector3& x3);

}  // namespace pbdval
