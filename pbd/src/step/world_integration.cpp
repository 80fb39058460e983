#include "pbd/step/world_integration.h"

#include "pbd/model/world.h"
#include "pbd/step/time_integration.h"

namespace pbd {

void resetAccelerations(World& world) {
  const Vector3& g = world.settings.gravitation;
  auto& rigid = world.bodies.rigid;
  for (std::size_t i = 0; i < rigid.size(); ++i)
    rigid.acceleration[i] = rigid.isDynamic(i) ? g : Vector3::Zero();
  auto& particles = world.bodies.particles;
  for (std::size_t i = 0; i < particles.size(); ++i)
    particles.acceleration[i] = particles.inverseMass[i] > 0 ? g : Vector3::Zero();
}

void predictPositions(World& world, Real h, bool keepLastState) {
  auto& b = world.bodies.rigid;
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (keepLastState) {
      b.lastPosition[i] = b.oldPosition[i];
      b.lastRotation[i] = b.oldRotation[i];
    }
    b.oldPosition[i] = b.position[i];
    integration::semiImplicitEuler(h, b.inverseMass[i], b.position[i], b.velocity[i],
                                   b.acceleration[i]);
    b.oldRotation[i] = b.rotation[i];
    integration::semiImplicitEulerRotation(h, b.inverseMass[i], b.inertia[i], b.inverseInertia[i],
                                           b.rotation[i], b.angularVelocity[i], b.torque[i]);
  }
  auto& p = world.bodies.particles;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (keepLastState) p.lastPosition[i] = p.oldPosition[i];
    p.oldPosition[i] = p.position[i];
    integration::semiImplicitEuler(h, p.inverseMass[i], p.position[i], p.velocity[i],
                                   p.acceleration[i]);
  }
  // Rod segments: the seed's semiImplicitEulerRotation with the isotropic inertia 1/(4 w_q)
  // (so no gyroscopic term) and the segment's torque (0 unless set in code); no gravity.
  auto& r = world.bodies.segments;
  for (std::size_t i = 0; i < r.size(); ++i) {
    r.oldRotation[i] = r.rotation[i];
    const Real wq = r.inverseMass[i];
    const Vector3 inertia = Vector3::Constant(wq > 0 ? Real(1) / (4 * wq) : Real(0));
    integration::semiImplicitEulerRotation(h, wq, inertia, Vector3::Constant(4 * wq), r.rotation[i],
                                           r.angularVelocity[i], r.torque[i]);
  }
}

void updateVelocities(World& world, Real h, bool secondOrder) {
  const Real inverseStep = Real(1) / h;
  const Real twoOverStep = Real(2) / h;
  auto& b = world.bodies.rigid;
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (secondOrder)
      integration::velocityUpdateSecondOrder(inverseStep, b.inverseMass[i], b.position[i],
                                             b.oldPosition[i], b.lastPosition[i], b.velocity[i]);
    else
      integration::velocityUpdateFirstOrder(inverseStep, b.inverseMass[i], b.position[i],
                                            b.oldPosition[i], b.velocity[i]);
    integration::angularVelocityUpdateFirstOrder(twoOverStep, b.inverseMass[i], b.rotation[i],
                                                 b.oldRotation[i], b.angularVelocity[i]);
  }
  auto& p = world.bodies.particles;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (secondOrder)
      integration::velocityUpdateSecondOrder(inverseStep, p.inverseMass[i], p.position[i],
                                             p.oldPosition[i], p.lastPosition[i], p.velocity[i]);
    else
      integration::velocityUpdateFirstOrder(inverseStep, p.inverseMass[i], p.position[i],
                                            p.oldPosition[i], p.velocity[i]);
  }
  auto& r = world.bodies.segments;  // first order in both modes, as the seed's angular update
  for (std::size_t i = 0; i < r.size(); ++i)
    integration::angularVelocityUpdateFirstOrder(twoOverStep, r.inverseMass[i], r.rotation[i],
                                                 r.oldRotation[i], r.angularVelocity[i]);
}

}  // namespace pbd
