// The ODE methods and their parameters.
//
//   ode.step       dWorldStep: the full constraint system, solved by ODE's direct LCP solver
//                  (Dantzig). Exact up to round-off for the system it builds.
//   ode.quickstep  dWorldQuickStep: projected Gauss–Seidel with successive over-relaxation,
//                  `iterations` sweeps (ODE's default 20), relaxation `sor` (ODE's default 1.3).
//
// Both: semi-implicit Euler, one integration step per scene step. Joint rows correct a fraction
// `erp` of their error per step and are softened by `cfm`; contacts use `contactErp` and
// `contactCfm` (soft_erp, soft_cfm). Every default is ODE's own (dWorldCreate in double
// precision: ERP 0.2, CFM 1e-10), so the methods are ODE as its users get it.
#pragma once

#include <vector>

#include "adapters/engine.h"

namespace pbdval {

struct OdeSettings {
  enum class Solver { Step, QuickStep };
  Solver solver = Solver::QuickStep;
  int iterations = 20;          ///< QuickStep sweeps
  double overRelaxation = 1.3;  ///< QuickStep SOR factor w
  double erp = 0.2;             ///< joints: fraction of the error corrected per step
  double cfm = 1e-10;           ///< joints: constraint force mixing
  double contactErp = 0.2;      ///< contacts: soft_erp
  double contactCfm = 1e-10;    ///< contacts: soft_cfm
  int maxContacts = 8;          ///< contact points per colliding pair (dCollide's limit)
  bool gyroscopic = true;       ///< dBodySetGyroscopicMode (ODE's default: on)
  /// ode.step: ball-on-line joints use an auxiliary carriage body of this mass relative to the
  /// lighter dynamic end (docs/parity-ode.md). QuickStep does not support them.
  double carriageMassRatio = 1e-3;
};

/// The catalogue entries of the ODE engine.
std::vector<MethodInfo> odeMethods();

/// Parses and range-checks a resolved ODE method; throws std::invalid_argument naming the
/// parameter.
OdeSettings odeSettingsFor(const Method& method);

}  // namespace pbdval
