# The installed package, as a consumer uses it; run by CTest as `package`.
# -DBIN=<vrv's build dir> -DSRC=<tests/package> -DOUT=<scratch dir> -DLAUNCHER=<ccache or empty>
# -DPYTHON=<python3> -DPYDIR=<VRV_INSTALL_PYTHONDIR>.  Installs into OUT/prefix, then configures, builds and runs the consumer
# project (tests/package/consumer) against it, and runs the installed program and module.
file(REMOVE_RECURSE ${OUT}/prefix)
function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what}: exit ${rc}\n${out}\n${err}")
  endif()
  set(LAST_OUT "${out}" PARENT_SCOPE)
endfunction()

run(install ${CMAKE_COMMAND} --install ${BIN} --prefix ${OUT}/prefix)
set(launcher)
if(LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
run(configure ${CMAKE_COMMAND} -S ${SRC}/consumer -B ${OUT}/consumer -DCMAKE_BUILD_TYPE=Release
  -DCMAKE_PREFIX_PATH=${OUT}/prefix ${launcher})
run(build ${CMAKE_COMMAND} --build ${OUT}/consumer --parallel 2)
run(consumer_tests ${CMAKE_CTEST_COMMAND} --test-dir ${OUT}/consumer --output-on-failure)
message(STATUS "${LAST_OUT}")

run(installed_program ${OUT}/prefix/bin/vrv ray --origin=-3,0.5,0 --direction=1,0,0 --json)
string(STRIP "${LAST_OUT}" cli)
run(installed_module ${CMAKE_COMMAND} -E env PYTHONPATH=${OUT}/prefix/${PYDIR} ${PYTHON} -c
  "import json, sys, vrv
r = vrv.Scene.default().reference([-3, 0.5, 0], [1, 0, 0])
assert float(r['value']) == json.loads(sys.argv[1])['value'], (r, sys.argv[1])" "${cli}")
