# Installation and the package config, so that find_package(ffdaabb) works after cmake --install.
include(CMakePackageConfigHelpers)
install(TARGETS ffdaabb EXPORT ffdaabbTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY include/ffdaabb DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY scenes DESTINATION ${CMAKE_INSTALL_DATADIR}/ffdaabb)
install(EXPORT ffdaabbTargets NAMESPACE ffdaabb:: FILE ffdaabbTargets.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ffdaabb)
configure_package_config_file(cmake/ffdaabbConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/ffdaabbConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ffdaabb)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/ffdaabbConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/ffdaabbConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/ffdaabbConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ffdaabb)
