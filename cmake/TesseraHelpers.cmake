# Shared build settings for project targets.

# Program modules compile against the program-side headers only: their API generation's include
# root, then the headers both roots share (the texture sampler, api/include_common), which an
# install copies into each root.
set(TESSERA_COMMON_INCLUDE_DIR ${CMAKE_CURRENT_LIST_DIR}/../api/include_common CACHE INTERNAL "")
set(TESSERA_PROGRAM_INCLUDE_DIRS ${CMAKE_CURRENT_LIST_DIR}/../api/include
  ${TESSERA_COMMON_INCLUDE_DIR} CACHE INTERNAL "")
set(TESSERA_OPTIX7_PROGRAM_INCLUDE_DIRS ${CMAKE_CURRENT_LIST_DIR}/../api/include7
  ${TESSERA_COMMON_INCLUDE_DIR} CACHE INTERNAL "")
include(${CMAKE_CURRENT_LIST_DIR}/TesseraEmbedProgram.cmake)

add_library(tessera_warnings INTERFACE)
target_compile_options(tessera_warnings INTERFACE
  $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Werror -Wno-unused-parameter>
  $<$<COMPILE_LANGUAGE:C>:-Wall -Wextra -Werror>)

# tessera_cc_library(NAME name SRCS ... [HDRS ...] [DEPS ...] [PUBLIC_INCLUDES ...] [SHARED])
# Creates tessera_<name> with alias tessera::<name>.
function(tessera_cc_library)
  cmake_parse_arguments(A "SHARED" "NAME" "SRCS;DEPS;PUBLIC_INCLUDES" ${ARGN})
  if(A_SHARED)
    add_library(tessera_${A_NAME} SHARED ${A_SRCS})
  else()
    add_library(tessera_${A_NAME} STATIC ${A_SRCS})
  endif()
  add_library(tessera::${A_NAME} ALIAS tessera_${A_NAME})
  target_link_libraries(tessera_${A_NAME} PUBLIC ${A_DEPS} PRIVATE tessera_warnings)
  if(A_PUBLIC_INCLUDES)
    target_include_directories(tessera_${A_NAME} PUBLIC ${A_PUBLIC_INCLUDES})
  endif()
endfunction()

# tessera_cc_test(NAME name SRCS ... [DEPS ...])
function(tessera_cc_test)
  cmake_parse_arguments(A "" "NAME" "SRCS;DEPS" ${ARGN})
  add_executable(${A_NAME} ${A_SRCS})
  target_link_libraries(${A_NAME} PRIVATE ${A_DEPS} GTest::gtest GTest::gtest_main tessera_warnings)
  # Tests name their devices: without TESSERA_DEVICES a context would spawn one worker process
  # per core (the default for applications), which tests of other things need not pay for.
  gtest_discover_tests(${A_NAME} DISCOVERY_TIMEOUT 60
    PROPERTIES TIMEOUT 300 ENVIRONMENT "TESSERA_DEVICES=inproc")
endfunction()

# Program modules of Tessera's own tree warn as errors, like the rest of its code.
set(TESSERA_PROGRAM_MODULE_OPTIONS -Wall -Wextra -Werror -Wno-unused-parameter
  -Wno-sign-compare)  # rtBuffer::size() is size_t, as in OptiX; SDK loops use int
set(TESSERA_OPTIX7_PROGRAM_MODULE_OPTIONS -Wall -Wextra -Werror)
include(${CMAKE_CURRENT_LIST_DIR}/TesseraProgramModule.cmake)
