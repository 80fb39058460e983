#include "validation/measure/deformation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "pbd/constraints/cosserat_rod.h"
#include "pbd/constraints/dihedral_bending.h"
#include "pbd/constraints/fem_tet.h"
#include "pbd/constraints/fem_triangle.h"
#include "pbd/constraints/isometric_bending.h"
#include "pbd/constraints/particle_distance.h"
#include "pbd/constraints/shape_matching.h"
#include "pbd/constraints/strain_tet.h"
#include "pbd/constraints/strain_triangle.h"
#include "pbd/constraints/tet_volume.h"
#include "pbd/model/mesh.h"

namespace pbdval {

double signedTetVolume(const Vector3& x0, const Vector3& x1, const Vector3& x2, const Vector3& x3) {
  return (x1 - x0).dot((x2 - x0).cross(x3 - x0)) / 6;
}

namespace {

const Vector3& positionOf(const State& state, int particle) {
  return state.particles[std::size_t(particle)].position;
}

}  // namespace

ElasticEnergy::ElasticEnergy(const pbd::Scene& scene) {
  // The constraints the Scene's methods define (the same builders the PBD library uses: they
  // are the scene's definition of the models); their values are evaluated here.
  for (const pbd::ParticleDistanceConstraint& c : pbd::deformableDistanceConstraints(scene)) {
    if (c.xpbd)
      springs_.push_back({c.particle1, c.particle2, double(c.restLength), double(c.stiffness)});
    else
      hasPbdConstraints_ = true;
  }
  for (const pbd::TetVolumeConstraint& c : pbd::solidVolumeConstraints(scene)) {
    if (c.xpbd)
      volumes_.push_back({c.particles, double(c.restVolume), double(c.stiffness)});
    else
      hasPbdConstraints_ = true;
  }
  for (const pbd::IsometricBendingConstraint& c : pbd::clothBendingConstraints(scene)) {
    if (c.xpbd)
      bending_.push_back(
          {c.particles,
           {double(c.weights[0]), double(c.weights[1]), double(c.weights[2]), double(c.weights[3])},
           double(c.scale),
           double(c.stiffness)});
    else
      hasPbdConstraints_ = true;
  }
  for (const pbd::FemTetConstraint& c : pbd::solidFemConstraints(scene)) {
    if (!c.xpbd) {
      hasPbdConstraints_ = true;
      continue;
    }
    // Lamé parameters from E and ν (computed here, not taken from the library).
    const double e = double(c.youngsModulus), nu = double(c.poissonRatio);
    femTets_.push_back({c.particles, c.inverseRestMatrix, double(c.restVolume), e / (2 * (1 + nu)),
                        e * nu / ((1 + nu) * (1 - 2 * nu))});
  }
  const auto need = [this](int particle) {
    particlesNeeded_ = std::max(particlesNeeded_, std::size_t(particle) + 1);
  };
  for (const Spring& s : springs_) {
    need(s.a);
    need(s.b);
  }
  for (const Volume& v : volumes_)
    for (int p : v.particles)
      need(p);
  for (const Bending& b : bending_)
    for (int p : b.particles)
      need(p);
  for (const FemTet& t : femTets_)
    for (int p : t.particles)
      need(p);
  // PBD-only families (a fraction per iteration, or the FEM energy with no stiffness factor):
  // no energy of their own.
  if (!pbd::clothDihedralConstraints(scene).empty() ||
      !pbd::femTriangleConstraints(scene).empty() ||
      !pbd::strainTriangleConstraints(scene).empty() || !pbd::strainTetConstraints(scene).empty() ||
      !pbd::shapeMatchingConstraints(scene).empty())
    hasPbdConstraints_ = true;
  // Cosserat rods: the PBD ones (fractions) define no energy; the XPBD ones' constraints, with
  // their rest lengths, rest Darboux quaternions and moduli, as the scene defines them.
  const pbd::RodConstraints rods = pbd::rodConstraints(scene);
  for (const pbd::RodStretchShearConstraint& c : rods.stretchShear) {
    if (!c.xpbd) continue;
    rodStretchShear_.push_back(
        {c.particles[0], c.particles[1], c.segment, c.restLength, c.stiffness});
    need(c.particles[0]);
    need(c.particles[1]);
    segmentsNeeded_ = std::max(segmentsNeeded_, std::size_t(c.segment) + 1);
  }
  for (const pbd::RodBendTwistConstraint& c : rods.bendTwist) {
    if (!c.xpbd) continue;
    rodBendTwist_.push_back(
        {c.segments[0], c.segments[1], c.restDarboux, c.meanLength, c.stiffness});
    segmentsNeeded_ = std::max(segmentsNeeded_, std::size_t(c.segments[1]) + 1);
  }
  for (const pbd::LineModelDesc& model : scene.lineModels)
    if (!model.usesModuli()) hasPbdConstraints_ = true;  // PBD rods: fractions, no energy
}

double rodStretchShearEnergy(const Vector3& p0, const Vector3& p1, const Quaternion& q,
                             Real restLength, const Vector3& stiffness) {
  // The directors d_i are the columns of R(q); C in the director frame is Rᵀ C.
  const pbd::Matrix3 directors = q.normalized().toRotationMatrix();
  const Vector3 value = (p1 - p0) / restLength - directors.col(2);
  const Vector3 local = directors.transpose() * value;
  return 0.5 * double(restLength) * double(stiffness.dot(local.cwiseAbs2()));
}

double rodBendTwistEnergy(const Quaternion& q0, const Quaternion& q1, const Quaternion& restDarboux,
                          Real meanLength, const Vector3& stiffness) {
  const Quaternion darboux = q0.normalized().conjugate() * q1.normalized();
  // q and −q are the same rotation: the rest value's sign closest to the current one.
  const Real plus = (darboux.coeffs() - restDarboux.coeffs()).squaredNorm();
  const Real minus = (darboux.coeffs() + restDarboux.coeffs()).squaredNorm();
  const Vector3 value = plus <= minus ? Vector3(darboux.vec() - restDarboux.vec())
                                      : Vector3(darboux.vec() + restDarboux.vec());
  // ½ Σ C_i² / α_i with α_i = ℓ̄/(4 K_i).
  return 2 / double(meanLength) * double(stiffness.dot(value.cwiseAbs2()));
}

double ElasticEnergy::of(const State& state) const {
  if (state.particles.empty()) return 0;
  if (state.particles.size() < particlesNeeded_)
    throw std::invalid_argument(
        "elastic energy: the state holds " + std::to_string(state.particles.size()) +
        " particles, the scene's constraints need " + std::to_string(particlesNeeded_));
  double energy = 0;
  for (const Spring& s : springs_) {
    const double stretch = (positionOf(state, s.a) - positionOf(state, s.b)).norm() - s.restLength;
    energy += 0.5 * s.stiffness * stretch * stretch;
  }
  for (const Volume& v : volumes_) {
    const auto& p = v.particles;
    const double change = signedTetVolume(positionOf(state, p[0]), positionOf(state, p[1]),
                                          positionOf(state, p[2]), positionOf(state, p[3])) -
                          v.restVolume;
    energy += 0.5 * v.stiffness * change * change;
  }
  for (const Bending& b : bending_) {
    Vector3 h = Vector3::Zero();
    for (std::size_t i = 0; i < 4; ++i)
      h += b.weights[i] * positionOf(state, b.particles[i]);
    const double c = 0.5 * b.scale * h.squaredNorm();
    energy += 0.5 * b.stiffness * c * c;
  }
  for (const FemTet& t : femTets_) {
    // F as the library defines it (its edges and rest matrix: fem_tet.h).
    std::array<Vector3, 4> x;
    for (std::size_t i = 0; i < 4; ++i)
      x[i] = positionOf(state, t.particles[i]);
    const pbd::Matrix3 f = pbd::femDeformationGradient(x, t.inverseRestMatrix);
    const pbd::Matrix3 strain = 0.5 * (f.transpose() * f - pbd::Matrix3::Identity());
    const double trace = strain.trace();
    energy += t.restVolume * (t.mu * strain.squaredNorm() + 0.5 * t.lambda * trace * trace);
  }
  if (state.segments.empty()) return energy;  // no orientations read back: the rods left out
  if (state.segments.size() < segmentsNeeded_)
    throw std::invalid_argument(
        "elastic energy: the state holds " + std::to_string(state.segments.size()) +
        " rod segments, the scene's rods need " + std::to_string(segmentsNeeded_));
  for (const RodStretchShear& c : rodStretchShear_)
    energy += rodStretchShearEnergy(positionOf(state, c.particle0), positionOf(state, c.particle1),
                                    state.segments[std::size_t(c.segment)].rotation, c.restLength,
                                    c.stiffness);
  for (const RodBendTwist& c : rodBendTwist_)
    energy += rodBendTwistEnergy(state.segments[std::size_t(c.segment0)].rotation,
                                 state.segments[std::size_t(c.segment1)].rotation, c.restDarboux,
                                 c.meanLength, c.stiffness);
  return energy;
}

RestShape::RestShape(const pbd::Scene& scene) {
  const auto isStatic = [&](int particle) {
    return !(scene.particles[std::size_t(particle)].mass > 0);
  };
  const auto rest = [&](int particle) -> Vector3 {
    return scene.particles[std::size_t(particle)].position;
  };
  const auto addEdges = [&](const std::vector<std::array<int, 2>>& edges, int first) {
    for (const auto& e : edges) {
      const int a = first + e[0], b = first + e[1];
      if (isStatic(a) && isStatic(b)) continue;
      const double length = (rest(a) - rest(b)).norm();
      if (length > 0) edges_.push_back({a, b, length});
      particlesNeeded_ = std::max(particlesNeeded_, std::size_t(std::max(a, b)) + 1);
    }
  };
  for (const pbd::TriangleModelDesc& model : scene.triangleModels)
    addEdges(pbd::uniqueEdges(model.mesh.triangles), model.firstParticle);
  for (const pbd::TetModelDesc& model : scene.tetModels) {
    addEdges(pbd::uniqueEdges(model.mesh.tetrahedra), model.firstParticle);
    double total = 0;
    for (const auto& t : model.mesh.tetrahedra) {
      Tet tet;
      for (std::size_t i = 0; i < 4; ++i) {
        tet.particles[i] = model.firstParticle + t[i];
        particlesNeeded_ = std::max(particlesNeeded_, std::size_t(tet.particles[i]) + 1);
      }
      tet.restVolume = signedTetVolume(rest(tet.particles[0]), rest(tet.particles[1]),
                                       rest(tet.particles[2]), rest(tet.particles[3]));
      tet.model = modelRestVolumes_.size();
      total += tet.restVolume;
      if (tet.restVolume != 0) tets_.push_back(tet);
    }
    modelRestVolumes_.push_back(total);
  }
  // Cosserat rods: each segment is an edge (its stretch is the rod's axial strain).
  for (const pbd::LineModelDesc& model : scene.lineModels) {
    std::vector<std::array<int, 2>> segments;
    for (std::size_t k = 0; k < model.segmentCount(); ++k)
      segments.push_back({int(k), int(k) + 1});
    addEdges(segments, model.firstParticle);
  }
}

RestShape::Measures RestShape::measure(const State& state) const {
  if (state.particles.size() < particlesNeeded_)
    throw std::invalid_argument(
        "deformation metrics: the state holds " + std::to_string(state.particles.size()) +
        " particles, the scene's models need " + std::to_string(particlesNeeded_));
  Measures m;
  for (const Edge& e : edges_) {
    const double strain =
        (positionOf(state, e.a) - positionOf(state, e.b)).norm() / e.restLength - 1;
    m.stretchMax = std::max(m.stretchMax, std::abs(strain));
    m.stretchSumOfSquares += strain * strain;
  }
  m.edges = edges_.size();
  std::vector<double> volumes(modelRestVolumes_.size(), 0.0);
  for (const Tet& t : tets_) {
    const auto& p = t.particles;
    const double volume = signedTetVolume(positionOf(state, p[0]), positionOf(state, p[1]),
                                          positionOf(state, p[2]), positionOf(state, p[3]));
    m.tetVolumeErrorMax = std::max(m.tetVolumeErrorMax, std::abs(volume / t.restVolume - 1));
    volumes[t.model] += volume;
  }
  for (std::size_t k = 0; k < volumes.size(); ++k)
    if (modelRestVolumes_[k] != 0)
      m.solidVolumeErrorMax =
          std::max(m.solidVolumeErrorMax, std::abs(volumes[k] / modelRestVolumes_[k] - 1));
  return m;
}

}  // namespace pbdval
