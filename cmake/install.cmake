# Installation and packaging of the ellipsekit library.
#
# Included from the top-level CMakeLists.txt after the `ellipsekit` target is defined.
# `cmake --install <build> [--prefix P]` then provides
#   P/include/ellipsekit/*.h                                public headers
#   P/<libdir>/libellipsekit.a (or .so)                      the library (static by default)
#   P/<libdir>/cmake/ellipsekit/ellipsekitConfig.cmake       find_package(ellipsekit) -> ellipsekit::ellipsekit
#   P/<libdir>/cmake/ellipsekit/ellipsekitConfigVersion.cmake
#   P/<libdir>/cmake/ellipsekit/ellipsekitTargets*.cmake
#   P/<libdir>/pkgconfig/ellipsekit.pc                       pkg-config --cflags --libs ellipsekit
# Both the CMake package and the .pc file are relocatable: they locate the prefix from their own path,
# so --prefix chosen at install time works.
#
# Dependencies. A static library carries its PRIVATE link libraries into its consumers' link lines
# (CMake exports them as $<LINK_ONLY:...>), so the installed package must find them too. The set is
# read from the target at the end of configuration (a deferred call), so links added later by other
# CMakeLists.txt files are seen. Known imported targets are mapped in _ellipsekit_map_dependency()
# below: add a new dependency there (a find_dependency() line and its pkg-config module).
# A dependency linked as $<BUILD_INTERFACE:...> is build-only and is not exported.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(ELLIPSEKIT_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/ellipsekit"
    CACHE STRING "Where the ellipsekit CMake package files go, relative to the install prefix")
mark_as_advanced(ELLIPSEKIT_INSTALL_CMAKEDIR)

install(TARGETS ellipsekit
  EXPORT ellipsekitTargets
  ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
  LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}"
  RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}"
  INCLUDES DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")

# The robot adapter (include/ellipsekit/robot/, library ellipsekit_robot, target ellipsekit::robot) is
# defined after this file is included (robot/CMakeLists.txt); it is installed by the deferred
# _ellipsekit_write_package_files() below, with its headers, into the same export set, and gets its
# own pkg-config file ellipsekit-robot.pc (Requires: ellipsekit eigen3).
install(DIRECTORY "${PROJECT_SOURCE_DIR}/include/ellipsekit"
  DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}"
  FILES_MATCHING PATTERN "*.h"
  PATTERN "robot" EXCLUDE)

install(EXPORT ellipsekitTargets
  NAMESPACE ellipsekit::
  FILE ellipsekitTargets.cmake
  DESTINATION "${ELLIPSEKIT_INSTALL_CMAKEDIR}")

# 0.x: minor versions may break the API, so only the same major.minor is accepted.
write_basic_package_version_file(
  "${PROJECT_BINARY_DIR}/ellipsekitConfigVersion.cmake"
  VERSION "${PROJECT_VERSION}"
  COMPATIBILITY SameMinorVersion)

install(FILES
  "${PROJECT_BINARY_DIR}/ellipsekitConfig.cmake"
  "${PROJECT_BINARY_DIR}/ellipsekitConfigVersion.cmake"
  DESTINATION "${ELLIPSEKIT_INSTALL_CMAKEDIR}")

install(FILES "${PROJECT_BINARY_DIR}/ellipsekit.pc"
  DESTINATION "${CMAKE_INSTALL_LIBDIR}/pkgconfig")

# Maps one link item of the library to what a consumer of the installed package needs.
# Appends to the caller's _find_deps (config-file lines), _pc_modules (pkg-config modules that
# have libraries to link) and _pc_libs (plain linker flags).
# >>> Add new dependencies of the library here (e.g. another imported target). <<<
macro(_ellipsekit_map_dependency item)
  if("${item}" MATCHES "Eigen3::Eigen")
    # Header-only: CMake needs the target name defined, pkg-config needs nothing.
    list(APPEND _find_deps "find_dependency(Eigen3 3.3 NO_MODULE)")
  elseif("${item}" MATCHES "hwy::hwy_contrib")
    list(APPEND _find_deps "find_dependency(hwy)")
    list(APPEND _pc_modules libhwy-contrib libhwy)
  elseif("${item}" MATCHES "hwy::")
    list(APPEND _find_deps "find_dependency(hwy)")
    list(APPEND _pc_modules libhwy)
  elseif("${item}" MATCHES "Vulkan::")
    list(APPEND _find_deps "find_dependency(Vulkan)")
    list(APPEND _pc_modules vulkan)
  elseif("${item}" MATCHES "Threads::Threads")
    list(APPEND _find_deps "set(THREADS_PREFER_PTHREAD_FLAG ON)" "find_dependency(Threads)")
    list(APPEND _pc_libs -pthread)
  elseif("${item}" MATCHES "::")
    message(WARNING "cmake/install.cmake: ellipsekit links ${item}, which the installed package does "
                    "not know how to find; add it to _ellipsekit_map_dependency().")
  elseif(TARGET "${item}")
    get_target_property(_imported "${item}" IMPORTED)
    if(NOT _imported)
      message(WARNING "cmake/install.cmake: ellipsekit links the project target ${item}; install(EXPORT) "
                      "needs it in the export set (add it to install(TARGETS ... EXPORT ellipsekitTargets)) "
                      "or link it as $<BUILD_INTERFACE:${item}> / make it an OBJECT library.")
    endif()
  elseif("${item}" MATCHES "^-")
    list(APPEND _pc_libs "${item}")
  elseif(NOT "${item}" MATCHES "[$<>/]")
    list(APPEND _pc_libs "-l${item}")  # a plain system library name such as m or dl
  endif()
endmacro()

# Runs after the whole project is configured: writes ellipsekitConfig.cmake and ellipsekit.pc
# with the dependencies the library has at that point.
function(_ellipsekit_write_package_files)
  set(_robot_find_deps "")
  if(TARGET ellipsekit_robot)
    # Exported as ellipsekit::robot (the build tree's alias has the same name).
    set_target_properties(ellipsekit_robot PROPERTIES EXPORT_NAME robot)
    install(TARGETS ellipsekit_robot
      EXPORT ellipsekitTargets
      ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
      LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}"
      RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}"
      INCLUDES DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
    install(DIRECTORY "${PROJECT_SOURCE_DIR}/include/ellipsekit/robot"
      DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/ellipsekit"
      FILES_MATCHING PATTERN "*.h")
    list(APPEND _robot_find_deps "find_dependency(Eigen3 3.3 NO_MODULE)")  # robot headers use Eigen
  endif()
  get_target_property(_type ellipsekit TYPE)
  get_target_property(_interface ellipsekit INTERFACE_LINK_LIBRARIES)
  get_target_property(_all ellipsekit LINK_LIBRARIES)
  set(_items "")
  if(_interface)
    list(APPEND _items ${_interface})
  endif()
  if(_type STREQUAL "STATIC_LIBRARY" AND _all)
    list(APPEND _items ${_all})  # PRIVATE links reach the consumer's link line too
  endif()

  set(_find_deps "")
  set(_pc_modules "")
  set(_pc_libs "")
  foreach(_item IN LISTS _items)
    string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" _item "${_item}")
    if(_item MATCHES "^\\$<BUILD_INTERFACE:" OR _item STREQUAL "")
      continue()
    endif()
    _ellipsekit_map_dependency("${_item}")
  endforeach()
  list(APPEND _find_deps ${_robot_find_deps})
  list(REMOVE_DUPLICATES _find_deps)
  list(REMOVE_DUPLICATES _pc_modules)
  list(REMOVE_DUPLICATES _pc_libs)

  list(JOIN _find_deps "\n" ELLIPSEKIT_FIND_DEPENDENCIES)
  configure_package_config_file(
    "${CMAKE_CURRENT_FUNCTION_LIST_DIR}/ellipsekitConfig.cmake.in"
    "${PROJECT_BINARY_DIR}/ellipsekitConfig.cmake"
    INSTALL_DESTINATION "${ELLIPSEKIT_INSTALL_CMAKEDIR}")

  # pkg-config: a static library's dependencies must be linked by every consumer, so they go in
  # Requires/Libs; a shared library's only in the .private fields (used with --static).
  list(JOIN _pc_modules ", " _modules)
  list(JOIN _pc_libs " " _libs)
  if(_type STREQUAL "STATIC_LIBRARY")
    set(ELLIPSEKIT_PC_REQUIRES "${_modules}")
    set(ELLIPSEKIT_PC_REQUIRES_PRIVATE "")
    set(ELLIPSEKIT_PC_LIBS "${_libs}")
    set(ELLIPSEKIT_PC_LIBS_PRIVATE "")
  else()
    set(ELLIPSEKIT_PC_REQUIRES "")
    set(ELLIPSEKIT_PC_REQUIRES_PRIVATE "${_modules}")
    set(ELLIPSEKIT_PC_LIBS "")
    set(ELLIPSEKIT_PC_LIBS_PRIVATE "${_libs}")
  endif()
  # Relocatable: the prefix is found from the .pc file's own directory (${pcfiledir}).
  set(_pcdir "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
  if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}" OR IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
    set(ELLIPSEKIT_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
    set(ELLIPSEKIT_PC_LIBDIR "${CMAKE_INSTALL_FULL_LIBDIR}")
    set(ELLIPSEKIT_PC_INCLUDEDIR "${CMAKE_INSTALL_FULL_INCLUDEDIR}")
  else()
    file(RELATIVE_PATH _up "/root/${_pcdir}" "/root")
    string(REGEX REPLACE "/$" "" _up "${_up}")
    set(ELLIPSEKIT_PC_PREFIX "\${pcfiledir}/${_up}")
    set(ELLIPSEKIT_PC_LIBDIR "\${prefix}/${CMAKE_INSTALL_LIBDIR}")
    set(ELLIPSEKIT_PC_INCLUDEDIR "\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}")
  endif()
  configure_file("${CMAKE_CURRENT_FUNCTION_LIST_DIR}/ellipsekit.pc.in"
                 "${PROJECT_BINARY_DIR}/ellipsekit.pc" @ONLY)
  if(TARGET ellipsekit_robot)
    file(CONFIGURE OUTPUT "${PROJECT_BINARY_DIR}/ellipsekit-robot.pc" @ONLY CONTENT [=[
prefix=@ELLIPSEKIT_PC_PREFIX@
exec_prefix=${prefix}
libdir=@ELLIPSEKIT_PC_LIBDIR@
includedir=@ELLIPSEKIT_PC_INCLUDEDIR@

Name: ellipsekit-robot
Description: ellipsekit's robot adapter: camera model, rim centres from depth, circle pose, tracking, conveyor and grasp planning, the per-frame loop. Compile with -std=c++20.
Version: @PROJECT_VERSION@
Requires: ellipsekit = @PROJECT_VERSION@, eigen3
Cflags: -I${includedir}
Libs: -L${libdir} -lellipsekit_robot
]=])
    install(FILES "${PROJECT_BINARY_DIR}/ellipsekit-robot.pc" DESTINATION "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
  endif()
endfunction()

cmake_language(DEFER CALL _ellipsekit_write_package_files)
