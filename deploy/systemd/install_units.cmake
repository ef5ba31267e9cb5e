# Installs the systemd units with ExecStart and Documentation naming the prefix installed to.
# Runs inside `cmake --install` (install(SCRIPT) in deploy/CMakeLists.txt, which sets the
# TESSERA_UNIT_* variables), where CMAKE_INSTALL_PREFIX is the prefix of this install.
function(tessera_unit_path out dir)
  if(IS_ABSOLUTE "${dir}")
    set(${out} "${dir}" PARENT_SCOPE)
  else()
    set(${out} "${CMAKE_INSTALL_PREFIX}/${dir}" PARENT_SCOPE)
  endif()
endfunction()

tessera_unit_path(bindir "${TESSERA_UNIT_BINDIR}")
tessera_unit_path(TESSERA_DOCDIR "${TESSERA_UNIT_DOCDIR}")
tessera_unit_path(unitdir "${TESSERA_UNIT_DIR}")
set(TESSERA_WORKER_PATH "${bindir}/tessera-worker")
foreach(unit tessera-worker.service tessera-worker@.service)
  configure_file("${TESSERA_UNIT_SOURCE_DIR}/${unit}.in" "${TESSERA_UNIT_BINARY_DIR}/${unit}" @ONLY)
  file(INSTALL "${TESSERA_UNIT_BINARY_DIR}/${unit}" DESTINATION "${unitdir}"
    FILE_PERMISSIONS OWNER_READ OWNER_WRITE GROUP_READ WORLD_READ)
endforeach()
