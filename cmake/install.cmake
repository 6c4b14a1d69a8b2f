# What `cmake --install` puts under the prefix: the libraries and their headers, a CMake package
# (find_package(crowdbake CONFIG): crowd::formats, crowd::runtime_core, crowd::runtime) and
# pkg-config files (crowdbake-formats, crowdbake-runtime); with the full build also the tools,
# the image module they load (<libdir>/crowdbake) and the shaders (embedded in the renderer;
# installed to read). Nothing installed names the build tree.
include(CMakePackageConfigHelpers)
set(CROWD_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/crowdbake)

install(DIRECTORY ${PROJECT_SOURCE_DIR}/formats/include/ ${CMAKE_BINARY_DIR}/generated/include/
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
set(crowd_targets crowd_formats)
set(CROWD_PC_FILES crowdbake-formats)
if(NOT CROWD_FORMATS_ONLY)
  list(APPEND crowd_targets crowd_support crowd_runtime crowd_gl)
  list(APPEND CROWD_PC_FILES crowdbake-runtime)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/support/include/ ${PROJECT_SOURCE_DIR}/runtime/include/
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(TARGETS crowdbake crowdplay RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(TARGETS crowd_oiio LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/crowdbake)
  install(FILES ${CROWD_SHADER_FILES} DESTINATION ${CMAKE_INSTALL_DATADIR}/crowdbake/shaders)
endif()
install(TARGETS ${crowd_targets} EXPORT crowdbakeTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT crowdbakeTargets NAMESPACE crowd:: DESTINATION ${CROWD_CMAKE_DIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/crowdbakeConfig.cmake.in
  ${CMAKE_BINARY_DIR}/crowdbakeConfig.cmake INSTALL_DESTINATION ${CROWD_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/crowdbakeConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/crowdbakeConfig.cmake ${CMAKE_BINARY_DIR}/crowdbakeConfigVersion.cmake
  DESTINATION ${CROWD_CMAKE_DIR})
# Relocatable: the prefix is found from the .pc file's own folder.
file(RELATIVE_PATH CROWD_PC_TO_PREFIX /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
foreach(pc ${CROWD_PC_FILES})
  configure_file(${PROJECT_SOURCE_DIR}/cmake/${pc}.pc.in ${CMAKE_BINARY_DIR}/${pc}.pc @ONLY)
  install(FILES ${CMAKE_BINARY_DIR}/${pc}.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endforeach()
