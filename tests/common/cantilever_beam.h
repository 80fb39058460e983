// A cantilever beam of tets for the beam tests and the convergence study
// (tests/pbd/test_cantilever_beam.cpp, bench/particle_convergence.cpp): length L = 0.5 m along
// x, square section H = D = 0.1 m, ρ = 1000 kg/m³, E = 10⁷ Pa, ν = 0 (no Poisson coupling: the
// clamped face then imposes nothing beyond beam theory's clamp), every node of the face x = 0
// static, gravity 0.981 m/s² along −y (a small load). Load per length q = ρ g H D = 9.81 N/m,
// I = D H³/12:
//   Euler–Bernoulli tip deflection  δ_EB = q L⁴ / (8 E I)            = 9.197·10⁻⁴ m,
//   Timoshenko's shear term         δ_s  = q L² / (2 κ G A), κ = 5/6, G = E/2 (ν = 0),
//                                   δ_s / δ_EB = 0.8 (H/L)² = 3.2 %.
// The tip deflection δ/L ≈ 2·10⁻³ keeps StVK's geometric nonlinearity negligible.
// Mesh: pbd::tetLattice (each cube split into the six Kuhn tets around its main diagonal,
// conforming, unlike one five-tet pattern repeated), downwards from y = 0.
// The static state of a world is found by mass-proportional damping of the velocities between
// steps (a viscous force −c m v, c = 64/s, of the order of the critical 2ω₁ = 81/s of the first
// bending mode, ω₁ = 1.875² √(EI/(ρA L⁴)) = 41 rad/s), which moves no fixed point of the step
// map. The linear FEM solution of the same mesh is an independent sparse solve (no PBD code).
#pragma once

#include <Eigen/Sparse>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "pbd/model/mass_properties.h"
#include "pbd/model/mesh.h"
#include "pbd/model/world.h"

namespace pbd::test::beam {

constexpr Real kLength = Real(0.5), kHeight = Real(0.1), kDensity = 1000, kYoungs = Real(1e7);
constexpr Real kGravity = Real(0.981);

/// The beam with `cells` cubes across its height (spacing H / cells), Kuhn tets, density
/// masses, the face x = 0 static.
inline Scene beamScene(int cells, int substeps, int iterations, int solidMethod = 3) {
  const int nx = static_cast<int>(std::lround(kLength / kHeight)) * cells + 1;
  const int ny = cells + 1, nz = cells + 1;
  const Real spacing = kHeight / static_cast<Real>(cells);
  TetModelDesc beam;
  beam.mesh = tetLattice(nx, ny, nz, Vector3(spacing, -spacing, spacing));
  Scene scene;
  scene.simulation.timeStepSize = Real(0.005);
  scene.simulation.subSteps = substeps;
  scene.simulation.maxIterations = iterations;
  scene.simulation.solidSimulationMethod = solidMethod;
  scene.simulation.solid_stiffness = kYoungs;
  scene.simulation.solid_poissonRatio = 0;
  scene.simulation.gravitation = Vector3(0, -kGravity, 0);
  // pbdval's FEM without the seed's absolute cut-off (10⁻⁶ on Σ w|∇C|²): the beam's strains
  // (~10⁻⁴) would fall below it and go uncorrected (docs/methods.md, "femCutoff").
  scene.simulation.femCutoff = 0;
  const std::vector<Real> masses = lumpedMasses(beam.mesh, kDensity);
  for (std::size_t p = 0; p < beam.mesh.vertices.size(); ++p) {
    const Vector3& x = beam.mesh.vertices[p];
    scene.particles.push_back({x, Vector3::Zero(), x.x() == 0 ? Real(0) : masses[p]});
  }
  scene.tetModels.push_back(std::move(beam));
  return scene;
}

struct Deflection {
  Real tip = 0;   ///< mean downward displacement of the nodes of the face x = L
  int steps = 0;  ///< steps to converge
  bool converged = false;
};

/// Settles the beam with mass-proportional damping of rate `damping` (1/s; a viscous force −c m v
/// on every particle, which moves no equilibrium), until the tip moves less than `tolerance`
/// (relative) over 0.1 s.
inline Deflection staticTipDeflection(const Scene& scene, Real damping, Real tolerance,
                                      int maxSteps) {
  World world = buildWorld(scene);
  auto& particles = world.bodies.particles;
  std::vector<std::size_t> tip;
  for (std::size_t p = 0; p < particles.size(); ++p)
    if (std::abs(scene.particles[p].position.x() - kLength) < 1e-9) tip.push_back(p);
  const auto tipDeflection = [&] {
    Real sum = 0;
    for (std::size_t p : tip)
      sum += scene.particles[p].position.y() - particles.position[p].y();
    return sum / static_cast<Real>(tip.size());
  };
  const Real decay = std::exp(-damping * scene.simulation.timeStepSize);
  const int window = static_cast<int>(std::lround(Real(0.1) / scene.simulation.timeStepSize));
  Deflection result;
  Real checkpoint = 0;
  for (int step = 1; step <= maxSteps; ++step) {
    world.step();
    for (Vector3& v : particles.velocity)
      v *= decay;
    if (step % window == 0) {
      const Real now = tipDeflection();
      if (std::abs(now - checkpoint) < tolerance * std::abs(now)) return {now, step, true};
      checkpoint = now;
    }
  }
  result.tip = tipDeflection();
  result.steps = maxSteps;
  return result;
}

inline Real eulerBernoulli() {
  const Real q = kDensity * kGravity * kHeight * kHeight;
  const Real inertia = kHeight * kHeight * kHeight * kHeight / 12;
  return q * std::pow(kLength, 4) / (8 * kYoungs * inertia);
}

inline Real timoshenko() {
  const Real q = kDensity * kGravity * kHeight * kHeight;
  const Real shearModulus = kYoungs / 2, kappa = Real(5) / 6;
  return eulerBernoulli() + q * kLength * kLength / (2 * kappa * shearModulus * kHeight * kHeight);
}

/// The same mesh solved as linear elasticity, independently of the PBD library's constraint
/// code: K u = f with the standard linear-tet stiffness
///   K_e[i a][j b] = V (μ (δ_ab ∇N_i·∇N_j + ∂_b N_i ∂_a N_j) + λ_L ∂_a N_i ∂_b N_j),
/// f = the lumped weights, the static nodes' rows removed; a sparse Cholesky solve. Returns the
/// mean downward displacement of the tip face.
inline Real linearFemTipDeflection(const Scene& scene) {
  const TetModelDesc& beam = scene.tetModels.front();
  const std::size_t n = beam.mesh.vertices.size();
  std::vector<int> dof(n, -1);
  int free = 0;
  for (std::size_t p = 0; p < n; ++p)
    if (scene.particles[p].mass > 0) dof[p] = free++;
  const Real mu = kYoungs / 2, lambda = 0;  // ν = 0
  std::vector<Eigen::Triplet<Real>> entries;
  for (const std::array<int, 4>& tet : beam.mesh.tetrahedra) {
    const auto x = [&](int k) { return beam.mesh.vertices[std::size_t(tet[std::size_t(k)])]; };
    Matrix3 edges;
    edges << x(1) - x(0), x(2) - x(0), x(3) - x(0);
    const Real volume = std::abs(edges.determinant()) / 6;
    const Matrix3 inverse = edges.inverse();  // row k − 1: ∇N_k
    std::array<Vector3, 4> grad;
    for (int k = 1; k < 4; ++k)
      grad[std::size_t(k)] = inverse.row(k - 1).transpose();
    grad[0] = -(grad[1] + grad[2] + grad[3]);
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = 0; j < 4; ++j) {
        const int di = dof[std::size_t(tet[i])], dj = dof[std::size_t(tet[j])];
        if (di < 0 || dj < 0) continue;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) {
            const Real k =
                volume * (mu * ((a == b ? grad[i].dot(grad[j]) : 0) + grad[i][b] * grad[j][a]) +
                          lambda * grad[i][a] * grad[j][b]);
            entries.emplace_back(3 * di + a, 3 * dj + b, k);
          }
      }
  }
  Eigen::SparseMatrix<Real> stiffness(3 * free, 3 * free);
  stiffness.setFromTriplets(entries.begin(), entries.end());
  Eigen::Matrix<Real, Eigen::Dynamic, 1> load =
      Eigen::Matrix<Real, Eigen::Dynamic, 1>::Zero(3 * free);
  for (std::size_t p = 0; p < n; ++p)
    if (dof[p] >= 0) load(3 * dof[p] + 1) = -scene.particles[p].mass * kGravity;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<Real>> solver(stiffness);
  if (solver.info() != Eigen::Success) return std::numeric_limits<Real>::quiet_NaN();
  const Eigen::Matrix<Real, Eigen::Dynamic, 1> u = solver.solve(load);
  Real sum = 0;
  int count = 0;
  for (std::size_t p = 0; p < n; ++p)
    if (std::abs(beam.mesh.vertices[p].x() - kLength) < 1e-9) {
      sum -= u(3 * dof[p] + 1);
      ++count;
    }
  return sum / count;
}

}  // namespace pbd::test::beam
