# Installation and the package config, so that find_package(ffdaabb [COMPONENTS core content])
# works after cmake --install. Each component has its own export set: asking for the core alone
# finds the threading library alone.
include(CMakePackageConfigHelpers)
install(TARGETS ffdaabb EXPORT ffdaabbCoreTargets COMPONENT core
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS ffdaabb_content EXPORT ffdaabbContentTargets COMPONENT content
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY include/ffdaabb DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# The content's data folder: the scenes, and the model data when the setup script has fetched it.
install(DIRECTORY scenes DESTINATION ${CMAKE_INSTALL_DATADIR}/ffdaabb COMPONENT content)
install(DIRECTORY .cache/models/ DESTINATION ${CMAKE_INSTALL_DATADIR}/ffdaabb/models
        COMPONENT content OPTIONAL FILES_MATCHING PATTERN "*.ply.gz")
install(EXPORT ffdaabbCoreTargets NAMESPACE ffdaabb:: FILE ffdaabbCoreTargets.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ffdaabb COMPONENT core)
install(EXPORT ffdaabbContentTargets NAMESPACE ffdaabb:: FILE ffdaabbContentTargets.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ffdaabb COMPONENT content)
configure_package_config_file(cmake/ffdaabbConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/ffdaabbConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ffdaabb)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/ffdaabbConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/ffdaabbConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/ffdaabbConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ffdaabb)
