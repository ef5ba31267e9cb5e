# TESSERA_SANITIZE=ON (tools/sanitize.sh, docs/sanitizers.md): every target of the tree, program
# modules and the tessera-worker that tests spawn included, is built with AddressSanitizer and
# UndefinedBehaviorSanitizer (`undefined` includes vptr with g++). Findings do not recover, so
# they fail the test that hit them. A test that cannot run under a sanitizer says why: a gtest
# case calls GTEST_SKIP() << "reason" when TESSERA_SANITIZER_BUILD is defined, a whole ctest test
# is named in tessera_sanitizer_skip().

# tessera_sanitizer_skip(TESTS name... REASON "why"): under TESSERA_SANITIZE, the ctest tests
# named (add_test ones, not gtest cases) are DISABLED, and each with its reason is listed in
# <build>/sanitizer-disabled-tests.txt, which tools/sanitize.sh prints. Otherwise nothing.
function(tessera_sanitizer_skip)
  cmake_parse_arguments(A "" "REASON" "TESTS" ${ARGN})
  if(NOT TESSERA_SANITIZE)
    return()
  endif()
  if(NOT A_REASON OR NOT A_TESTS)
    message(FATAL_ERROR "tessera_sanitizer_skip needs TESTS and a REASON")
  endif()
  foreach(test IN LISTS A_TESTS)
    set_tests_properties(${test} PROPERTIES DISABLED TRUE LABELS sanitizer-skip)
    file(APPEND ${CMAKE_BINARY_DIR}/sanitizer-disabled-tests.txt "${test}\t${A_REASON}\n")
  endforeach()
endfunction()

if(NOT TESSERA_SANITIZE)
  return()
endif()
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "TESSERA_SANITIZE needs g++ or clang++ (${CMAKE_CXX_COMPILER_ID} found)")
endif()
set(TESSERA_SANITIZE_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=all
  -fno-omit-frame-pointer)
add_compile_options(${TESSERA_SANITIZE_FLAGS})
add_link_options(-fsanitize=address,undefined)
# Tests read it to skip, with the reason, what a sanitizer cannot run.
add_compile_definitions(TESSERA_SANITIZER_BUILD=1)
# Written afresh by each configuration (tessera_sanitizer_skip appends).
file(WRITE ${CMAKE_BINARY_DIR}/sanitizer-disabled-tests.txt "")
message(STATUS "Tessera: built with ${TESSERA_SANITIZE_FLAGS}")
