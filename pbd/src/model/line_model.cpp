// Line models (Cosserat rods): rest frames by parallel transport, the helix generator, and the
// particles a rod adds to the scene.
#include <cmath>
#include <stdexcept>
#include <string>

#include "pbd/math/quaternion.h"
#include "pbd/model/scene.h"

namespace pbd {

Real LineModelDesc::segmentInverseMass(std::size_t segment) const {
  for (int s : staticSegments)
    if (static_cast<std::size_t>(s) == segment) return 0;
  if (!density || !radius) return 1;
  const Real length = (points[segment + 1] - points[segment]).norm();
  const Real r = *radius;
  const Real mass = *density * Real(EIGEN_PI) * r * r * length;
  const Real inertia = Real(0.5) * mass * r * r;
  return Real(1) / (4 * inertia);
}

std::vector<Quaternion> lineModelFrames(const std::vector<Vector3>& points) {
  std::vector<Quaternion> frames;
  if (points.size() < 2) throw std::invalid_argument("a line model needs at least 2 points");
  frames.reserve(points.size() - 1);
  Vector3 previousTangent = Vector3::Zero();
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    const Vector3 edge = points[k + 1] - points[k];
    const Real length = edge.norm();
    if (!(length > 0))
      throw std::invalid_argument("segment " + std::to_string(k) + " (points " + std::to_string(k) +
                                  " and " + std::to_string(k + 1) + ") has zero length");
    const Vector3 tangent = edge / length;
    if (k == 0) {
      // frameFromAxis: columns (d₃, d₃ × helper normalised, d₃ × that); d₁ = column 1,
      // d₂ = d₃ × d₁ = column 2, so (d₁, d₂, d₃) is right-handed.
      const Matrix3 axes = frameFromAxis(tangent);
      Matrix3 director;
      director.col(0) = axes.col(1);
      director.col(1) = axes.col(2);
      director.col(2) = tangent;
      frames.push_back(Quaternion(director).normalized());
    } else {
      if (previousTangent.dot(tangent) < Real(-0.999))
        throw std::invalid_argument("segments " + std::to_string(k - 1) + " and " +
                                    std::to_string(k) +
                                    " point in opposite directions (a reversal: the frame "
                                    "cannot be transported)");
      const Quaternion transport = Quaternion::FromTwoVectors(previousTangent, tangent);
      frames.push_back((transport * frames.back()).normalized());
    }
    previousTangent = tangent;
  }
  return frames;
}

std::vector<Vector3> helixPoints(Real radius, Real pitch, Real turns, int segments,
                                 const Vector3& center) {
  std::vector<Vector3> points;
  points.reserve(static_cast<std::size_t>(segments) + 1);
  for (int i = 0; i <= segments; ++i) {
    const Real phi = Real(2 * EIGEN_PI) * turns * Real(i) / Real(segments);
    points.push_back(center + Vector3(radius * std::cos(phi), -pitch * phi / Real(2 * EIGEN_PI),
                                      radius * std::sin(phi)));
  }
  return points;
}

void appendLineModel(Scene& scene, LineModelDesc model) {
  model.frames = lineModelFrames(model.points);
  model.firstParticle = static_cast<int>(scene.particles.size());
  model.firstSegment = 0;
  for (const LineModelDesc& m : scene.lineModels)
    model.firstSegment += static_cast<int>(m.segmentCount());
  std::vector<Real> masses(model.points.size(), Real(1));
  if (model.density && model.radius) {
    const Real area = Real(EIGEN_PI) * *model.radius * *model.radius;
    masses.assign(model.points.size(), Real(0));
    for (std::size_t k = 0; k + 1 < model.points.size(); ++k) {
      const Real half =
          Real(0.5) * *model.density * area * (model.points[k + 1] - model.points[k]).norm();
      masses[k] += half;
      masses[k + 1] += half;
    }
  }
  for (std::size_t i = 0; i < model.points.size(); ++i) {
    ParticleDesc particle;
    particle.position = model.points[i];
    particle.mass = masses[i];
    scene.particles.push_back(particle);
  }
  for (int index : model.staticParticles)
    scene.particles[static_cast<std::size_t>(model.firstParticle + index)].mass = 0;
  scene.lineModels.push_back(std::move(model));
}

}  // namespace pbd
