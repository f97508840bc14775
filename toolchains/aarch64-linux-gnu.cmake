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

# Two roots to build against. Without VIFUSION_ARM64_SYSROOT: Debian's cross root /usr/aarch64-linux-gnu, which
# holds only the target's libc, libstdc++ and headers (the GPU-free libraries; no separate sysroot). With
# -DVIFUSION_ARM64_SYSROOT=DIR, a sysroot of Debian's arm64 packages made by .ci/arm64-sysroot: the compiler's
# --sysroot and the only place libraries, headers, CMake packages and .pc files are searched (everything builds).
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES VIFUSION_ARM64_SYSROOT)
if(VIFUSION_ARM64_SYSROOT)
  set(VIFUSION_TARGET_ROOT ${VIFUSION_ARM64_SYSROOT})
  set(CMAKE_SYSROOT ${VIFUSION_TARGET_ROOT})
  # pkg-config stays the host's program and reads the sysroot's .pc files, prefixing their paths with it.
  set(ENV{PKG_CONFIG_SYSROOT_DIR} ${VIFUSION_TARGET_ROOT})
  set(ENV{PKG_CONFIG_LIBDIR}
      ${VIFUSION_TARGET_ROOT}/usr/lib/${VIFUSION_CROSS_TRIPLE}/pkgconfig:${VIFUSION_TARGET_ROOT}/usr/share/pkgconfig)
else()
  set(VIFUSION_TARGET_ROOT /usr/${VIFUSION_CROSS_TRIPLE})
  # Header-only and the same bytes on every architecture: take the host's Eigen package explicitly
  # rather than opening the whole host prefix to find_package.
  set(Eigen3_DIR /usr/share/eigen3/cmake CACHE PATH "Eigen3Config.cmake (architecture-independent)")
endif()
set(CMAKE_FIND_ROOT_PATH ${VIFUSION_TARGET_ROOT})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# Target programs (unit tests, gtest_discover_tests' listing step) run under user-mode qemu; -L makes it
# load the arm64 dynamic loader and shared libraries (and files such as the Vulkan ICD list) from the target
# root first. Either qemu-user (qemu-aarch64) or qemu-user-static (qemu-aarch64-static) will do.
find_program(VIFUSION_QEMU_AARCH64 NAMES qemu-aarch64 qemu-aarch64-static)
if(VIFUSION_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${VIFUSION_QEMU_AARCH64} -L ${VIFUSION_TARGET_ROOT})
  if(VIFUSION_ARM64_SYSROOT)
    # The sysroot's lavapipe (mesa-vulkan-drivers:arm64): under qemu the Vulkan loader does not find the ICD list by
    # itself; the path is read through -L, so it is the one the board would have.
    set(CMAKE_CROSSCOMPILING_EMULATOR
        env VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.${CMAKE_SYSTEM_PROCESSOR}.json ${CMAKE_CROSSCOMPILING_EMULATOR})
  endif()
endif()
