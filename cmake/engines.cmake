# The reference engines and the distance oracle, all double precision, all from Debian.
# Why each is found this way, and the traps the obvious ways fall into:
# docs/build.md#how-cmake-finds-the-engines.

find_package(PkgConfig REQUIRED)
# Bullet: Debian ships a double-precision build; its CMake config is broken (relative include
# paths), so use pkg-config. bullet-float64 carries -DBT_USE_DOUBLE_PRECISION.
pkg_check_modules(BULLET REQUIRED IMPORTED_TARGET bullet-float64)
# ODE: double precision (dDOUBLE); no CMake config is shipped.
pkg_check_modules(ODE REQUIRED IMPORTED_TARGET ode)
# FCL: use the CMake target `fcl`; pkg-config's flags would downgrade -std to c++11.
find_package(fcl 0.7 REQUIRED)
# MuJoCo 2.2.2: Debian's mujocoConfig.cmake needs OpenGL and qhull headers, so build the
# imported target by hand (the runtime needs neither).
if(NOT TARGET mujoco::mujoco)
  find_path(MUJOCO_INCLUDE_DIR mujoco/mujoco.h REQUIRED)
  find_library(MUJOCO_LIBRARY NAMES mujoco REQUIRED)
  add_library(mujoco::mujoco SHARED IMPORTED)
  set_target_properties(mujoco::mujoco PROPERTIES
    IMPORTED_LOCATION "${MUJOCO_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${MUJOCO_INCLUDE_DIR}")
endif()
