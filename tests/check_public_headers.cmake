# SPDX-License-Identifier: Apache-2.0
# CTest test public_header_hygiene: the installed headers stay cheap to include and free of
# implementation details (STYLE.md, compile cost table).
#
#   cmake -DVDBI_HEADER_DIR=<lib/vdbi> -P check_public_headers.cmake
#
# No header in lib/vdbi may include
#   - openvdb/tools/*            (5-7 s and 500 MB per translation unit; .cc files only)
#   - openvdb/tree/LeafManager.h (a parallel-pass helper, .cc files only)
#   - tbb/*                      (threading is an implementation detail)
#   - OpenMesh/*                 except PatchMeshes.h, the OpenMesh conversion, so that the
#                                SOP, the writers and most tests need no mesh library.
# Comments are ignored; both <...> and "..." includes are checked.

cmake_minimum_required(VERSION 3.20)

if(NOT VDBI_HEADER_DIR OR NOT IS_DIRECTORY "${VDBI_HEADER_DIR}")
  message(FATAL_ERROR "check_public_headers: -DVDBI_HEADER_DIR=<lib/vdbi> is required")
endif()

# Headers allowed to include OpenMesh.
set(openmesh_headers PatchMeshes.h)

file(GLOB headers "${VDBI_HEADER_DIR}/*.h")
if(NOT headers)
  message(FATAL_ERROR "check_public_headers: no headers in ${VDBI_HEADER_DIR}")
endif()

set(violations "")
set(checked 0)
foreach(header IN LISTS headers)
  get_filename_component(name "${header}" NAME)
  math(EXPR checked "${checked} + 1")
  file(STRINGS "${header}" lines REGEX "^[ \t]*#[ \t]*include")
  foreach(line IN LISTS lines)
    string(REGEX REPLACE "//.*$" "" code "${line}")
    if(NOT code MATCHES "#[ \t]*include[ \t]*[<\"]([^>\"]+)[>\"]")
      continue()
    endif()
    set(included "${CMAKE_MATCH_1}")
    set(reason "")
    if(included MATCHES "^openvdb/tools/")
      set(reason "openvdb/tools/* belongs in the .cc")
    elseif(included STREQUAL "openvdb/tree/LeafManager.h")
      set(reason "LeafManager.h belongs in the .cc")
    elseif(included MATCHES "^tbb/")
      set(reason "TBB belongs in the .cc")
    elseif(included MATCHES "^OpenMesh/" AND NOT name IN_LIST openmesh_headers)
      set(reason "only ${openmesh_headers} may include OpenMesh")
    endif()
    if(reason)
      string(STRIP "${code}" code)
      list(APPEND violations "  ${name}: ${code}  (${reason})")
    endif()
  endforeach()
endforeach()

if(violations)
  list(JOIN violations "\n" text)
  message(FATAL_ERROR "public headers include implementation details:\n${text}")
endif()
message(STATUS "public_header_hygiene: ${checked} headers in ${VDBI_HEADER_DIR} are clean")
