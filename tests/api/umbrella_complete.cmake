# SPDX-License-Identifier: MIT
#
# cmake -DINCLUDE_DIR=<include> -P umbrella_complete.cmake: fails naming
# every public header that <ecmxf/ecmxf.hpp> does not include (a header
# that moved and forwards to its new path is not asked for).
file(READ ${INCLUDE_DIR}/ecmxf/ecmxf.hpp _umbrella)
file(GLOB_RECURSE _headers RELATIVE ${INCLUDE_DIR} ${INCLUDE_DIR}/ecmxf/*.hpp)
set(_missing)
foreach(_h IN LISTS _headers)
  if(_h STREQUAL "ecmxf/ecmxf.hpp" OR _h STREQUAL "ecmxf/export.hpp" OR _h MATCHES "/types_[a-z0-9]+\\.hpp$")
    continue()
  endif()
  # a header that moved forwards to its new path for one release: the
  # umbrella includes the new one
  file(READ ${INCLUDE_DIR}/${_h} _text)
  if(_text MATCHES "@brief Moved to <ecmxf/")
    continue()
  endif()
  string(FIND "${_umbrella}" "#include <${_h}>" _at)
  if(_at EQUAL -1)
    list(APPEND _missing ${_h})
  endif()
endforeach()
if(_missing)
  list(JOIN _missing ", " _text)
  message(FATAL_ERROR "ecmxf/ecmxf.hpp does not include: ${_text}")
endif()
list(LENGTH _headers _n)
message(STATUS "ecmxf/ecmxf.hpp includes every public header (${_n} found)")
