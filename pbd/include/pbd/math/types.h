// Scalar and Eigen aliases used everywhere in the library.
//
// `Real` is double unless the library is configured with -DPBD_USE_FLOAT=ON (then float).
// Every file uses these aliases, never `double` or Eigen's `d` types directly, so the
// precision switch is one line.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace pbd {

#ifdef PBD_USE_FLOAT
using Real = float;
#else
using Real = double;
#endif

using Vector2 = Eigen::Matrix<Real, 2, 1>;
using Vector3 = Eigen::Matrix<Real, 3, 1>;
using Vector4 = Eigen::Matrix<Real, 4, 1>;
using Vector3i = Eigen::Vector3i;
using Matrix3 = Eigen::Matrix<Real, 3, 3>;
using Matrix4 = Eigen::Matrix<Real, 4, 4>;
using Quaternion = Eigen::Quaternion<Real>;
using AngleAxis = Eigen::AngleAxis<Real>;

/// Machine epsilon of `Real`; tolerances in tests are written as multiples of it.
inline constexpr Real kEpsilon = Eigen::NumTraits<Real>::epsilon();

}  // namespace pbd
