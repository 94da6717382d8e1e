# `cmake --install build --prefix P`: the program, the Python module beside it, the static core
# with its headers under include/vrv/ and the CMake package (find_package(vrv CONFIG), vrv::vrv).
# Consumers include <vrv/vrv.h>; the headers keep the repository's own include paths
# ("lib/scene.h"), so include/vrv is on the package's include path too.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(VRV_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/vrv)
set_target_properties(vrvcore PROPERTIES EXPORT_NAME vrv)
add_library(vrv::vrv ALIAS vrvcore)

install(TARGETS vrvcore EXPORT vrvTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} ${CMAKE_INSTALL_INCLUDEDIR}/vrv)
install(DIRECTORY lib analytic DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/vrv
  FILES_MATCHING PATTERN "*.h")
install(FILES lib/vrv.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/vrv)
install(TARGETS vrv RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The image module (lib/io/image_module.h), where the installed loader looks for it.
install(TARGETS vrv_image LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/vrv)
if(TARGET vrv_python)
  install(TARGETS vrv_python LIBRARY DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

install(EXPORT vrvTargets NAMESPACE vrv:: DESTINATION ${VRV_CMAKE_DIR})
configure_package_config_file(cmake/vrvConfig.cmake.in ${PROJECT_BINARY_DIR}/vrvConfig.cmake
  INSTALL_DESTINATION ${VRV_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/vrvConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/vrvConfig.cmake ${PROJECT_BINARY_DIR}/vrvConfigVersion.cmake
  DESTINATION ${VRV_CMAKE_DIR})
