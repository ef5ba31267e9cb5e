# `cmake --install <build> [--prefix P]`: what an application that embeds Tessera needs, in the
# GNUInstallDirs layout (docs/install.md):
#   <libdir>/libtessera.so.<version>       the host API (and its SONAME link, libtessera.so)
#   <libdir>/libtessera_image.so.<version> image files into buffers (OpenImageIO), Tessera::image
#   <bindir>/tessera-worker                 the worker libtessera spawns for local:N devices, and
#                                           that other machines run
#   <includedir>/tessera/                   optix.h, optixu/, tessera/: the include root of host
#                                           code and of program modules (kept out of
#                                           <includedir> itself, where a real OptiX SDK's
#                                           optix.h may be)
#   <includedir>/tessera/optix7/            the OptiX 7 include root (optix.h of OptiX 7.7,
#                                           cuda_runtime.h, ...), Tessera::optix7; declarations
#                                           only so far (docs/optix7.md)
#   <libdir>/cmake/Tessera/                 find_package(Tessera): Tessera::tessera and
#                                           tessera_add_program_module()
# libtessera finds the worker and the headers relative to itself (scheduler/src/install_paths.cc),
# so a prefix can be moved as a whole.
include(CMakePackageConfigHelpers)

set(TESSERA_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/Tessera)

set_target_properties(tessera PROPERTIES VERSION ${PROJECT_VERSION} SOVERSION
  ${PROJECT_VERSION_MAJOR})
target_include_directories(tessera PUBLIC
  $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/tessera>)
# optix.h's program-side half (tessera/device.h) is C++17.
target_compile_features(tessera INTERFACE cxx_std_17)

set_target_properties(tessera_image PROPERTIES EXPORT_NAME image VERSION ${PROJECT_VERSION}
  SOVERSION ${PROJECT_VERSION_MAJOR})
install(TARGETS tessera tessera_image EXPORT TesseraTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS tessera-worker RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/api/include/
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tessera)
target_include_directories(tessera_optix7_headers INTERFACE
  $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/tessera/optix7>)
install(TARGETS tessera_optix7_headers EXPORT TesseraTargets)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/api/include7/
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tessera/optix7)
# The headers both roots share (the texture sampler, api/include_common) go into each, so that an
# installed root is one -I directory, as an SDK's is.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/api/include_common/
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tessera)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/api/include_common/
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tessera/optix7)
install(EXPORT TesseraTargets NAMESPACE Tessera:: DESTINATION ${TESSERA_INSTALL_CMAKEDIR})

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/TesseraConfig.cmake.in
  ${CMAKE_BINARY_DIR}/TesseraConfig.cmake
  INSTALL_DESTINATION ${TESSERA_INSTALL_CMAKEDIR}
  PATH_VARS CMAKE_INSTALL_INCLUDEDIR)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/TesseraConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/TesseraConfig.cmake ${CMAKE_BINARY_DIR}/TesseraConfigVersion.cmake
  ${CMAKE_CURRENT_LIST_DIR}/TesseraProgramModule.cmake
  ${CMAKE_CURRENT_LIST_DIR}/TesseraEmbedProgram.cmake ${CMAKE_CURRENT_LIST_DIR}/TesseraEmbedBytes.cmake
  DESTINATION ${TESSERA_INSTALL_CMAKEDIR})
