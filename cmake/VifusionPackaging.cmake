# Debian packages of the service (issue 23): `cpack -G DEB` in a build directory writes
# vifusion_<version>_<arch>.deb from the install() rules the programs (COMPONENT service) and systemd/ already
# declare. CPack's DEB generator rather than debhelper: the package is then the same CMake tree and install rules
# for amd64 and for the arm64 cross build, with no second description of what goes where; dpkg-shlibdeps still
# computes the library dependencies. systemd/debian holds the maintainer scripts, conffiles, changelog and copyright.
set(debian_dir ${PROJECT_SOURCE_DIR}/systemd/debian)

# The changelog's newest entry must be this version (one version: project(VERSION)); lintian reads it.
file(STRINGS ${debian_dir}/changelog changelog_head LIMIT_COUNT 1)
if(NOT changelog_head MATCHES "^vifusion \\(${PROJECT_VERSION}\\) ")
  message(FATAL_ERROR "systemd/debian/changelog starts with '${changelog_head}', not version ${PROJECT_VERSION} of "
                      "project(VERSION): add an entry for it")
endif()
set(changelog_gz ${CMAKE_CURRENT_BINARY_DIR}/packaging/changelog.gz)
add_custom_command(OUTPUT ${changelog_gz}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/packaging
  COMMAND sh -c "gzip -9n < \"$0\" > \"$1\"" ${debian_dir}/changelog ${changelog_gz}
  DEPENDS ${debian_dir}/changelog VERBATIM)
add_custom_target(vifusion_package_changelog ALL DEPENDS ${changelog_gz})
install(FILES ${changelog_gz} ${debian_dir}/copyright DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/vifusion
        COMPONENT service)

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME vifusion)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "vifusion maintainers <maintainers@users.noreply.h-seed-d043f22d.example>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "dense RGB-D-inertial SLAM service for robots")
set(CPACK_PACKAGE_DESCRIPTION "vifusiond tracks an RGB-D camera with its IMU and maps the scene as surfels on
Vulkan compute, closing loops by deforming the map, and publishes poses,
odometry and the map over Cyclone DDS with ROS 2 types. vifusion-health
watches it and reports to systemd; the vifusion tool runs, evaluates, records
and inspects maps. The services are installed disabled.")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
if(CMAKE_CROSSCOMPILING)
  # CPack names the build machine's architecture (dpkg --print-architecture); a cross build packages the target's.
  set(deb_architecture_aarch64 arm64)
  set(elf_machine_aarch64 AArch64)
  set(VIFUSION_DEB_ARCHITECTURE ${deb_architecture_${CMAKE_SYSTEM_PROCESSOR}})
  set(VIFUSION_ELF_MACHINE ${elf_machine_${CMAKE_SYSTEM_PROCESSOR}})
  if(NOT VIFUSION_DEB_ARCHITECTURE OR NOT CMAKE_SYSROOT)
    message(FATAL_ERROR "the Debian package of a cross build needs a sysroot (-DVIFUSION_ARM64_SYSROOT) and a "
                        "Debian architecture for ${CMAKE_SYSTEM_PROCESSOR}: only aarch64 (arm64) is known")
  endif()
  set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE ${VIFUSION_DEB_ARCHITECTURE})
  # dpkg-shlibdeps finds the target's libraries in the sysroot, whose DEBIAN/ holds their packages' symbols and
  # shlibs files (.ci/arm64-sysroot).
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS
      ${CMAKE_SYSROOT}/usr/lib/${VIFUSION_CROSS_TRIPLE} ${CMAKE_SYSROOT}/lib/${VIFUSION_CROSS_TRIPLE})
endif()
# The maintainer scripts call systemd-sysusers and systemd-tmpfiles; a Vulkan device is needed to run at all,
# and Mesa's (lavapipe on the CPU, or the board's GPU driver) is the one every test here uses.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "systemd")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "mesa-vulkan-drivers")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
    ${debian_dir}/conffiles ${debian_dir}/postinst ${debian_dir}/prerm ${debian_dir}/postrm)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
