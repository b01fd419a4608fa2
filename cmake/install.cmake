# What `cmake --install` puts under the prefix, and the install test.
#
#   bin/fssim
#   lib/libfss.a, or libfss.so.0.1.0 with its links (BUILD_SHARED_LIBS=ON)
#   include/fss/**.h
#   lib/cmake/fss/fssConfig.cmake, fssConfigVersion.cmake, fssTargets*.cmake
#       find_package(fss CONFIG) gives the target fss::fss
#   lib/pkgconfig/fss.pc
#   share/fssim/codes/*.txt                  the paper's six codes
#   share/man/man1/fssim.1                   docs/fssim.1, version and date made true
#   lib/python3.X/site-packages/fss/         the Python package (cmake/python.cmake)
#   share/bash-completion/completions/fssim
#
# (lib is CMAKE_INSTALL_LIBDIR: lib/x86_64-linux-gnu under /usr on Debian.)

include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# The headers use C++20 (std::span): consumers compile with it too.
target_compile_features(fss PUBLIC cxx_std_20)
set_target_properties(fss PROPERTIES EXPORT_NAME fss)
add_library(fss::fss ALIAS fss)

get_target_property(_fss_type fss TYPE)
if(_fss_type STREQUAL "SHARED_LIBRARY")
  set(FSS_SHARED ON)
  set_target_properties(fss PROPERTIES VERSION ${PROJECT_VERSION}
                                       SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
  # The installed fssim finds libfss.so next to it, wherever the prefix is
  # moved: RUNPATH $ORIGIN/../lib (the relative path from bin to lib); not
  # needed when the libdir is one the linker searches anyway (/usr/lib/...).
  if(NOT CMAKE_INSTALL_FULL_LIBDIR IN_LIST CMAKE_CXX_IMPLICIT_LINK_DIRECTORIES)
    file(RELATIVE_PATH _fss_bin_to_lib "${CMAKE_INSTALL_FULL_BINDIR}" "${CMAKE_INSTALL_FULL_LIBDIR}")
    set_target_properties(fssim PROPERTIES INSTALL_RPATH "$ORIGIN/${_fss_bin_to_lib}")
  endif()
else()
  set(FSS_SHARED OFF)
endif()

install(TARGETS fss EXPORT fssTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS fssim RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY include/fss DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h")
install(FILES ${FSS_CODE_FILES} DESTINATION ${CMAKE_INSTALL_DATADIR}/fssim/codes)
install(FILES ${PROJECT_BINARY_DIR}/fssim.1 DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
install(FILES scripts/completion/fssim.bash DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions
        RENAME fssim)

# The installed man page is docs/fssim.1 with its .TH line made true at
# configure time: the project's version, and the date of the last commit that
# changed the page (the date in the source is kept outside a git checkout).
file(READ ${PROJECT_SOURCE_DIR}/docs/fssim.1 _fss_man)
set(_fss_man_date "")
if(GIT_FOUND)
  execute_process(
    COMMAND "${GIT_EXECUTABLE}" log -1 --format=%cs -- docs/fssim.1
    WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}"
    OUTPUT_VARIABLE _fss_man_date
    OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
endif()
if(NOT _fss_man_date MATCHES "^[0-9]+-[0-9]+-[0-9]+$")
  string(REGEX MATCH "\n[.]TH FSSIM 1 \"([^\"]*)\"" _fss_match "${_fss_man}")
  set(_fss_man_date "${CMAKE_MATCH_1}")
endif()
string(REGEX REPLACE "\n[.]TH FSSIM 1 \"[^\"]*\" \"fssim [^\"]*\""
       "\n.TH FSSIM 1 \"${_fss_man_date}\" \"fssim ${PROJECT_VERSION}\"" _fss_man "${_fss_man}")
file(CONFIGURE OUTPUT ${PROJECT_BINARY_DIR}/fssim.1 CONTENT "${_fss_man}" @ONLY)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/docs/fssim.1)

# The CMake package. The library links ISA-L and the dynamic loader's library
# (CMAKE_DL_LIBS) privately: a shared libfss carries them, a static one needs
# them at the consumer's link, so the config file finds ISA-L only for a static
# build. PLplot and libtiff are not linked: libfss loads them at their first
# use (src/io/plplot_api.cpp, src/io/tiff_api.cpp), from the installed system.
set(FSS_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/fss)
install(EXPORT fssTargets NAMESPACE fss:: DESTINATION ${FSS_CMAKE_DIR})
configure_package_config_file(cmake/fssConfig.cmake.in ${PROJECT_BINARY_DIR}/fssConfig.cmake
                              INSTALL_DESTINATION ${FSS_CMAKE_DIR})
# 0.x: a minor version may break the interface.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/fssConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/fssConfig.cmake ${PROJECT_BINARY_DIR}/fssConfigVersion.cmake
        DESTINATION ${FSS_CMAKE_DIR})

# fss.pc. A static install has no shared variant, so what a shared libfss
# would hide (ISA-L, the dynamic loader's library) is needed by every link: ISA-L goes to
# Requires, -ldl to Libs, and plain `pkg-config --libs fss` links. No public header includes a
# third-party one; FFTW3, libpng and nlohmann_json are listed for either kind of library.
set(FSS_PC_REQUIRES "fftw3 libpng nlohmann_json >= 3.9")
set(FSS_PC_LIBS "-L\${libdir} -lfss -pthread")
if(NOT FSS_SHARED)
  string(APPEND FSS_PC_REQUIRES " libisal")
  foreach(_fss_dl IN LISTS CMAKE_DL_LIBS)
    string(APPEND FSS_PC_LIBS " -l${_fss_dl}")
  endforeach()
endif()
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  set(FSS_PC_LIBDIR "${CMAKE_INSTALL_LIBDIR}")
else()
  set(FSS_PC_LIBDIR "\${prefix}/${CMAKE_INSTALL_LIBDIR}")
endif()
if(IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
  set(FSS_PC_INCLUDEDIR "${CMAKE_INSTALL_INCLUDEDIR}")
else()
  set(FSS_PC_INCLUDEDIR "\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}")
endif()
# The prefix is written at install time, so `cmake --install --prefix DIR`
# gives a fss.pc that points into DIR.
set(FSS_PC_PREFIX "@FSS_PC_PREFIX@")  # kept for the install step
configure_file(cmake/fss.pc.in ${PROJECT_BINARY_DIR}/fss.pc.in @ONLY)
install(CODE "
  set(FSS_PC_PREFIX \"\${CMAKE_INSTALL_PREFIX}\")
  configure_file(\"${PROJECT_BINARY_DIR}/fss.pc.in\" \"${PROJECT_BINARY_DIR}/fss.pc\" @ONLY)
")
install(FILES ${PROJECT_BINARY_DIR}/fss.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# The install test (scripts/test-install.sh): installs this build and a
# shared one into temporary prefixes and builds and runs a find_package and a
# pkg-config consumer against each. Not under the sanitizers or the fuzzer:
# their flags are not part of the installed package.
if(FSS_BUILD_TESTS AND NOT FSS_SANITIZE AND NOT FSS_FUZZ)
  add_test(NAME install COMMAND ${PROJECT_SOURCE_DIR}/scripts/test-install.sh
                                --reuse-build ${PROJECT_BINARY_DIR})
  set_tests_properties(install PROPERTIES LABELS install TIMEOUT 1500 PROCESSORS 2)
endif()
