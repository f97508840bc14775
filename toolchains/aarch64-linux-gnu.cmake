# Cross build for 64-bit Arm Linux (the robot's SBC) with Debian's cross compiler, tests under qemu.
#
#   apt-get install g++-aarch64-linux-gnu qemu-user      # crossbuild-essential-arm64 pulls in the same
#   cmake -S . -B build-aarch64 -G Ninja -DCMAKE_TOOLCHAIN_FILE=toolchains/aarch64-linux-gnu.cmake \
#         -DVIFUSION_WITH_GPU=OFF -DVIFUSION_WITH_DATASETS=OFF -DVIFUSION_WITH_LIVE_DRIVERS=OFF \
#         -DVIFUSION_BUILD_BENCHMARKS=OFF \
#         -DGTest_DIR=<GoogleTest built with this file>/lib/cmake/GTest
#
# .ci/cross-aarch64 does all of it, GoogleTest included; toolchains/README.md explains the choices.
#
# Libraries are searched only under Debian's arm64 cross root /usr/aarch64-linux-gnu, never in the host's
# x86-64 directories; packages built elsewhere for arm64 are named explicitly (GTest_DIR). Programs
# (glslc, idlc, pkg-config) stay host tools. Eigen is header-only and architecture-independent, so the
# host's copy is used as is.

set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

set(VIFUSION_CROSS_TRIPLE aarch64-linux-gnu)
set(CMAKE_C_COMPILER ${VIFUSION_CROSS_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${VIFUSION_CROSS_TRIPLE}-g++)

# Debian's cross toolchain keeps the target's libc, libstdc++ and headers here (no separate sysroot).
set(CMAKE_FIND_ROOT_PATH /usr/${VIFUSION_CROSS_TRIPLE})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# Header-only and the same bytes on every architecture: take the host's Eigen package explicitly
# rather than opening the whole host prefix to find_package.
set(Eigen3_DIR /usr/share/eigen3/cmake CACHE PATH "Eigen3Config.cmake (architecture-independent)")

# Target programs (unit tests, gtest_discover_tests' listing step) run under user-mode qemu; -L makes it
# load the arm64 dynamic loader and shared libraries from Debian's cross libc. Either qemu-user
# (qemu-aarch64) or qemu-user-static (qemu-aarch64-static) will do.
find_program(VIFUSION_QEMU_AARCH64 NAMES qemu-aarch64 qemu-aarch64-static)
if(VIFUSION_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${VIFUSION_QEMU_AARCH64} -L /usr/${VIFUSION_CROSS_TRIPLE})
endif()
