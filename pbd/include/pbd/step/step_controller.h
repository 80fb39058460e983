// The step controller: the seed's TimeStepController::step order (docs/seed.md#the-step).
//
// One step of size h with n = subSteps substeps of h_s = h/n:
//   0. motors take their set point for the end of the step (t + h)
//   1. accelerations of dynamic bodies and particles := gravitation (torques are kept)
//   2. n times: predict (semi-implicit Euler for x and q), maxIterations Gauss–Seidel sweeps
//      over the joints (in colouring order), velocity update from the positions
//   3. collision detection on the positions after the substeps; every contact is set up from
//      the current velocities (restitution target, friction data)
//   4. velocity pass: maxIterationsV sweeps, each the joints' velocity solve (velocity motors)
//      then every rigid–rigid contact, then every particle–rigid contact
//   5. t ← t + h
// Nothing here allocates.
#pragma once

namespace pbd {

struct World;

void stepWorld(World& world);

}  // namespace pbd
