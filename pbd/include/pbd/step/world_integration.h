// The time-integration passes over a whole world that both step methods share (the seed's step,
// step_controller.h, and XPBD, xpbd_step.h): gravity, the prediction of a substep, and the
// velocity update after it. Per-body formulas: time_integration.h.
#pragma once

#include "pbd/math/types.h"

namespace pbd {

class World;

/// Accelerations of dynamic bodies and particles := gravitation; static ones 0.
void resetAccelerations(World& world);
/// Semi-implicit Euler prediction of every body and particle over `h`, keeping the substep's
/// start (old*) and, when `keepLastState`, the previous substep's start (last*: read only by the
/// second-order velocity update; the XPBD step, first order, skips the copies).
void predictPositions(World& world, Real h, bool keepLastState = true);
/// Velocities from the positions: first order, or the seed's second order (BDF2, linear part
/// only) when `secondOrder`.
void updateVelocities(World& world, Real h, bool secondOrder);

}  // namespace pbd
