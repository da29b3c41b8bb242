# Locate an installed shared-library LAMMPS and its source tree (for headers) and
# define the interface target sphcut::lammps that the plugin, the launcher and the
# tests link against.
#
# Inputs (cache variables, usually from sphcut-deps.cmake):
#   LAMMPS_SOURCE_DIR  LAMMPS src/ folder (headers: src/, src/KOKKOS)
#   LAMMPS_ROOT        install prefix holding lib/liblammps.so, lib/cmake/LAMMPS, bin/lmp
#   Kokkos_ROOT        Kokkos install prefix (only when LAMMPS has KOKKOS)
#   SPHCUT_KOKKOS      AUTO (default: when LAMMPS has KOKKOS), ON, OFF
# Outputs: sphcut::lammps, SPHCUT_WITH_KOKKOS, LAMMPS_BINARY, LAMMPS_LIBRARY_DIR,
#          SPHCUT_LAMMPS_VERSION (e.g. 20210929)

set(LAMMPS_SOURCE_DIR "" CACHE PATH "LAMMPS source folder src/ (headers)")
set(LAMMPS_ROOT "" CACHE PATH "LAMMPS install prefix (lib/liblammps.so, bin/lmp)")
set(SPHCUT_KOKKOS AUTO CACHE STRING "Build the /kk styles: AUTO, ON or OFF")
set_property(CACHE SPHCUT_KOKKOS PROPERTY STRINGS AUTO ON OFF)

if(NOT LAMMPS_SOURCE_DIR OR NOT EXISTS "${LAMMPS_SOURCE_DIR}/lammps.h")
  message(FATAL_ERROR "sphcut: LAMMPS_SOURCE_DIR='${LAMMPS_SOURCE_DIR}' has no lammps.h; "
    "run tools/build-deps.sh and pass -DSPHCUT_DEPS_FILE=<prefix>/sphcut-deps.cmake, "
    "or set LAMMPS_SOURCE_DIR to the src/ folder of the LAMMPS you link against")
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

# version as a number YYYYMMDD, from version.h ("29 Sep 2021")
file(STRINGS "${LAMMPS_SOURCE_DIR}/version.h" _ver REGEX "LAMMPS_VERSION")
string(REGEX MATCH "\"([0-9]+) ([A-Za-z]+) ([0-9]+)\"" _m "${_ver}")
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
message(STATUS "sphcut: LAMMPS ${CMAKE_MATCH_1} ${CMAKE_MATCH_2} ${CMAKE_MATCH_3} at ${_lmp_prefix}")

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
