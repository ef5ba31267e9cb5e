# tessera_add_program_module(TARGET name SOURCES file.cu ... [INCLUDES dir ...]
#                            [OUTPUT_DIRECTORY dir] [FAST_MATH])
# Builds an OptiX-style program module (the PTX analogue): a shared library compiled as C++ from
# .cu sources against the program-side headers in TESSERA_PROGRAM_INCLUDE_DIRS, which
# rtProgramCreateFromPTXFile(context, "<dir>/name.so", "function", &program) loads. It lands in
# ${CMAKE_BINARY_DIR}/modules/<name>.so (a stable path for hosts) unless OUTPUT_DIRECTORY says
# otherwise. One module per .cu, as OptiX compiles one PTX file per .cu (docs/install.md).
# TESSERA_PROGRAM_MODULE_OPTIONS adds compile options (Tessera's own tree: warnings as errors).
# The compile is the README's g++ line: __CUDACC__ defined, as nvcc defines it (optix.h then gives
# the program-side API, and a program's own `#ifdef __CUDACC__` code is compiled), and each
# include directory's optixu/ searched as well (OptiX SDK projects put include/optixu on the
# path: `#include <optixu_math_namespace.h>`).
# FAST_MATH is nvcc's --use_fast_math analogue (docs/fast_math.md): -ffast-math with isnan/isinf
# kept working (-fno-finite-math-only), and TESSERA_FAST_MATH defined so that the module says so
# to the engine, which flushes denormals to zero on the threads of launches that run it.
# Used in Tessera's tree (TesseraHelpers.cmake) and installed with its CMake package.

function(tessera_add_program_module)
  cmake_parse_arguments(A "FAST_MATH" "TARGET;OUTPUT_DIRECTORY" "SOURCES;INCLUDES" ${ARGN})
  if(NOT A_TARGET OR NOT A_SOURCES)
    message(FATAL_ERROR "tessera_add_program_module needs TARGET and SOURCES")
  endif()
  if(A_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "tessera_add_program_module(${A_TARGET}): unknown arguments ${A_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT A_OUTPUT_DIRECTORY)
    set(A_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/modules)
  endif()
  get_property(_tessera_languages GLOBAL PROPERTY ENABLED_LANGUAGES)
  if(NOT "CXX" IN_LIST _tessera_languages)
    message(FATAL_ERROR "tessera_add_program_module(${A_TARGET}): program modules are compiled "
      "as C++, which this project has not enabled: add CXX to its project(... LANGUAGES ...)")
  endif()
  add_library(${A_TARGET} MODULE ${A_SOURCES})
  set_source_files_properties(${A_SOURCES} PROPERTIES LANGUAGE CXX)
  target_compile_features(${A_TARGET} PRIVATE cxx_std_17)
  target_compile_options(${A_TARGET} PRIVATE -x c++ -O2 ${TESSERA_PROGRAM_MODULE_OPTIONS})
  target_compile_definitions(${A_TARGET} PRIVATE __CUDACC__)
  if(A_FAST_MATH)
    target_compile_options(${A_TARGET} PRIVATE -ffast-math -fno-finite-math-only)
    target_compile_definitions(${A_TARGET} PRIVATE TESSERA_FAST_MATH=1)
  endif()
  set(_tessera_optixu_dirs)
  foreach(_tessera_dir IN LISTS TESSERA_PROGRAM_INCLUDE_DIRS)
    list(APPEND _tessera_optixu_dirs ${_tessera_dir}/optixu)
  endforeach()
  target_include_directories(${A_TARGET} PRIVATE ${TESSERA_PROGRAM_INCLUDE_DIRS}
    ${_tessera_optixu_dirs} ${A_INCLUDES})
  # A generator expression keeps multi-config generators (Ninja Multi-Config) from adding a
  # per-configuration subdirectory: the path stays the one hosts are told.
  set_target_properties(${A_TARGET} PROPERTIES PREFIX "" SUFFIX ".so"
    LIBRARY_OUTPUT_DIRECTORY "$<1:${A_OUTPUT_DIRECTORY}>")

  # The same module built with initial-exec thread-local variables, which the module carries in a
  # section that is not loaded with it: devices whose processes reserve static TLS load that build
  # instead (docs/programs.md, "Thread-local storage"). It takes the module's own compile and link
  # settings, those added to the target after this call included: the two builds must differ in
  # nothing else. Without objcopy to embed it, none is made.
  if(NOT CMAKE_OBJCOPY)
    return()
  endif()
  set(_tessera_ie ${A_TARGET}_initial_exec)
  add_library(${_tessera_ie} MODULE ${A_SOURCES})
  foreach(_tessera_property IN ITEMS COMPILE_OPTIONS INCLUDE_DIRECTORIES LINK_OPTIONS
                                     LINK_LIBRARIES COMPILE_FEATURES)
    set_property(TARGET ${_tessera_ie} PROPERTY ${_tessera_property}
      "$<TARGET_PROPERTY:${A_TARGET},${_tessera_property}>")
  endforeach()
  set_property(TARGET ${_tessera_ie} PROPERTY COMPILE_DEFINITIONS
    "$<TARGET_PROPERTY:${A_TARGET},COMPILE_DEFINITIONS>" TESSERA_TLS_INITIAL_EXEC=1)
  set_target_properties(${_tessera_ie} PROPERTIES PREFIX "" SUFFIX ".so"
    LIBRARY_OUTPUT_DIRECTORY "$<1:${CMAKE_CURRENT_BINARY_DIR}/initial_exec>")
  add_dependencies(${A_TARGET} ${_tessera_ie})
  add_custom_command(TARGET ${A_TARGET} POST_BUILD
    COMMAND ${CMAKE_OBJCOPY} --add-section
      .tessera_initial_exec=$<TARGET_FILE:${_tessera_ie}>
      --set-section-flags .tessera_initial_exec=readonly $<TARGET_FILE:${A_TARGET}>
    VERBATIM)
endfunction()

# tessera_add_optix7_program_module(TARGET name SOURCES file.cu ... [INCLUDES dir ...]
#                                   [OUTPUT_DIRECTORY dir] [FAST_MATH])
# The same for OptiX 7 programs: the .cu file compiled as C++ with __CUDACC__ defined against the
# OptiX 7 include root in TESSERA_OPTIX7_PROGRAM_INCLUDE_DIRS (optix.h then gives
# optix_device.h), the g++ line of docs/optix7.md. The engine finds its entry points
# (__raygen__*, ...) and launch parameters by symbol name. One module per .cu, as OptiX compiles
# one PTX or OptiX-IR file per .cu. FAST_MATH as above.
function(tessera_add_optix7_program_module)
  cmake_parse_arguments(A "FAST_MATH" "TARGET;OUTPUT_DIRECTORY" "SOURCES;INCLUDES" ${ARGN})
  if(NOT A_TARGET OR NOT A_SOURCES)
    message(FATAL_ERROR "tessera_add_optix7_program_module needs TARGET and SOURCES")
  endif()
  if(A_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "tessera_add_optix7_program_module(${A_TARGET}): unknown arguments ${A_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT A_OUTPUT_DIRECTORY)
    set(A_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/modules)
  endif()
  add_library(${A_TARGET} MODULE ${A_SOURCES})
  set_source_files_properties(${A_SOURCES} PROPERTIES LANGUAGE CXX)
  target_compile_features(${A_TARGET} PRIVATE cxx_std_17)
  target_compile_options(${A_TARGET} PRIVATE -x c++ -O2 ${TESSERA_OPTIX7_PROGRAM_MODULE_OPTIONS})
  target_compile_definitions(${A_TARGET} PRIVATE __CUDACC__)
  if(A_FAST_MATH)
    target_compile_options(${A_TARGET} PRIVATE -ffast-math -fno-finite-math-only)
    target_compile_definitions(${A_TARGET} PRIVATE TESSERA_FAST_MATH=1)
  endif()
  target_include_directories(${A_TARGET} PRIVATE ${TESSERA_OPTIX7_PROGRAM_INCLUDE_DIRS}
    ${A_INCLUDES})
  set_target_properties(${A_TARGET} PROPERTIES PREFIX "" SUFFIX ".so"
    LIBRARY_OUTPUT_DIRECTORY "$<1:${A_OUTPUT_DIRECTORY}>")
endfunction()
