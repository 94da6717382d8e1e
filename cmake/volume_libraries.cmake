# The volume readers' libraries (lib/volume/): Teem for NRRD, niftilib for NIfTI, pugixml and
# libb64 for VTI, zlib for MetaImage's and VTI's compressed data.  Debian's NIfTI CMake package
# names files that its packages do not install (tools, lib/ without the multiarch folder) and
# Teem's has no imported target, so each is found as a header and a library; linked by path and
# privately, so that vrv's installed CMake package needs none of them by name.
set(VRV_VOLUME_INCLUDE_DIRS)
set(VRV_VOLUME_LIBRARIES)
function(vrv_volume_library name header library package)
  find_path(VRV_${name}_INCLUDE_DIR ${header} PATH_SUFFIXES ${ARGN})
  find_library(VRV_${name}_LIBRARY ${library})
  if(NOT VRV_${name}_INCLUDE_DIR OR NOT VRV_${name}_LIBRARY)
    message(FATAL_ERROR "vrv needs ${name} (${header}, lib${library}) for the volume readers: "
      "apt-get install ${package}")
  endif()
  set(VRV_VOLUME_INCLUDE_DIRS ${VRV_VOLUME_INCLUDE_DIRS} ${VRV_${name}_INCLUDE_DIR} PARENT_SCOPE)
  set(VRV_VOLUME_LIBRARIES ${VRV_VOLUME_LIBRARIES} ${VRV_${name}_LIBRARY} PARENT_SCOPE)
endfunction()
vrv_volume_library(TEEM teem/nrrd.h teem libteem-dev)
vrv_volume_library(NIFTI nifti2_io.h nifti2 libnifti2-dev nifti)
vrv_volume_library(ZNZ znzlib.h znz libnifti2-dev nifti)
vrv_volume_library(PUGIXML pugixml.hpp pugixml libpugixml-dev)
vrv_volume_library(B64 b64/cdecode.h b64 libb64-dev)
vrv_volume_library(ZLIB zlib.h z zlib1g-dev)
