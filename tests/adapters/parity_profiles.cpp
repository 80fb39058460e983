// One profile per engine. Each adapter's author keeps its entry; see parity_profiles.h.
#include "parity_profiles.h"

#include "adapters/engine.h"

namespace pbdval::test {
namespace {

using pbd::JointType;

ParityProfile pbdProfile() {
  ParityProfile p;
  p.engine = "pbd";
  p.method = "pbd";
  p.integrationStepsPerStep = 5;  // the parity scenes use subSteps 5
  p.pendulumJoints = {JointType::Ball, JointType::Hinge, JointType::Universal, JointType::Distance};
  p.contacts = false;                        // enabled once pbd/contacts lands (issue 3)
  p.frictionCone = FrictionCone::Isotropic;  // friction along the sliding direction
  return p;
}

}  // namespace

std::vector<ParityProfile> parityProfiles() {
  std::vector<ParityProfile> all;
  for (const std::string& engine : engineNames()) {
    if (engine == "pbd") all.push_back(pbdProfile());
  }
  return all;
}

}  // namespace pbdval::test
