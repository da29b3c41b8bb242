# Locate the LAMMPS to build against and define the interface target sphcut::lammps that the
# plugin, the launcher and the tests link against.  Two ways:
#   - an installed shared-library LAMMPS (LAMMPS_ROOT: its CMake package, liblammps.so, bin/lmp) and
#     its source tree (LAMMPS_SOURCE_DIR): the plugin, /kk styles where that LAMMPS has KOKKOS,
#     the launcher lmp_sphcut and the tests (what `make` does, with tools/build-deps.sh);
#   - the plugin alone (SPHCUT_PLUGIN_ONLY, the default when LAMMPS_ROOT is not given), as LAMMPS'
#     own examples/plugins build theirs: only the src/ folder of the LAMMPS it will be loaded into
#     (LAMMPS_SOURCE_DIR), its version from version.h (LAMMPS' get_lammps_version() from
#     cmake/Modules/LAMMPSUtils.cmake where the source tree has it), MPI found as LAMMPS' CMake
#     build finds it (find_package(MPI); BUILD_MPI=OFF: LAMMPS' STUBS), nothing linked: the
#     running LAMMPS provides every symbol at `plugin load`.  CPU styles only, no launcher, no
#     tests; `cmake --install` puts sphcutplugin.so into SPHCUT_PLUGIN_DIR (doc/build.md).
#
# Inputs (cache variables, usually from sphcut-deps.cmake):
#   LAMMPS_SOURCE_DIR  LAMMPS src/ folder (headers: src/, src/KOKKOS)
#   LAMMPS_ROOT        install prefix holding lib/liblammps.so, lib/cmake/LAMMPS, bin/lmp
#   Kokkos_ROOT        Kokkos install prefix (only when LAMMPS has KOKKOS)
#   SPHCUT_KOKKOS      AUTO (default: when LAMMPS has KOKKOS), ON, OFF
#   SPHCUT_PLUGIN_ONLY ON: the plugin alone against LAMMPS_SOURCE_DIR (default: ON without LAMMPS_ROOT)
#   BUILD_MPI, LAMMPS_SIZES  plugin-only: as LAMMPS was configured (default ON where MPI is found; smallbig)
#   LAMMPS_BINARY      plugin-only, optional: that LAMMPS's lmp, for its C++ standard and version
# Outputs: sphcut::lammps, SPHCUT_WITH_KOKKOS, LAMMPS_BINARY, LAMMPS_LIBRARY_DIR,
#          SPHCUT_LAMMPS_VERSION (e.g. 20210929), SPHCUT_PLUGIN_ONLY

set(LAMMPS_SOURCE_DIR "" CACHE PATH "LAMMPS source folder src/ (headers)")
set(LAMMPS_ROOT "" CACHE PATH "LAMMPS install prefix (lib/liblammps.so, bin/lmp)")
set(SPHCUT_KOKKOS AUTO CACHE STRING "Build the /kk styles: AUTO, ON or OFF")
set_property(CACHE SPHCUT_KOKKOS PROPERTY STRINGS AUTO ON OFF)

if(NOT LAMMPS_SOURCE_DIR OR NOT EXISTS "${LAMMPS_SOURCE_DIR}/lammps.h")
  message(FATAL_ERROR "sphcut: LAMMPS_SOURCE_DIR='${LAMMPS_SOURCE_DIR}' has no lammps.h; "
    "run tools/build-deps.sh and pass -DSPHCUT_DEPS_FILE=<prefix>/sphcut-deps.cmake, "
    "or set LAMMPS_SOURCE_DIR to the src/ folder of the LAMMPS you link against")
endif()

# version as a number YYYYMMDD, from version.h ("29 Sep 2021")
file(STRINGS "${LAMMPS_SOURCE_DIR}/version.h" _ver REGEX "LAMMPS_VERSION")
string(REGEX MATCH "\"([0-9]+) ([A-Za-z]+) ([0-9]+)\"" _m "${_ver}")
set(_lmp_version_text "${CMAKE_MATCH_1} ${CMAKE_MATCH_2} ${CMAKE_MATCH_3}")
set(_months Jan Feb Mar Apr May Jun Jul Aug Sep Oct Nov Dec)
list(FIND _months "${CMAKE_MATCH_2}" _mi)
math(EXPR _mi "${_mi} + 1")
if(_mi LESS 10)
  set(_mi "0${_mi}")
endif()
set(_d "${CMAKE_MATCH_1}")
if(_d LESS 10)
  set(_d "0${_d}")
endif()
set(SPHCUT_LAMMPS_VERSION "${CMAKE_MATCH_3}${_mi}${_d}")

if(NOT DEFINED SPHCUT_PLUGIN_ONLY)
  if(LAMMPS_ROOT)
    set(_plugin_only OFF)
  else()
    set(_plugin_only ON)
  endif()
  set(SPHCUT_PLUGIN_ONLY ${_plugin_only} CACHE BOOL
    "Build only the plugin against LAMMPS_SOURCE_DIR, as LAMMPS' examples/plugins do (no launcher, no tests)")
endif()

if(SPHCUT_PLUGIN_ONLY)
  # LAMMPS' own helper where the source tree has it (its format changed: 20210929 in 29Sep2021,
  # 2026.7.4.0 in 4Jul2026); both must agree with the number read above
  set(_lmp_utils "${LAMMPS_SOURCE_DIR}/../cmake/Modules/LAMMPSUtils.cmake")
  if(EXISTS "${_lmp_utils}")
    include("${_lmp_utils}")
    get_lammps_version("${LAMMPS_SOURCE_DIR}/version.h" _lmp_helper_version)
    if(_lmp_helper_version MATCHES "^([0-9][0-9][0-9][0-9])\\.([0-9]+)\\.([0-9]+)")
      math(EXPR _hv "${CMAKE_MATCH_1} * 10000 + ${CMAKE_MATCH_2} * 100 + ${CMAKE_MATCH_3}")
    else()
      set(_hv "${_lmp_helper_version}")
    endif()
    if(NOT _hv EQUAL SPHCUT_LAMMPS_VERSION)
      message(FATAL_ERROR "sphcut: LAMMPS' get_lammps_version() says ${_lmp_helper_version}, version.h ${_lmp_version_text}")
    endif()
  endif()
  # The C++ standard must be LAMMPS' own: 4Jul2026 built with C++20 formats its messages with
  # std::format instead of its bundled fmt, and a plugin compiled with C++17 then needs symbols that
  # LAMMPS lacks ("undefined symbol: ...Error8_warning...fmt...v10_lmp" at plugin load).  `lmp -h`
  # says which standard and which version: given the lmp (LAMMPS_BINARY), both are taken from it
  set(LAMMPS_BINARY "" CACHE FILEPATH "plugin-only: the lmp the plugin is for (its C++ standard and version are read from lmp -h)")
  if(LAMMPS_BINARY)
    execute_process(COMMAND ${LAMMPS_BINARY} -h OUTPUT_VARIABLE _lmp_help ERROR_QUIET TIMEOUT 60)
    if(NOT _lmp_help MATCHES "Simulator - ([0-9]+ [A-Za-z]+ [0-9]+)")
      message(FATAL_ERROR "sphcut: `${LAMMPS_BINARY} -h` does not name a LAMMPS version")
    endif()
    if(NOT CMAKE_MATCH_1 STREQUAL _lmp_version_text)
      message(FATAL_ERROR "sphcut: ${LAMMPS_BINARY} is LAMMPS ${CMAKE_MATCH_1}, but LAMMPS_SOURCE_DIR "
        "(${LAMMPS_SOURCE_DIR}) is ${_lmp_version_text}: use the source tree of the same version")
    endif()
    if(_lmp_help MATCHES "C\\+\\+ standard: C\\+\\+([0-9]+)")
      set(SPHCUT_LAMMPS_CXX_STANDARD ${CMAKE_MATCH_1})
      message(STATUS "sphcut: ${LAMMPS_BINARY} was built with C++${CMAKE_MATCH_1}: the plugin is too")
    endif()
  else()
    message(STATUS "sphcut: plugin only: compiled with C++${CMAKE_CXX_STANDARD} (17 for LAMMPS after 29Sep2021); "
      "it must be the standard `lmp -h` names (\"C++ standard\"): set CMAKE_CXX_STANDARD, or LAMMPS_BINARY=<lmp>")
  endif()
  add_library(sphcut_lammps INTERFACE)
  add_library(sphcut::lammps ALIAS sphcut_lammps)
  target_include_directories(sphcut_lammps INTERFACE "${LAMMPS_SOURCE_DIR}")
  target_compile_definitions(sphcut_lammps INTERFACE SPHCUT_LAMMPS_VERSION=${SPHCUT_LAMMPS_VERSION})
  # MPI as LAMMPS' CMake build and its plugin examples find it (the same MPI LAMMPS was built with:
  # put its mpicxx first on PATH, or set MPI_HOME); BUILD_MPI=OFF: LAMMPS' MPI stubs
  set(MPI_CXX_SKIP_MPICXX TRUE)
  find_package(MPI QUIET COMPONENTS CXX)
  option(BUILD_MPI "The LAMMPS this plugin is for uses MPI (OFF: its STUBS)" ${MPI_FOUND})
  if(BUILD_MPI)
    find_package(MPI REQUIRED COMPONENTS CXX)
    target_link_libraries(sphcut_lammps INTERFACE MPI::MPI_CXX)
    message(STATUS "sphcut: MPI ${MPI_CXX_VERSION} (${MPI_CXX_COMPILER})")
  else()
    target_include_directories(sphcut_lammps INTERFACE "${LAMMPS_SOURCE_DIR}/STUBS")
  endif()
  set(LAMMPS_SIZES "smallbig" CACHE STRING "LAMMPS integer sizes, as LAMMPS was built: smallbig or bigbig")
  string(TOUPPER "${LAMMPS_SIZES}" _sizes)
  target_compile_definitions(sphcut_lammps INTERFACE LAMMPS_${_sizes})
  if(SPHCUT_KOKKOS STREQUAL "ON")
    message(FATAL_ERROR "sphcut: the /kk styles need an installed LAMMPS with KOKKOS (LAMMPS_ROOT, "
      "SPHCUT_PLUGIN_ONLY=OFF): its Kokkos and its KOKKOS package options must be matched exactly")
  endif()
  set(SPHCUT_WITH_KOKKOS OFF)
  set(LAMMPS_LIBRARY_DIR "")
  message(STATUS "sphcut: LAMMPS ${_lmp_version_text}, plugin only against ${LAMMPS_SOURCE_DIR} "
    "(CPU styles; no launcher, no tests)")
  return()
endif()

find_package(LAMMPS CONFIG REQUIRED HINTS "${LAMMPS_ROOT}" "${LAMMPS_ROOT}/lib/cmake/LAMMPS")
get_target_property(_lmp_lib LAMMPS::lammps LOCATION)
get_filename_component(LAMMPS_LIBRARY_DIR "${_lmp_lib}" DIRECTORY)
get_filename_component(_lmp_prefix "${LAMMPS_LIBRARY_DIR}" DIRECTORY)
find_program(LAMMPS_BINARY NAMES lmp lmp_serial lmp_mpi HINTS "${_lmp_prefix}/bin" "${LAMMPS_ROOT}/bin"
  NO_DEFAULT_PATH)
if(NOT LAMMPS_BINARY)
  message(FATAL_ERROR "sphcut: no lmp executable next to ${_lmp_lib}")
endif()
message(STATUS "sphcut: LAMMPS ${_lmp_version_text} at ${_lmp_prefix}")

# which packages does that LAMMPS have? `lmp -h` lists them
execute_process(COMMAND ${LAMMPS_BINARY} -h OUTPUT_VARIABLE _lmp_help ERROR_QUIET
  RESULT_VARIABLE _rc TIMEOUT 60)
string(REGEX MATCH "Installed packages:[^\n]*\n\n?([^\n]*\n)*" _pkgs "${_lmp_help}")
if(_pkgs MATCHES "KOKKOS")
  set(_lmp_has_kokkos ON)
else()
  set(_lmp_has_kokkos OFF)
endif()

add_library(sphcut_lammps INTERFACE)
add_library(sphcut::lammps ALIAS sphcut_lammps)
target_include_directories(sphcut_lammps INTERFACE "${LAMMPS_SOURCE_DIR}")
target_link_libraries(sphcut_lammps INTERFACE LAMMPS::lammps)
target_compile_definitions(sphcut_lammps INTERFACE SPHCUT_LAMMPS_VERSION=${SPHCUT_LAMMPS_VERSION})

set(SPHCUT_WITH_KOKKOS OFF)
if(SPHCUT_KOKKOS STREQUAL "ON" OR (SPHCUT_KOKKOS STREQUAL "AUTO" AND _lmp_has_kokkos))
  if(NOT _lmp_has_kokkos)
    message(FATAL_ERROR "sphcut: SPHCUT_KOKKOS=ON but ${LAMMPS_BINARY} has no KOKKOS package")
  endif()
  find_package(Kokkos 3.4 REQUIRED CONFIG HINTS "${Kokkos_ROOT}")
  # CUDA builds: Kokkos 3.4 knows no Hopper architecture and hands its targets -arch=sm_80 (PTX that
  # the driver JIT-compiles for sm_90).  SPHCUT_CUDA_ARCH=sm_90 compiles the plugin's own kernels
  # natively instead (LAMMPS' kernels stay as they were built); bench/gpu/mechanics.sh arch compares.
  set(SPHCUT_CUDA_ARCH "" CACHE STRING "CUDA builds: architecture of the plugin's kernels, e.g. sm_90")
  if(SPHCUT_CUDA_ARCH)
    foreach(_t Kokkos::kokkoscore Kokkos::kokkoscontainers Kokkos::kokkos)
      if(TARGET ${_t})
        foreach(_prop INTERFACE_COMPILE_OPTIONS INTERFACE_LINK_OPTIONS)
          get_target_property(_opts ${_t} ${_prop})
          if(_opts)
            string(REGEX REPLACE "-arch=sm_[0-9]+" "-arch=${SPHCUT_CUDA_ARCH}" _new "${_opts}")
            set_target_properties(${_t} PROPERTIES ${_prop} "${_new}")
            if(NOT _new STREQUAL _opts)
              message(STATUS "sphcut: ${_t} ${_prop}: -arch=${SPHCUT_CUDA_ARCH}")
            endif()
          endif()
        endforeach()
      endif()
    endforeach()
  endif()
  target_include_directories(sphcut_lammps INTERFACE "${LAMMPS_SOURCE_DIR}/KOKKOS")
  target_compile_definitions(sphcut_lammps INTERFACE LMP_KOKKOS)
  target_link_libraries(sphcut_lammps INTERFACE Kokkos::kokkos)
  set(SPHCUT_WITH_KOKKOS ON)
endif()
message(STATUS "sphcut: KOKKOS styles ${SPHCUT_WITH_KOKKOS} (LAMMPS has KOKKOS: ${_lmp_has_kokkos})")
