#include "pbd/constraints/cosserat_rod.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "pbd/math/quaternion.h"
#include "pbd/model/scene.h"

namespace pbd {
namespace {

Vector4 coefficientsOf(const Quaternion& q) {
  return q.coeffs();
}

/// q ē₃ (ē₃ = [0, −e₃], the conjugate of the pure quaternion e₃).
Quaternion timesConjugateE3(const Quaternion& q) {
  return q * Quaternion(Real(0), Real(0), Real(0), Real(-1));
}

/// The rest Darboux quaternion with the sign s (±1) that makes |Ω − sΩ₀| smaller.
Quaternion signedRest(const Quaternion& darboux, const Quaternion& restDarboux) {
  const Vector4 minus = darboux.coeffs() - restDarboux.coeffs();
  const Vector4 plus = darboux.coeffs() + restDarboux.coeffs();
  return plus.squaredNorm() < minus.squaredNorm() ? Quaternion(-restDarboux.coeffs()) : restDarboux;
}

/// Applies a stretch–shear multiplier step Δλ (world) to the two particles and the quaternion.
StretchShearCorrection stretchShearStep(Real w0, Real w1, const Quaternion& q, Real wq,
                                        Real restLength, const Vector3& deltaLambdaWorld) {
  StretchShearCorrection c;
  c.position0 = -w0 / restLength * deltaLambdaWorld;  // w₀ ∇_{p₀}Cᵀ Δλ
  c.position1 = w1 / restLength * deltaLambdaWorld;
  c.quaternion = -2 * wq * coefficientsOf(pureQuaternion(deltaLambdaWorld) * timesConjugateE3(q));
  return c;
}

BendTwistCorrection bendTwistStep(const Quaternion& q0, Real wq0, const Quaternion& q1, Real wq1,
                                  const Vector3& deltaLambda) {
  BendTwistCorrection c;
  const Quaternion v = pureQuaternion(deltaLambda);
  c.quaternion0 = -wq0 * coefficientsOf(q1 * v);  // w ∇_{q₀}Cᵀ Δλ = −w q₁ [0, Δλ]
  c.quaternion1 = wq1 * coefficientsOf(q0 * v);
  return c;
}

/// The seed's regularisation of its PBD rod solves (PositionBasedCosseratRods: `eps` = 10⁻⁶ added
/// to the stretch–shear denominator Σ w |∇C|² ℓ and to the bend–twist one w_q₀ + w_q₁). It leaves
/// a stretch–shear residual of 10⁻⁶ ℓ/(w₀ + w₁) of the correction (3·10⁻¹² m on a 0.5 m
/// segment under gravity at h_s = 1 ms), which the recordings of the original show.
constexpr Real kSeedRodRegularisation = Real(1e-6);

/// Σ w |∇C|² per row of the stretch–shear constraint (the same for all three rows).
Real stretchShearWeight(Real w0, Real w1, Real wq, Real restLength) {
  return (w0 + w1) / (restLength * restLength) + 4 * wq;
}

}  // namespace

Vector3 rodTangentDirector(const Quaternion& q) {
  const Real w = q.w(), x = q.x(), y = q.y(), z = q.z();
  return Vector3(2 * (x * z + w * y), 2 * (y * z - w * x), w * w - x * x - y * y + z * z);
}

Vector3 stretchShearValue(const Vector3& p0, const Vector3& p1, const Quaternion& q,
                          Real restLength) {
  return (p1 - p0) / restLength - rodTangentDirector(q);
}

Matrix34 stretchShearQuaternionJacobian(const Quaternion& q) {
  Matrix34 j;
  for (int row = 0; row < 3; ++row)
    j.row(row) =
        -2 * coefficientsOf(pureQuaternion(Vector3::Unit(row)) * timesConjugateE3(q)).transpose();
  return j;
}

Vector3 bendTwistValue(const Quaternion& q0, const Quaternion& q1, const Quaternion& restDarboux) {
  const Quaternion darboux = q0.conjugate() * q1;
  return darboux.vec() - signedRest(darboux, restDarboux).vec();
}

Matrix34 bendTwistJacobianFirst(const Quaternion& q1) {
  Matrix34 j;
  for (int row = 0; row < 3; ++row)
    j.row(row) = -coefficientsOf(q1 * pureQuaternion(Vector3::Unit(row))).transpose();
  return j;
}

Matrix34 bendTwistJacobianSecond(const Quaternion& q0) {
  Matrix34 j;
  for (int row = 0; row < 3; ++row)
    j.row(row) = coefficientsOf(q0 * pureQuaternion(Vector3::Unit(row))).transpose();
  return j;
}

Quaternion restDarbouxQuaternion(const Quaternion& q0, const Quaternion& q1) {
  return withPositiveScalar(q0.conjugate() * q1);
}

StretchShearCorrection stretchShearPbd(const Vector3& p0, Real w0, const Vector3& p1, Real w1,
                                       const Quaternion& q, Real wq, Real restLength,
                                       const Vector3& fractions) {
  const Real weight = stretchShearWeight(w0, w1, wq, restLength);
  if (!(weight > 0)) return {};
  const Matrix3 director = q.normalized().toRotationMatrix();
  const Vector3 local = director.transpose() * stretchShearValue(p0, p1, q, restLength);
  // Δλ = −k C ℓ/(Σ w |∇C|² ℓ + ε): the seed's γ = C/((w₀ + w₁)/ℓ + 4 w_q ℓ + ε), scaled by ℓ.
  const Vector3 deltaLocal =
      -fractions.cwiseProduct(local) * restLength / (weight * restLength + kSeedRodRegularisation);
  return stretchShearStep(w0, w1, q, wq, restLength, director * deltaLocal);
}

StretchShearCorrection stretchShearXpbd(const Vector3& p0, Real w0, const Vector3& p1, Real w1,
                                        const Quaternion& q, Real wq, Real restLength,
                                        const Vector3& stiffness, Real substepSize,
                                        const Vector3& multiplier) {
  const Real weight = stretchShearWeight(w0, w1, wq, restLength);
  if (!(weight > 0)) return {};
  const Matrix3 director = q.normalized().toRotationMatrix();
  const Vector3 local = director.transpose() * stretchShearValue(p0, p1, q, restLength);
  Vector3 deltaLocal;
  for (int i = 0; i < 3; ++i) {
    // α̃ = 1/(ℓ k h²); k = 0 (no stiffness): no row.
    const Real compliance =
        stiffness[i] > 0 ? Real(1) / (restLength * stiffness[i] * substepSize * substepSize) : 0;
    deltaLocal[i] = stiffness[i] > 0
                        ? (-local[i] - compliance * multiplier[i]) / (weight + compliance)
                        : Real(0);
  }
  StretchShearCorrection c = stretchShearStep(w0, w1, q, wq, restLength, director * deltaLocal);
  c.multiplier = deltaLocal;
  return c;
}

BendTwistCorrection bendTwistPbd(const Quaternion& q0, Real wq0, const Quaternion& q1, Real wq1,
                                 const Quaternion& restDarboux, const Vector3& fractions) {
  const Real weight = wq0 + wq1;
  if (!(weight > 0)) return {};
  const Vector3 delta = -fractions.cwiseProduct(bendTwistValue(q0, q1, restDarboux)) /
                        (weight + kSeedRodRegularisation);
  return bendTwistStep(q0, wq0, q1, wq1, delta);
}

BendTwistCorrection bendTwistXpbd(const Quaternion& q0, Real wq0, const Quaternion& q1, Real wq1,
                                  const Quaternion& restDarboux, const Vector3& stiffness,
                                  Real meanLength, Real substepSize, const Vector3& multiplier) {
  const Real weight = wq0 + wq1;
  if (!(weight > 0)) return {};
  const Vector3 value = bendTwistValue(q0, q1, restDarboux);
  Vector3 delta;
  for (int i = 0; i < 3; ++i) {
    // α̃ = ℓ̄/(4 K h²).
    const Real compliance =
        stiffness[i] > 0 ? meanLength / (4 * stiffness[i] * substepSize * substepSize) : Real(0);
    delta[i] = stiffness[i] > 0 ? (-value[i] - compliance * multiplier[i]) / (weight + compliance)
                                : Real(0);
  }
  BendTwistCorrection c = bendTwistStep(q0, wq0, q1, wq1, delta);
  c.multiplier = delta;
  return c;
}

Real stretchShearEnergy(const Vector3& p0, const Vector3& p1, const Quaternion& q, Real restLength,
                        const Vector3& stiffness) {
  const Vector3 local =
      q.normalized().toRotationMatrix().transpose() * stretchShearValue(p0, p1, q, restLength);
  return Real(0.5) * restLength * stiffness.dot(local.cwiseAbs2());
}

Real bendTwistEnergy(const Quaternion& q0, const Quaternion& q1, const Quaternion& restDarboux,
                     const Vector3& stiffness, Real meanLength) {
  const Vector3 value = bendTwistValue(q0, q1, restDarboux);
  return Real(0.5) * (4 / meanLength) * stiffness.dot(value.cwiseAbs2());
}

RodConstraints rodConstraints(const Scene& scene) {
  RodConstraints rods;
  const SimulationSettings& s = scene.simulation;
  const Vector3 stretchFractions(s.rod_shearingStiffnessX, s.rod_shearingStiffnessY,
                                 s.rod_stretchingStiffness);
  const Vector3 bendFractions(s.rod_bendingStiffnessX, s.rod_bendingStiffnessY,
                              s.rod_twistingStiffness);
  for (std::size_t m = 0; m < scene.lineModels.size(); ++m) {
    const LineModelDesc& model = scene.lineModels[m];
    const bool xpbd = model.usesModuli();
    Vector3 stretchStiffness = stretchFractions, bendStiffness = bendFractions;
    if (xpbd) {
      const Real r = model.radius.value_or(0);
      const Real area = Real(EIGEN_PI) * r * r;
      const Real areaMoment = Real(EIGEN_PI) * r * r * r * r / 4;  // I = πr⁴/4
      const Real polarMoment = 2 * areaMoment;                     // J = πr⁴/2
      const Real e = *model.youngsModulus, g = *model.shearModulus;
      stretchStiffness =
          Vector3(model.shearFactor * g * area, model.shearFactor * g * area, e * area);
      bendStiffness = Vector3(e * areaMoment, e * areaMoment, g * polarMoment);
    }
    const std::size_t segments = model.segmentCount();
    for (std::size_t k = 0; k < segments; ++k) {
      RodStretchShearConstraint c;
      c.model = int(m);
      c.particles = {model.firstParticle + int(k), model.firstParticle + int(k) + 1};
      c.segment = model.firstSegment + int(k);
      c.restLength = (model.points[k + 1] - model.points[k]).norm();
      c.xpbd = xpbd;
      c.stiffness = stretchStiffness;
      rods.stretchShear.push_back(c);
    }
    for (std::size_t k = 0; k + 1 < segments; ++k) {
      RodBendTwistConstraint c;
      c.model = int(m);
      c.segments = {model.firstSegment + int(k), model.firstSegment + int(k) + 1};
      c.restDarboux = restDarbouxQuaternion(model.frames[k], model.frames[k + 1]);
      c.meanLength = Real(0.5) * ((model.points[k + 1] - model.points[k]).norm() +
                                  (model.points[k + 2] - model.points[k + 1]).norm());
      c.xpbd = xpbd;
      c.stiffness = bendStiffness;
      rods.bendTwist.push_back(c);
    }
  }
  return rods;
}

namespace {

void solveStretchShear(RodStretchShearConstraint& c, ParticleStates& particles,
                       SegmentStates& segments, Real substepSize, bool firstIteration) {
  const auto i0 = std::size_t(c.particles[0]), i1 = std::size_t(c.particles[1]);
  const auto s = std::size_t(c.segment);
  Quaternion& q = segments.rotation[s];
  const Real w0 = particles.inverseMass[i0], w1 = particles.inverseMass[i1];
  const Real wq = segments.inverseMass[s];
  StretchShearCorrection d;
  if (c.xpbd) {
    if (firstIteration) c.multiplier.setZero();
    d = stretchShearXpbd(particles.position[i0], w0, particles.position[i1], w1, q, wq,
                         c.restLength, c.stiffness, substepSize, c.multiplier);
    c.multiplier += d.multiplier;
  } else {
    d = stretchShearPbd(particles.position[i0], w0, particles.position[i1], w1, q, wq, c.restLength,
                        c.stiffness);
  }
  if (w0 != 0) particles.position[i0] += d.position0;
  if (w1 != 0) particles.position[i1] += d.position1;
  if (wq != 0) {
    q.coeffs() += d.quaternion;
    q.normalize();
  }
}

void solveBendTwist(RodBendTwistConstraint& c, SegmentStates& segments, Real substepSize,
                    bool firstIteration) {
  const auto s0 = std::size_t(c.segments[0]), s1 = std::size_t(c.segments[1]);
  Quaternion& q0 = segments.rotation[s0];
  Quaternion& q1 = segments.rotation[s1];
  const Real wq0 = segments.inverseMass[s0], wq1 = segments.inverseMass[s1];
  BendTwistCorrection d;
  if (c.xpbd) {
    if (firstIteration) c.multiplier.setZero();
    d = bendTwistXpbd(q0, wq0, q1, wq1, c.restDarboux, c.stiffness, c.meanLength, substepSize,
                      c.multiplier);
    c.multiplier += d.multiplier;
  } else {
    d = bendTwistPbd(q0, wq0, q1, wq1, c.restDarboux, c.stiffness);
  }
  if (wq0 != 0) {
    q0.coeffs() += d.quaternion0;
    q0.normalize();
  }
  if (wq1 != 0) {
    q1.coeffs() += d.quaternion1;
    q1.normalize();
  }
}

}  // namespace

void orderRodsAsTheSeed(RodConstraints& rods) {
  // The seed's list: per line model its stretch–shear constraints, then its bend–twist ones
  // (both families are built model by model, in segment order).
  std::vector<int> list;
  std::size_t ss = 0, bt = 0;
  while (ss < rods.stretchShear.size() || bt < rods.bendTwist.size()) {
    const int model =
        ss < rods.stretchShear.size() ? rods.stretchShear[ss].model : rods.bendTwist[bt].model;
    for (; ss < rods.stretchShear.size() && rods.stretchShear[ss].model == model; ++ss)
      list.push_back(int(ss));
    for (; bt < rods.bendTwist.size() && rods.bendTwist[bt].model == model; ++bt)
      list.push_back(-int(bt) - 1);
  }
  // Greedy colouring in list order, over the seed's one index space.
  int largest = 0;
  const auto indices = [&](int k, std::array<int, 3>& out) {
    if (k >= 0) {
      const RodStretchShearConstraint& c = rods.stretchShear[std::size_t(k)];
      out = {c.particles[0], c.particles[1], c.segment};
      return 3;
    }
    const RodBendTwistConstraint& c = rods.bendTwist[std::size_t(-k - 1)];
    out = {c.segments[0], c.segments[1], -1};
    return 2;
  };
  std::array<int, 3> idx{};
  for (int k : list) {
    const int n = indices(k, idx);
    for (int i = 0; i < n; ++i)
      largest = std::max(largest, idx[std::size_t(i)]);
  }
  std::vector<std::vector<char>> used;
  std::vector<std::vector<int>> groups;
  for (int k : list) {
    const int n = indices(k, idx);
    std::size_t g = 0;
    for (; g < used.size(); ++g) {
      bool free = true;
      for (int i = 0; i < n; ++i)
        if (used[g][std::size_t(idx[std::size_t(i)])]) free = false;
      if (free) break;
    }
    if (g == used.size()) {
      used.emplace_back(std::size_t(largest) + 1, char(0));
      groups.emplace_back();
    }
    for (int i = 0; i < n; ++i)
      used[g][std::size_t(idx[std::size_t(i)])] = 1;
    groups[g].push_back(k);
  }
  rods.seedOrder.clear();
  for (const std::vector<int>& group : groups)
    rods.seedOrder.insert(rods.seedOrder.end(), group.begin(), group.end());
}

void solveRods(RodConstraints& rods, ParticleStates& particles, SegmentStates& segments,
               Real substepSize, bool firstIteration) {
  if (!rods.seedOrder.empty()) {
    for (int k : rods.seedOrder) {
      if (k >= 0)
        solveStretchShear(rods.stretchShear[std::size_t(k)], particles, segments, substepSize,
                          firstIteration);
      else
        solveBendTwist(rods.bendTwist[std::size_t(-k - 1)], segments, substepSize, firstIteration);
    }
    return;
  }
  for (RodStretchShearConstraint& c : rods.stretchShear)
    solveStretchShear(c, particles, segments, substepSize, firstIteration);
  for (RodBendTwistConstraint& c : rods.bendTwist)
    solveBendTwist(c, segments, substepSize, firstIteration);
}

Real rodElasticEnergy(const RodConstraints& rods, const ParticleStates& particles,
                      const SegmentStates& segments) {
  Real energy = 0;
  for (const RodStretchShearConstraint& c : rods.stretchShear)
    if (c.xpbd)
      energy +=
          stretchShearEnergy(particles.position[std::size_t(c.particles[0])],
                             particles.position[std::size_t(c.particles[1])],
                             segments.rotation[std::size_t(c.segment)], c.restLength, c.stiffness);
  for (const RodBendTwistConstraint& c : rods.bendTwist)
    if (c.xpbd)
      energy += bendTwistEnergy(segments.rotation[std::size_t(c.segments[0])],
                                segments.rotation[std::size_t(c.segments[1])], c.restDarboux,
                                c.stiffness, c.meanLength);
  return energy;
}

}  // namespace pbd
