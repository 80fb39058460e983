// The step controller: the seed's TimeStepController::step order (research/pbd.md §3.1).
//
// One step of size h with n = subSteps substeps of h_s = h/n:
//   0. motors take their set point for the end of the step (t + h)
//   1. accelerations of dynamic bodies and particles := gravitation (torques are kept)
//   2. n times: predict (semi-implicit Euler for x and q), maxIterations Gauss–Seidel sweeps
//      over the joints (in colouring order), velocity update from the positions
//   3. velocity pass: maxIterationsV sweeps of the joints' velocity solve (velocity motors)
//   4. t ← t + h
// Nothing here allocates.
#pragma once

namespace pbd {

struct World;

void stepWorld(World& world);

}  // namespace pbd
