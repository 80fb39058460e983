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
//                   + the XPBD Cosserat rods' (pbd/constraints/cosserat_rod.h; LineModels with
//                   youngsModulus and shearModulus), ½ Cᵀ α⁻¹ C of each constraint with its
//                   compliance α, from the particles and the segment orientations q:
//                     stretch–shear, per segment of rest length ℓ: C = (p₁ − p₀)/ℓ − d₃(q),
//                       α_i = 1/(ℓ k_i) along the director d_i of q, k = (κGA, κGA, EA):
//                       E_ss = ½ ℓ Σ_i k_i (d_iᵀ C)²   (stretch ε: ½ EA ℓ ε²; shear γ: ½ κGA ℓ γ²)
//                     bend–twist, per pair of segments of mean rest length ℓ̄: C = Im(q̄₀ q₁ − s Ω₀)
//                       (Ω₀ the rest Darboux quaternion, s = ±1 minimising |q̄₀ q₁ − s Ω₀|),
//                       α_i = ℓ̄/(4 K_i), K = (EI, EI, GJ):  E_bt = (2/ℓ̄) Σ_i K_i C_i²
//                       (a bend or twist by θ from rest: (2K/ℓ̄) sin²(θ/2) → ½ K θ²/ℓ̄).
//                   Measured when the state holds the segments (State::segments; the PBD
//                   library's read does); otherwise left out. PBD rods (fractions) define none.
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
  /// J; 0 when the state holds no particles; the XPBD rods' terms only when it also holds the
  /// segments. Throws std::invalid_argument when it holds fewer particles or segments (but
  /// some) than the constraints need.
  double of(const State& state) const;
  /// Whether any XPBD cloth or solid constraint contributes (rods: hasXpbdRods).
  bool defined() const {
    return !springs_.empty() || !volumes_.empty() || !bending_.empty() || !femTets_.empty();
  }
  /// Whether the scene has PBD particle constraints, which define no energy.
  bool hasPbdConstraints() const { return hasPbdConstraints_; }
  /// Whether the scene has XPBD Cosserat rods, whose elastic energy needs the segment
  /// orientations (measured only for states that hold them).
  bool hasXpbdRods() const { return !rodStretchShear_.empty() || !rodBendTwist_.empty(); }

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
  struct RodStretchShear {
    int particle0, particle1, segment;
    Real restLength;
    Vector3 stiffness;  ///< (κGA, κGA, EA), N
  };
  struct RodBendTwist {
    int segment0, segment1;
    Quaternion restDarboux;
    Real meanLength;
    Vector3 stiffness;  ///< (EI, EI, GJ), N m²
  };
  std::vector<Spring> springs_;
  std::vector<FemTet> femTets_;
  std::vector<Volume> volumes_;
  std::vector<Bending> bending_;
  std::vector<RodStretchShear> rodStretchShear_;
  std::vector<RodBendTwist> rodBendTwist_;
  bool hasPbdConstraints_ = false;
  std::size_t particlesNeeded_ = 0;
  std::size_t segmentsNeeded_ = 0;
};

/// The XPBD stretch–shear energy ½ ℓ Σ_i k_i (d_iᵀ C)² of one segment (deformation.h), q the
/// segment's director frame → world (normalised here), k = (κGA, κGA, EA).
double rodStretchShearEnergy(const Vector3& p0, const Vector3& p1, const Quaternion& q,
                             Real restLength, const Vector3& stiffness);
/// The XPBD bend–twist energy (2/ℓ̄) Σ_i K_i C_i² of two neighbouring segments, K = (EI, EI, GJ).
double rodBendTwistEnergy(const Quaternion& q0, const Quaternion& q1, const Quaternion& restDarboux,
                          Real meanLength, const Vector3& stiffness);

/// The rest geometry of the models' edges and tets, for the deformation measures.
class RestShape {
 public:
  explicit RestShape(const pbd::Scene& scene);
  bool empty() const { return edges_.empty() && tets_.empty(); }
  bool hasTets() const { return !tets_.empty(); }

  struct Measures {
    double stretchMax = 0;           ///< max |ℓ/ℓ₀ − 1|
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
