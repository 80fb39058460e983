#include "pbd/constraints/constraint_families.h"

#include <type_traits>

namespace pbd {

ConstraintFamilies ConstraintFamilies::fromScene(const Scene& scene) {
  ConstraintFamilies families;
  families.forEachFamily([&](auto& array, const auto& build, const auto&) {
    if constexpr (!std::is_same_v<std::decay_t<decltype(build)>, AddedInCpp>) array = build(scene);
  });
  return families;
}

void ConstraintFamilies::solvePositions(BodyStates& bodies, Real substepSize, bool firstIteration) {
  forEachFamily([&](auto& array, const auto&, const auto& sweep) {
    sweep(array, bodies, substepSize, firstIteration);
  });
}

}  // namespace pbd
