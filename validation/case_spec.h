// The `Validation` block of a case (docs/validation-block.md): how long to run, how often to
// sample, and (later) the reference and checks.
#pragma once

#include <optional>
#include <string>

#include "pbd/model/scene.h"

namespace pbdval {

struct CaseSpec {
  std::optional<double> duration;        ///< s
  std::optional<double> sampleInterval;  ///< s
  std::string description;
};

/// Parses scene.validationJson; throws std::invalid_argument naming the file and JSON path.
CaseSpec parseCaseSpec(const pbd::Scene& scene);

/// The run length a case asks for: Validation.duration, else the seed's pauseAt when > 0, else
/// 5 s.
double defaultDuration(const pbd::Scene& scene, const CaseSpec& spec);

}  // namespace pbdval
