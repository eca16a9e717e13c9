# Every dependency comes from a Debian 12 package (scripts/setup installs them all).
# Each block names the package to install when the lookup fails.

find_package(Eigen3 3.4 REQUIRED NO_MODULE)
if(NOT TARGET Eigen3::Eigen)
  message(FATAL_ERROR "Eigen3 not found: run scripts/setup (apt-get install libeigen3-dev)")
endif()

# CGAL is header-only here; keep its warnings out of ours.
set(CGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE TRUE)
find_package(CGAL QUIET)
if(NOT CGAL_FOUND)
  message(FATAL_ERROR "CGAL not found: run scripts/setup (apt-get install libcgal-dev libgmp-dev libmpfr-dev)")
endif()

find_package(PNG QUIET)
if(NOT PNG_FOUND)
  message(FATAL_ERROR "libpng not found: run scripts/setup (apt-get install libpng-dev)")
endif()

find_package(CLI11 CONFIG QUIET)
if(NOT CLI11_FOUND)
  message(FATAL_ERROR "CLI11 not found: run scripts/setup (apt-get install libcli11-dev)")
endif()

find_package(tomlplusplus CONFIG QUIET)
if(NOT tomlplusplus_FOUND)
  message(FATAL_ERROR "toml++ not found: run scripts/setup (apt-get install libtomlplusplus-dev)")
endif()

find_package(Threads REQUIRED)

if(CRACKLE_BUILD_TESTS)
  find_package(doctest CONFIG QUIET)
  if(NOT doctest_FOUND)
    message(FATAL_ERROR "doctest not found: run scripts/setup (apt-get install doctest-dev)")
  endif()
endif()

# CHOLMOD (SuiteSparse 5.12 has no CMake package on Debian 12): library + headers.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
if(NOT CHOLMOD_INCLUDE_DIR OR NOT CHOLMOD_LIBRARY)
  message(FATAL_ERROR "CHOLMOD not found: run scripts/setup (apt-get install libsuitesparse-dev)")
endif()
add_library(crackle_cholmod INTERFACE)
add_library(SuiteSparse::CHOLMOD ALIAS crackle_cholmod)
target_include_directories(crackle_cholmod SYSTEM INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(crackle_cholmod INTERFACE ${CHOLMOD_LIBRARY})

find_package(OpenMP REQUIRED)

find_package(PkgConfig REQUIRED)
pkg_check_modules(OSMESA QUIET IMPORTED_TARGET osmesa)
if(NOT OSMESA_FOUND)
  message(FATAL_ERROR "OSMesa not found: run scripts/setup (apt-get install libosmesa6-dev)")
endif()

find_package(assimp CONFIG QUIET)
if(NOT assimp_FOUND)
  message(FATAL_ERROR "assimp not found: run scripts/setup (apt-get install libassimp-dev)")
endif()

find_package(TinyGLTF CONFIG QUIET)
if(NOT TinyGLTF_FOUND)
  message(FATAL_ERROR "tinygltf not found: run scripts/setup (apt-get install libtinygltf-dev)")
endif()

find_package(OpenEXR CONFIG QUIET)
if(NOT OpenEXR_FOUND)
  message(FATAL_ERROR "OpenEXR not found: run scripts/setup (apt-get install libopenexr-dev)")
endif()
