# `cmake --install build --prefix P`: the program (bin/), the image module (lib/vrv/), the plot
# script (share/vrv/), the Python module where P's Python looks (VRV_INSTALL_PYTHONDIR), the static
# core with its headers under include/vrv/ and the CMake package (find_package(vrv CONFIG), vrv::vrv).
# Nothing refers to P itself: the program and the module find the image module and the plot script
# relative to their own files (lib/util/install_dirs.h), so the prefix can be moved.
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
install(FILES studies/engine/plot_study.py DESTINATION ${CMAKE_INSTALL_DATADIR}/vrv)

# The Python module's directory under the prefix: the interpreter's own platlib scheme made
# relative to its base, Debian's deb_system (lib/python3/dist-packages, which /usr/bin/python3
# searches for prefix /usr) when it has one, else posix_prefix (lib/python3.X/site-packages).
if(NOT DEFINED VRV_INSTALL_PYTHONDIR)
  set(dir lib/python3/dist-packages)
  if(VRV_PYTHON_EXECUTABLE)
    execute_process(COMMAND ${VRV_PYTHON_EXECUTABLE} -c "import sysconfig
s = 'deb_system' if 'deb_system' in sysconfig.get_scheme_names() else 'posix_prefix'
print(sysconfig.get_path('platlib', s, vars={'base': '/P', 'platbase': '/P'})[3:])"
      OUTPUT_VARIABLE dir OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0 OR dir STREQUAL "")
      set(dir lib/python3/dist-packages)
    endif()
  endif()
  set(VRV_INSTALL_PYTHONDIR ${dir} CACHE STRING "Where the Python module installs, relative to the prefix")
endif()
if(TARGET vrv_python)
  install(TARGETS vrv_python LIBRARY DESTINATION ${VRV_INSTALL_PYTHONDIR})
endif()
# The relative paths the installed files find each other by (lib/util/install_dirs.cpp).
set(p ${CMAKE_INSTALL_PREFIX})
file(RELATIVE_PATH bin_to_module ${p}/${CMAKE_INSTALL_BINDIR} ${p}/${CMAKE_INSTALL_LIBDIR}/vrv)
file(RELATIVE_PATH bin_to_data ${p}/${CMAKE_INSTALL_BINDIR} ${p}/${CMAKE_INSTALL_DATADIR}/vrv)
file(RELATIVE_PATH py_to_module ${p}/${VRV_INSTALL_PYTHONDIR} ${p}/${CMAKE_INSTALL_LIBDIR}/vrv)
file(RELATIVE_PATH py_to_data ${p}/${VRV_INSTALL_PYTHONDIR} ${p}/${CMAKE_INSTALL_DATADIR}/vrv)
set_source_files_properties(lib/util/install_dirs.cpp PROPERTIES COMPILE_DEFINITIONS
  "VRV_BIN_TO_IMAGE_MODULE=\"${bin_to_module}\";VRV_BIN_TO_DATA=\"${bin_to_data}\";VRV_PYTHON_TO_IMAGE_MODULE=\"${py_to_module}\";VRV_PYTHON_TO_DATA=\"${py_to_data}\"")

install(EXPORT vrvTargets NAMESPACE vrv:: DESTINATION ${VRV_CMAKE_DIR})
configure_package_config_file(cmake/vrvConfig.cmake.in ${PROJECT_BINARY_DIR}/vrvConfig.cmake
  INSTALL_DESTINATION ${VRV_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/vrvConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/vrvConfig.cmake ${PROJECT_BINARY_DIR}/vrvConfigVersion.cmake
  DESTINATION ${VRV_CMAKE_DIR})
