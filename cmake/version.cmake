# FSS_VERSION_FULL: the version `fssim --version` prints. From a git checkout
# of this project it carries the revision, "0.1.0 (git fb29452)", with
# "-dirty" when tracked files differed from the commit at configure time;
# elsewhere (a release tarball, git missing) it is the plain PROJECT_VERSION.
#
# The revision is read at configure time. Moving HEAD (a commit, a checkout)
# re-runs the configure step by itself, through CMAKE_CONFIGURE_DEPENDS on
# git's HEAD and branch files; edits that are not committed do not, so the
# "-dirty" mark is the state of the last configure.
#
# fssim, the Python module and report.json (below) get the revision. The rest
# of the library keeps FSS_VERSION at the plain PROJECT_VERSION: it is written
# into report.html, whose bytes must not change with each commit, and a
# changed definition would recompile all of it.

set(FSS_VERSION_FULL "${PROJECT_VERSION}")

find_package(Git QUIET)
if(GIT_FOUND)
  execute_process(
    COMMAND "${GIT_EXECUTABLE}" rev-parse --show-toplevel
    WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}"
    OUTPUT_VARIABLE _fss_git_top
    RESULT_VARIABLE _fss_git_status
    OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  # Only a checkout of this project, not a source tree unpacked inside some
  # other repository.
  if(_fss_git_status EQUAL 0)
    get_filename_component(_fss_git_top "${_fss_git_top}" REALPATH)
    get_filename_component(_fss_source "${PROJECT_SOURCE_DIR}" REALPATH)
  endif()
  if(_fss_git_status EQUAL 0 AND _fss_git_top STREQUAL _fss_source)
    execute_process(
      COMMAND "${GIT_EXECUTABLE}" describe --always --dirty --abbrev=7
      WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}"
      OUTPUT_VARIABLE _fss_git_describe
      RESULT_VARIABLE _fss_git_status
      OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    if(_fss_git_status EQUAL 0 AND NOT _fss_git_describe STREQUAL "")
      set(FSS_VERSION_FULL "${PROJECT_VERSION} (git ${_fss_git_describe})")
    endif()
    # Re-configure when HEAD moves: HEAD itself (a checkout), the branch it
    # points to (a commit) and packed-refs (a branch packed by git gc).
    set(_fss_git_files HEAD packed-refs)
    execute_process(
      COMMAND "${GIT_EXECUTABLE}" symbolic-ref -q HEAD
      WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}"
      OUTPUT_VARIABLE _fss_git_branch
      OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    if(NOT _fss_git_branch STREQUAL "")
      list(APPEND _fss_git_files "${_fss_git_branch}")
    endif()
    foreach(_fss_git_file IN LISTS _fss_git_files)
      execute_process(
        COMMAND "${GIT_EXECUTABLE}" rev-parse --path-format=absolute --git-path "${_fss_git_file}"
        WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}"
        OUTPUT_VARIABLE _fss_git_path
        OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
      if(EXISTS "${_fss_git_path}")
        set_property(DIRECTORY "${PROJECT_SOURCE_DIR}" APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
                                                                  "${_fss_git_path}")
      endif()
    endforeach()
  endif()
endif()
message(STATUS "fssim version: ${FSS_VERSION_FULL}")

# report.json records the same version ("fssim_version"): the definition is
# given to its one source file, so that a new commit recompiles only that
# file of the library.
set_property(SOURCE ${PROJECT_SOURCE_DIR}/src/io/report_json.cpp APPEND
             PROPERTY COMPILE_DEFINITIONS "FSS_VERSION_FULL=\"${FSS_VERSION_FULL}\"")
