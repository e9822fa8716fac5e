# Helpers shared by every folder: warning flags and one-line test registration.

# pwsim_set_warnings(<target>): the project's warning set; errors when PWSIM_WERROR is ON.
function(pwsim_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                         -Wno-sign-conversion -Wnon-virtual-dtor -Wold-style-cast)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    # GCC 12 reports false -Wrestrict positives inside std::string concatenation (GCC bug 105329).
    target_compile_options(${target} PRIVATE -Wno-restrict)
  endif()
  if(PWSIM_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# pwsim_add_library(<name> SOURCES ... PUBLIC_LIBS ... PRIVATE_LIBS ...)
function(pwsim_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_LIBS;PRIVATE_LIBS" ${ARGN})
  add_library(${name} STATIC ${ARG_SOURCES})
  target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_compile_features(${name} PUBLIC cxx_std_20)
  target_link_libraries(${name} PUBLIC ${ARG_PUBLIC_LIBS} PRIVATE ${ARG_PRIVATE_LIBS})
  pwsim_set_warnings(${name})
endfunction()

# pwsim_add_test(<name> SOURCES ... LIBS ... [LABELS ...])
# Builds one GoogleTest executable and registers each TEST with CTest.
function(pwsim_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main)
  # the tests' shared helpers (tests/run_command.h, tests/hardware/child_process.h) by full path
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR})
  target_compile_definitions(${name} PRIVATE
      PWSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}" PWSIM_BINARY_DIR="${PROJECT_BINARY_DIR}")
  pwsim_set_warnings(${name})
  # Tests labelled slow start first under `ctest -j` (COST) where no timing of an earlier run
  # exists (a clean clone): a long test started last would run alone at the end.
  set(cost 1)
  if("slow" IN_LIST ARG_LABELS)
    set(cost 100)
  endif()
  gtest_discover_tests(${name} WORKING_DIRECTORY ${PROJECT_BINARY_DIR} DISCOVERY_TIMEOUT 60
                       PROPERTIES LABELS "${ARG_LABELS}" COST ${cost})
endfunction()

# The dependency direction between pwsim's libraries, enforced at configure time:
#   pwsim_allow_dependencies(<lib> <allowed pwsim libs>...)  records what <lib> may link;
#   pwsim_check_dependencies()  (end of the top-level CMakeLists.txt) fails the configuration
#   when a library links another pwsim library outside its list, or when a library declared
#   real-time (pwsim_forbid_links) links a forbidden package.
function(pwsim_allow_dependencies name)
  set_property(GLOBAL APPEND PROPERTY PWSIM_LAYERED_LIBRARIES ${name})
  set_property(TARGET ${name} PROPERTY PWSIM_ALLOWED_DEPENDENCIES ${ARGN})
endfunction()

function(pwsim_forbid_links name)
  set_property(TARGET ${name} PROPERTY PWSIM_FORBIDDEN_LINKS ${ARGN})
endfunction()

function(pwsim_check_dependencies)
  get_property(layered GLOBAL PROPERTY PWSIM_LAYERED_LIBRARIES)
  foreach(lib IN LISTS layered)
    get_target_property(allowed ${lib} PWSIM_ALLOWED_DEPENDENCIES)
    if(NOT allowed)
      set(allowed "")
    endif()
    get_target_property(links ${lib} LINK_LIBRARIES)
    get_target_property(forbidden ${lib} PWSIM_FORBIDDEN_LINKS)
    foreach(dep IN LISTS links)
      if(dep IN_LIST layered AND NOT dep STREQUAL lib AND NOT dep IN_LIST allowed)
        message(FATAL_ERROR "pwsim layering: ${lib} links ${dep}, but may link only: ${allowed}"
                            " (see the README's layout section)")
      endif()
      if(forbidden AND dep IN_LIST forbidden)
        message(FATAL_ERROR "pwsim layering: ${lib} is real-time core and must not link ${dep}")
      endif()
    endforeach()
  endforeach()
endfunction()
