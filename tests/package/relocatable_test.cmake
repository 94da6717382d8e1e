# The installed program and Python module find their own files relative to themselves: installed
# into a scratch prefix that is then moved, they read and write images through the prefix's image
# module (never the build tree's) and draw plots with its plot script.  Run by CTest as
# `install.relocatable`.
# -DBIN=<vrv's build dir> -DPYTHON=<python3> -DPYDIR=<VRV_INSTALL_PYTHONDIR> -DSCENE=<scene file>
# The scratch prefix is outside the build tree (code running inside it may use the build tree's
# module, lib/io/image_module.h): a fresh directory under $TMPDIR (else /tmp), removed when the
# test passes and left for inspection when it fails.
set(tmp /tmp)
if(DEFINED ENV{TMPDIR} AND IS_DIRECTORY "$ENV{TMPDIR}")
  set(tmp $ENV{TMPDIR})
endif()
string(RANDOM LENGTH 10 tag)
set(OUT ${tmp}/vrv-relocatable-${tag})
file(MAKE_DIRECTORY ${OUT})
set(P ${OUT}/moved)
set(env ${CMAKE_COMMAND} -E env --unset=VRV_IMAGE_MODULE --unset=VRV_STUDY_PATH --unset=PYTHONPATH)

# Runs a command in OUT (no studies/ there) and checks its exit status; LAST_OUT, LAST_ERR.
function(run expected what)
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY ${OUT} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL ${expected})
    message(FATAL_ERROR "${what}: exit ${rc}, expected ${expected}\n${out}\n${err}")
  endif()
  set(LAST_OUT "${out}" PARENT_SCOPE)
  set(LAST_ERR "${err}" PARENT_SCOPE)
endfunction()

run(0 install ${CMAKE_COMMAND} --install ${BIN} --prefix ${OUT}/staged)
file(RENAME ${OUT}/staged ${P})
foreach(f bin/vrv lib/vrv/libvrv_image.so share/vrv/plot_study.py)
  if(NOT EXISTS ${P}/${f})
    message(FATAL_ERROR "install: ${P}/${f} was not installed")
  endif()
endforeach()
file(GLOB module ${P}/${PYDIR}/vrv*.so)
if(NOT module)
  message(FATAL_ERROR "install: no Python module in ${P}/${PYDIR}")
endif()

# The program: images written and read through the prefix's module (LD_DEBUG names what is
# loaded), the plot drawn with the prefix's script.
set(images "")
foreach(h 0.1 0.05 0.025 0.0125)
  run(0 render_${h} ${env} ${P}/bin/vrv render --scene ${SCENE} --method alpha --strategy inviwo
      --step ${h} --width 16 --height 16 --quiet -o ${OUT}/alpha_${h}.exr)
  list(APPEND images ${OUT}/alpha_${h}.exr)
endforeach()
run(0 verify ${env} LD_DEBUG=files ${P}/bin/vrv verify --scene ${SCENE} ${images} --steps 0.1,0.05,0.025,0.0125
    --out ${OUT}/v --cache-dir ${OUT}/cache --plots --quiet)
if(NOT LAST_ERR MATCHES "file=${P}/lib/vrv/libvrv_image.so" OR LAST_ERR MATCHES "file=${BIN}/libvrv_image")
  message(FATAL_ERROR "verify: the image module was not loaded from ${P}/lib/vrv:\n${LAST_ERR}")
endif()
if(LAST_ERR MATCHES "could not be drawn" OR NOT EXISTS ${OUT}/v/error_vs_step.png)
  message(FATAL_ERROR "verify: the plot was not drawn:\n${LAST_ERR}")
endif()

# The module: found where the prefix's Python looks, it finds the image module beside itself.
set(py "import sys, vrv
assert vrv.__file__.startswith(sys.argv[1]), vrv.__file__
scene = vrv.Scene.from_file(sys.argv[2])
steps = [0.1, 0.05, 0.025, 0.0125]
images = [scene.render(method='alpha', strategy='inviwo', step=h, width=16, height=16) for h in steps]
r = vrv.verify(scene, images, steps, diagnose=False, out=sys.argv[3], plots=False)
print(r['verdict'])")
run(0 python ${env} PYTHONPATH=${P}/${PYDIR} LD_DEBUG=files ${PYTHON} -c "${py}" ${P} ${SCENE} ${OUT}/pv)
if(NOT LAST_ERR MATCHES "file=${P}/lib/vrv/libvrv_image.so" OR NOT EXISTS ${OUT}/pv/reference.exr)
  message(FATAL_ERROR "python: the image module was not loaded from ${P}/lib/vrv:\n${LAST_ERR}")
endif()

# Without the prefix's module both refuse, naming where they looked (not the build tree), and
# vrv.verify(out=...) writes nothing.
file(RENAME ${P}/lib/vrv/libvrv_image.so ${OUT}/aside.so)
run(2 verify_no_module ${env} ${P}/bin/vrv verify --scene ${SCENE} ${images} --steps 0.1,0.05,0.025,0.0125 --quiet)
if(NOT LAST_ERR MATCHES "${P}/lib/vrv/libvrv_image.so \\(missing\\)" OR LAST_ERR MATCHES "${BIN}/libvrv_image")
  message(FATAL_ERROR "verify_no_module: unexpected message:\n${LAST_ERR}")
endif()
run(1 python_no_module ${env} PYTHONPATH=${P}/${PYDIR} ${PYTHON} -c "${py}" ${P} ${SCENE} ${OUT}/none)
if(NOT LAST_ERR MATCHES "${P}/lib/vrv/libvrv_image.so \\(missing\\)" OR EXISTS ${OUT}/none)
  message(FATAL_ERROR "python_no_module: wrote ${OUT}/none or unexpected message:\n${LAST_ERR}")
endif()
file(RENAME ${OUT}/aside.so ${P}/lib/vrv/libvrv_image.so)
file(REMOVE_RECURSE ${OUT})
