// Placeholder until the references land.
#include "validation/references/reference.h"

#include <stdexcept>

namespace pbdval {

ReferenceTrajectory buildAnalyticReference(const pbd::Scene& /*scene*/, const ReferenceSpec& spec,
                                           const std::vector<double>& /*times*/,
                                           double /*integrationStep*/) {
  throw std::invalid_argument("analytic reference '" + spec.model + "': not implemented yet");
}

std::vector<std::pair<std::string, std::string>> analyticReferenceModels() { return {}; }

}  // namespace pbdval
