# tessera_embed_program(SYMBOL name SOURCE file.cu TARGET app [INCLUDES dir ...] [FAST_MATH])
# The OptiX 7 SDK's embed_ptx / cuda_compile_and_embed for Tessera: compiles an OptiX 7 program
# (.cu) at build time, as nvcc compiles it to PTX, and adds to `app` a source that defines
#   extern "C" const char name[];
# holding the compiled module as NUL-free text, which the host passes to optixModuleCreate as
# it would the PTX (`std::string ptx = name; optixModuleCreate(..., ptx.c_str(), ptx.size(), ...)`).
# Compile errors then stop the build, not the application, and nothing is compiled at run time.
# The module is compiled against TESSERA_OPTIX7_PROGRAM_INCLUDE_DIRS (OptiX 7's optix.h) with
# __CUDACC__ defined, plus INCLUDES (the application's own headers, e.g. its LaunchParams.h).
# The text is "TESSERA-MODULE-HEX:" followed by the module's bytes in hexadecimal (docs/optix7.md,
# "Embedded programs"). FAST_MATH compiles it as tessera_add_optix7_program_module's FAST_MATH does
# (docs/fast_math.md).
set(_TESSERA_EMBED_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/TesseraEmbedBytes.cmake)

function(tessera_embed_program)
  cmake_parse_arguments(A "FAST_MATH" "SYMBOL;SOURCE;TARGET" "INCLUDES" ${ARGN})
  if(NOT A_SYMBOL OR NOT A_SOURCE OR NOT A_TARGET)
    message(FATAL_ERROR "tessera_embed_program needs SYMBOL, SOURCE and TARGET")
  endif()
  if(A_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "tessera_embed_program(${A_SYMBOL}): unknown arguments ${A_UNPARSED_ARGUMENTS}")
  endif()
  get_filename_component(_source ${A_SOURCE} ABSOLUTE)
  set(_module ${A_SYMBOL}_tessera_module)
  add_library(${_module} MODULE ${_source})
  set_source_files_properties(${_source} TARGET_DIRECTORY ${_module} PROPERTIES LANGUAGE CXX)
  target_compile_features(${_module} PRIVATE cxx_std_17)
  target_compile_options(${_module} PRIVATE -x c++ -O2 ${TESSERA_PROGRAM_MODULE_OPTIONS})
  target_compile_definitions(${_module} PRIVATE __CUDACC__)
  if(A_FAST_MATH)
    target_compile_options(${_module} PRIVATE -ffast-math -fno-finite-math-only)
    target_compile_definitions(${_module} PRIVATE TESSERA_FAST_MATH=1)
  endif()
  target_include_directories(${_module} PRIVATE ${TESSERA_OPTIX7_PROGRAM_INCLUDE_DIRS} ${A_INCLUDES})
  set_target_properties(${_module} PROPERTIES PREFIX "" SUFFIX ".so"
    LIBRARY_OUTPUT_DIRECTORY "$<1:${CMAKE_CURRENT_BINARY_DIR}/${_module}>")
  set(_embedded ${CMAKE_CURRENT_BINARY_DIR}/${A_SYMBOL}_embedded.cc)
  add_custom_command(OUTPUT ${_embedded}
    COMMAND ${CMAKE_COMMAND} -DINPUT=$<TARGET_FILE:${_module}> -DOUTPUT=${_embedded}
      -DSYMBOL=${A_SYMBOL} -P ${_TESSERA_EMBED_SCRIPT}
    DEPENDS ${_module} ${_TESSERA_EMBED_SCRIPT}
    COMMENT "Embedding OptiX 7 program ${A_SOURCE} as ${A_SYMBOL}" VERBATIM)
  target_sources(${A_TARGET} PRIVATE ${_embedded})
endfunction()
