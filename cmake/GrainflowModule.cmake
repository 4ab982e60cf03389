# SPDX-License-Identifier: GPL-3.0-or-later
# gf_add_module(NAME SOURCES ... DEPS ...): one static library per module, includes from src/.
function(gf_add_module name)
  cmake_parse_arguments(M "" "" "SOURCES;DEPS" ${ARGN})
  if(M_SOURCES)
    add_library(gf_${name} STATIC ${M_SOURCES})
    target_include_directories(gf_${name} PUBLIC ${PROJECT_SOURCE_DIR}/src ${PROJECT_BINARY_DIR}/generated)
    target_link_libraries(gf_${name} PUBLIC ${M_DEPS} PRIVATE gf_warnings)
  else()
    add_library(gf_${name} INTERFACE)
    target_include_directories(gf_${name} INTERFACE ${PROJECT_SOURCE_DIR}/src ${PROJECT_BINARY_DIR}/generated)
    target_link_libraries(gf_${name} INTERFACE ${M_DEPS})
  endif()
endfunction()
