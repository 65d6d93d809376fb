# SPDX-License-Identifier: Apache-2.0
# CTest test consumer_project: install this build into a scratch prefix, then configure, build
# and run tests/consumer against it with find_package(vdb_interfaces).
#
#   cmake -DVDBI_BUILD_DIR=<build> -DVDBI_WORK_DIR=<scratch> -DVDBI_GENERATOR=<generator>
#         [-DVDBI_MAKE_PROGRAM=...] [-DVDBI_CXX_COMPILER=...] [-DVDBI_CXX_LAUNCHER=...]
#         [-DVDBI_BUILD_TYPE=Release] -P run.cmake

cmake_minimum_required(VERSION 3.20)

foreach(var VDBI_BUILD_DIR VDBI_WORK_DIR VDBI_GENERATOR)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "run.cmake: -D${var}=... is required")
  endif()
endforeach()
if(NOT VDBI_BUILD_TYPE)
  set(VDBI_BUILD_TYPE Release)
endif()

set(prefix "${VDBI_WORK_DIR}/prefix")
set(build "${VDBI_WORK_DIR}/build")
# A fresh prefix and a fresh configure every run: nothing stale can make the test pass.
file(REMOVE_RECURSE "${prefix}" "${build}")

function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "consumer_project: ${what} failed (${rc})")
  endif()
endfunction()

run_step("install" "${CMAKE_COMMAND}" --install "${VDBI_BUILD_DIR}" --prefix "${prefix}"
  --config "${VDBI_BUILD_TYPE}")

set(configure_args
  -S "${CMAKE_CURRENT_LIST_DIR}" -B "${build}" -G "${VDBI_GENERATOR}"
  "-DCMAKE_PREFIX_PATH=${prefix}"
  "-DCMAKE_BUILD_TYPE=${VDBI_BUILD_TYPE}")
if(VDBI_MAKE_PROGRAM)
  list(APPEND configure_args "-DCMAKE_MAKE_PROGRAM=${VDBI_MAKE_PROGRAM}")
endif()
if(VDBI_CXX_COMPILER)
  list(APPEND configure_args "-DCMAKE_CXX_COMPILER=${VDBI_CXX_COMPILER}")
endif()
if(VDBI_CXX_LAUNCHER)
  list(APPEND configure_args "-DCMAKE_CXX_COMPILER_LAUNCHER=${VDBI_CXX_LAUNCHER}")
endif()
run_step("configure" "${CMAKE_COMMAND}" ${configure_args})
run_step("build" "${CMAKE_COMMAND}" --build "${build}" --config "${VDBI_BUILD_TYPE}")

# Multi-config generators put the program in a per-configuration folder.
set(consumer "")
foreach(candidate "${build}/vdbi_consumer" "${build}/${VDBI_BUILD_TYPE}/vdbi_consumer")
  if(NOT consumer AND EXISTS "${candidate}")
    set(consumer "${candidate}")
  endif()
endforeach()
if(NOT consumer)
  message(FATAL_ERROR "consumer_project: vdbi_consumer was not built in ${build}")
endif()
run_step("run" "${consumer}")
message(STATUS "consumer_project: passed")
