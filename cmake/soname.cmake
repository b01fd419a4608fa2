# fss_soname(OUT LIBRARIES MODULE DEBIAN): sets OUT to the SONAME of the
# shared library among LIBRARIES (the full paths a find module or pkg-config
# gave for MODULE), read from its dynamic section with readelf, or objdump
# where readelf is missing. The library loads PLplot and libtiff by that name
# at their first use (src/io/plplot_api.cpp, src/io/tiff_api.cpp), so the name
# is the one the build compiled against. Configure fails, naming MODULE and
# DEBIAN (the package of its development files), when there is no shared
# library or no SONAME in it. Sets OUT_PACKAGE to the Debian name of the
# package holding that SONAME (libtiff.so.6: libtiff6; libfoo2.so.1: libfoo2-1),
# for the error of a run that cannot load it.
function(fss_soname out libraries module debian)
  set(_library "")
  foreach(_candidate IN LISTS libraries)
    if(_candidate MATCHES "\\.so(\\.[0-9.]+)?$" AND EXISTS "${_candidate}")
      set(_library "${_candidate}")
      break()
    endif()
  endforeach()
  if(NOT _library)
    message(FATAL_ERROR "${module}: no shared library among '${libraries}'; fss loads it at "
                        "run time by its SONAME (Debian: ${debian})")
  endif()
  if(CMAKE_READELF)
    execute_process(COMMAND "${CMAKE_READELF}" -d "${_library}" OUTPUT_VARIABLE _dynamic
                    RESULT_VARIABLE _status ERROR_QUIET)
    string(REGEX MATCH "\\(SONAME\\)[^[]*\\[([^]]+)\\]" _match "${_dynamic}")
  elseif(CMAKE_OBJDUMP)
    execute_process(COMMAND "${CMAKE_OBJDUMP}" -p "${_library}" OUTPUT_VARIABLE _dynamic
                    RESULT_VARIABLE _status ERROR_QUIET)
    string(REGEX MATCH "SONAME[ \t]+([^ \t\r\n]+)" _match "${_dynamic}")
  else()
    message(FATAL_ERROR "${module}: neither readelf nor objdump found to read the SONAME of "
                        "${_library} (Debian: binutils)")
  endif()
  if(NOT _status EQUAL 0 OR NOT CMAKE_MATCH_1)
    message(FATAL_ERROR "${module}: cannot read the SONAME of ${_library}; fss loads it at run "
                        "time by that name (Debian: ${debian})")
  endif()
  set(_soname "${CMAKE_MATCH_1}")
  set(${out} "${_soname}" PARENT_SCOPE)
  if(_soname MATCHES "^(.*)\\.so\\.([^.]+)")
    set(_base "${CMAKE_MATCH_1}")
    set(_major "${CMAKE_MATCH_2}")
    if(_base MATCHES "[0-9]$")
      set(_base "${_base}-")
    endif()
    string(TOLOWER "${_base}${_major}" _package)
  else()
    string(REGEX REPLACE "\\.so$" "" _package "${_soname}")
  endif()
  set(${out}_PACKAGE "${_package}" PARENT_SCOPE)
endfunction()
