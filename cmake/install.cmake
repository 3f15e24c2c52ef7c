# `cmake --install build --prefix P`: the libraries, their headers and a CMake package
# configuration (find_package(billiards) gives billiards::geometry, billiards::dynamics,
# billiards::analysis), the billiard program, and under share/billiards the bundled shapes,
# scenes and plotting scripts that it finds there.  `cpack -G DEB` packs the same files.
include(CMakePackageConfigHelpers)

set(BILLIARDS_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/billiards)
foreach(lib geometry dynamics analysis)
  set_target_properties(billiards_${lib} PROPERTIES EXPORT_NAME ${lib})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${lib}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()
install(FILES ${PROJECT_BINARY_DIR}/generated/billiards/version.hpp DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/billiards)
install(TARGETS billiards_geometry billiards_dynamics billiards_analysis EXPORT billiardsTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT billiardsTargets NAMESPACE billiards:: DESTINATION ${BILLIARDS_CMAKE_DIR})
configure_package_config_file(cmake/billiardsConfig.cmake.in ${PROJECT_BINARY_DIR}/billiardsConfig.cmake
  INSTALL_DESTINATION ${BILLIARDS_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/billiardsConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/billiardsConfig.cmake ${PROJECT_BINARY_DIR}/billiardsConfigVersion.cmake
  DESTINATION ${BILLIARDS_CMAKE_DIR})

install(TARGETS billiard RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY shapes scenes DESTINATION ${CMAKE_INSTALL_DATADIR}/billiards)
install(DIRECTORY scripts/ DESTINATION ${CMAKE_INSTALL_DATADIR}/billiards/scripts FILES_MATCHING PATTERN "*.py")
# billiardkit's drawing of movies, which scripts/plot_animate.py loads from beside itself.
install(FILES python/billiardkit/movie.py DESTINATION ${CMAKE_INSTALL_DATADIR}/billiards/scripts)

# `cpack -G DEB` (run in the build folder): a Debian package of the files above, under /usr.
# dpkg-shlibdeps finds the run-time libraries billiard needs; its plotting scripts need
# matplotlib; `billiard animate` needs ffmpeg (and Pillow for GIF), recommended; find_package(billiards)
# needs the -dev packages the libraries were built with.
set(CPACK_PACKAGE_NAME billiards)
set(CPACK_PACKAGE_VENDOR "billiards")
set(CPACK_PACKAGE_CONTACT "billiards maintainers <billiards@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "exact geometry, driven ensembles and energy diffusion of billiards")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3, python3-matplotlib, python3-numpy")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "ffmpeg, python3-pil, cmake, g++, libcgal-dev, libeigen3-dev, libgmp-dev, libmpfr-dev, libyaml-cpp-dev, libmuparser-dev, libginac-dev, pkg-config, libfmt-dev, nlohmann-json3-dev, libboost-dev")
include(CPack)
