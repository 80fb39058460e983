#include "pbd/joints/joint.h"

namespace pbd {
namespace {

template <std::size_t I>
Joint makeAlternative(const BodyStates& bodies, const JointDesc& desc) {
  return Joint(std::in_place_index<I>, bodies, desc);
}

template <std::size_t... I>
Joint makeByIndex(std::size_t index, const BodyStates& bodies, const JointDesc& desc,
                  std::index_sequence<I...>) {
  using Factory = Joint (*)(const BodyStates&, const JointDesc&);
  static constexpr Factory factories[] = {&makeAlternative<I>...};
  return factories[index](bodies, desc);
}

}  // namespace

Joint makeJoint(const BodyStates& bodies, const JointDesc& desc) {
  return makeByIndex(static_cast<std::size_t>(desc.type), bodies, desc,
                     std::make_index_sequence<kJointTypeCount>{});
}

}  // namespace pbd
