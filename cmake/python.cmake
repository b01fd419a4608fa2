# The Python package `fss` (python/, pybind11), its install rule, its pytest
# suite (CTest label python) and the test of its pip install (label install).
# pip builds it through setup.py, which configures this project with
# FSS_BUILD_PYTHON=ON and builds the target fss_python alone.
#
#   FSS_BUILD_PYTHON        build the module; default ON when pybind11 and the
#                           Python headers are found (Debian: pybind11-dev,
#                           python3-dev), OFF under the sanitizers and the
#                           fuzzer (an instrumented module cannot be loaded
#                           by an uninstrumented interpreter).
#   Python3_EXECUTABLE      the interpreter the module is built for. Unset, it
#                           is the first python3 on PATH that imports numpy,
#                           else the first python3 on PATH.
#   FSS_PYTHON_INSTALL_DIR  where `cmake --install` puts the package (into
#                           FSS_PYTHON_INSTALL_DIR/fss), relative
#                           to the prefix (or absolute): the interpreter's
#                           posix_prefix platlib, lib/python3.X/site-packages.
#                           Debian's own interpreter searches
#                           /usr/local/lib/python3/dist-packages and
#                           /usr/lib/python3/dist-packages instead: pass
#                           -DFSS_PYTHON_INSTALL_DIR=lib/python3/dist-packages
#                           to install there, or set PYTHONPATH.

if(NOT DEFINED Python3_EXECUTABLE AND NOT FSS_SANITIZE AND NOT FSS_FUZZ)
  # pyenv shims and the like may come first on PATH without numpy: prefer an
  # interpreter that has it.
  string(REPLACE ":" ";" _fss_path "$ENV{PATH}")
  foreach(_fss_dir IN LISTS _fss_path)
    if(EXISTS "${_fss_dir}/python3")
      execute_process(COMMAND "${_fss_dir}/python3" -c "import numpy"
                      RESULT_VARIABLE _fss_numpy_status OUTPUT_QUIET ERROR_QUIET)
      if(_fss_numpy_status EQUAL 0)
        set(Python3_EXECUTABLE "${_fss_dir}/python3" CACHE FILEPATH
            "The Python interpreter the module is built for")
        break()
      endif()
    endif()
  endforeach()
endif()

set(_fss_python_default OFF)
if(NOT FSS_SANITIZE AND NOT FSS_FUZZ)
  find_package(Python3 COMPONENTS Interpreter Development.Module QUIET)
  if(Python3_FOUND)
    find_package(pybind11 CONFIG QUIET)
  endif()
  if(Python3_FOUND AND pybind11_FOUND)
    set(_fss_python_default ON)
  endif()
endif()
option(FSS_BUILD_PYTHON "Build the Python module fss (needs pybind11 and the Python headers)"
       ${_fss_python_default})
if(NOT FSS_BUILD_PYTHON)
  message(STATUS "Python module: not built (FSS_BUILD_PYTHON is OFF; needs pybind11-dev and python3-dev)")
  return()
endif()
if(NOT Python3_FOUND OR NOT pybind11_FOUND)
  message(FATAL_ERROR "FSS_BUILD_PYTHON is ON but pybind11 or the Python headers were not found "
                      "(Debian: pybind11-dev python3-dev)")
endif()
message(STATUS "Python module: built for ${Python3_EXECUTABLE} (${Python3_VERSION})")

# A static libfss goes into a shared module.
set_target_properties(fss PROPERTIES POSITION_INDEPENDENT_CODE ON)
# NO_EXTRAS: no link-time optimization (it only slows the link down here).
pybind11_add_module(fss_python MODULE NO_EXTRAS python/module.cpp python/convert.cpp
                    python/simulate_bindings.cpp python/code_bindings.cpp
                    python/image_bindings.cpp python/arguments.cpp
                    python/design_arguments.cpp python/campaign_bindings.cpp
                    python/campaign_columns.cpp)
# The package fss: the compiled fss._fss and the files of python/fss/, in
# build/python/fss as in the install.
set_target_properties(fss_python PROPERTIES OUTPUT_NAME _fss LIBRARY_OUTPUT_DIRECTORY
                                            ${PROJECT_BINARY_DIR}/python/fss)
file(GLOB _fss_package_files CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/python/fss/*.py
     ${PROJECT_SOURCE_DIR}/python/fss/*.pyi ${PROJECT_SOURCE_DIR}/python/fss/py.typed)
# Each file is copied when it changes (a rule with its output), whether or
# not the module is relinked.
set(_fss_package_copies)
foreach(_fss_file IN LISTS _fss_package_files)
  get_filename_component(_fss_name "${_fss_file}" NAME)
  set(_fss_copy "${PROJECT_BINARY_DIR}/python/fss/${_fss_name}")
  add_custom_command(OUTPUT "${_fss_copy}"
                     COMMAND ${CMAKE_COMMAND} -E copy "${_fss_file}" "${_fss_copy}"
                     DEPENDS "${_fss_file}" VERBATIM)
  list(APPEND _fss_package_copies "${_fss_copy}")
endforeach()
add_custom_target(fss_python_files ALL DEPENDS ${_fss_package_copies})
add_dependencies(fss_python fss_python_files)
target_link_libraries(fss_python PRIVATE fss_internal)
target_compile_options(fss_python PRIVATE -Wall -Wextra)
target_compile_definitions(fss_python PRIVATE FSS_VERSION_FULL="${FSS_VERSION_FULL}")

if(NOT DEFINED FSS_PYTHON_INSTALL_DIR)
  execute_process(
    COMMAND "${Python3_EXECUTABLE}" -c
            "import sysconfig; print(sysconfig.get_path('platlib', 'posix_prefix', vars={'platbase': '', 'base': ''}).lstrip('/'))"
    OUTPUT_VARIABLE _fss_platlib OUTPUT_STRIP_TRAILING_WHITESPACE)
  set(FSS_PYTHON_INSTALL_DIR "${_fss_platlib}" CACHE STRING
      "Where the Python module is installed, relative to the prefix")
endif()
# A module linked to a shared libfss finds it in the prefix wherever the
# prefix is moved: RUNPATH $ORIGIN/<module dir to libdir>.
include(GNUInstallDirs)
get_target_property(_fss_library_type fss TYPE)
if(_fss_library_type STREQUAL "SHARED_LIBRARY")
  get_filename_component(_fss_python_dir "${FSS_PYTHON_INSTALL_DIR}/fss" ABSOLUTE
                         BASE_DIR "${CMAKE_INSTALL_PREFIX}")
  file(RELATIVE_PATH _fss_python_to_lib "${_fss_python_dir}" "${CMAKE_INSTALL_FULL_LIBDIR}")
  set_target_properties(fss_python PROPERTIES INSTALL_RPATH "$ORIGIN/${_fss_python_to_lib}")
endif()
install(TARGETS fss_python LIBRARY DESTINATION ${FSS_PYTHON_INSTALL_DIR}/fss)
install(FILES ${_fss_package_files} DESTINATION ${FSS_PYTHON_INSTALL_DIR}/fss)

if(FSS_BUILD_TESTS)
  add_test(NAME python
           COMMAND "${Python3_EXECUTABLE}" -m pytest -q -p no:cacheprovider
                   ${PROJECT_SOURCE_DIR}/python/tests)
  set_tests_properties(python PROPERTIES
    LABELS python TIMEOUT 600
    ENVIRONMENT "PYTHONPATH=${PROJECT_BINARY_DIR}/python;FSSIM=$<TARGET_FILE:fssim>;FSS_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
  # pip install of a fresh clone into a venv, offline, and its wheel, compared
  # with this build's module (scripts/test-python-install.sh); skipped (77)
  # outside a git checkout.
  add_test(NAME python_install COMMAND ${PROJECT_SOURCE_DIR}/scripts/test-python-install.sh
                                       --build ${PROJECT_BINARY_DIR})
  set_tests_properties(python_install PROPERTIES LABELS install TIMEOUT 900 SKIP_RETURN_CODE 77)
endif()
