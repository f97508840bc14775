# Cross build for 64-bit Arm Linux (the robot's SBC) with Debian's cross compiler against a sysroot of Debian 12's
# arm64 packages; tests run under qemu.
#
#   .ci/arm64-sysroot build-aarch64-sysroot
#   cmake -S . -B build-aarch64 -G Ninja -DCMAKE_TOOLCHAIN_FILE=toolchains/aarch64-linux-gnu.cmake \
#         -DVIFUSION_ARM64_SYSROOT=$PWD/build-aarch64-sysroot -DVIFUSION_BUILD_BENCHMARKS=OFF
#
# .ci/cross-aarch64 does all of it (tests and the arm64 package included); toolchains/README.md explains the
# choices. The sysroot is the compiler's --sysroot and the only place libraries, headers, CMake packages and .pc
# files are searched, so nothing of the host's x86-64 directories leaks in. Programs (glslc, idlc, pkg-config,
# python3) stay host tools.

set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

set(VIFUSION_CROSS_TRIPLE aarch64-linux-gnu)
set(CMAKE_C_COMPILER ${VIFUSION_CROSS_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${VIFUSION_CROSS_TRIPLE}-g++)

list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES VIFUSION_ARM64_SYSROOT)
if(NOT VIFUSION_ARM64_SYSROOT OR NOT EXISTS ${VIFUSION_ARM64_SYSROOT}/usr/lib/${VIFUSION_CROSS_TRIPLE})
  message(FATAL_ERROR "the aarch64 cross build needs -DVIFUSION_ARM64_SYSROOT=DIR, a sysroot made by "
                      ".ci/arm64-sysroot DIR (got '${VIFUSION_ARM64_SYSROOT}')")
endif()
set(CMAKE_SYSROOT ${VIFUSION_ARM64_SYSROOT})
# pkg-config stays the host's program and reads the sysroot's .pc files, prefixing their paths with it.
set(ENV{PKG_CONFIG_SYSROOT_DIR} ${CMAKE_SYSROOT})
set(ENV{PKG_CONFIG_LIBDIR}
    ${CMAKE_SYSROOT}/usr/lib/${VIFUSION_CROSS_TRIPLE}/pkgconfig:${CMAKE_SYSROOT}/usr/share/pkgconfig)
set(CMAKE_FIND_ROOT_PATH ${CMAKE_SYSROOT})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# Target programs (unit tests, gtest_discover_tests' listing step) run under user-mode qemu; -L makes it load the
# arm64 dynamic loader and shared libraries (and files such as the Vulkan ICD list) from the sysroot first. Either
# qemu-user (qemu-aarch64) or qemu-user-static (qemu-aarch64-static) will do. The sysroot's lavapipe
# (mesa-vulkan-drivers:arm64) is named explicitly: under qemu the Vulkan loader does not find the ICD list by
# itself; the path is read through -L, so it is the one the board would have.
find_program(VIFUSION_QEMU_AARCH64 NAMES qemu-aarch64 qemu-aarch64-static)
if(VIFUSION_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR env VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.${CMAKE_SYSTEM_PROCESSOR}.json
      ${VIFUSION_QEMU_AARCH64} -L ${CMAKE_SYSROOT})
endif()
