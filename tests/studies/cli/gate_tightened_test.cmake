# A bound tightened past the measured value fails the gate: run by CTest as `gate.tightened`.
# Runs one case of studies/gate/vrv-methods.toml, reads its measured RMS from bounds.json, and
# gates the same case again with the fail limit just below (exit 1, verdict fail) and at it (exit 0).
# -DVRV=<path to vrv> -DSRC=<source dir> -DOUT=<scratch dir>
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
set(common --cache-dir ${OUT}/cache --no-plots --no-diagnosis --quiet)
execute_process(COMMAND ${VRV} gate --bounds ${SRC}/studies/gate/vrv-methods.toml --case alpha-inviwo
                --out ${OUT}/measured ${common} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the default bounds fail: exit ${rc}\n${out}\n${err}")
endif()
file(READ ${OUT}/measured/bounds.json rows)
string(JSON n LENGTH "${rows}")
math(EXPR last "${n} - 1")
set(measured "")
foreach(i RANGE ${last})
  string(JSON bound GET "${rows}" ${i} bound)
  if(bound STREQUAL "rms")
    string(JSON measured GET "${rows}" ${i} measured)
  endif()
endforeach()
if(measured STREQUAL "")
  message(FATAL_ERROR "no rms row in ${OUT}/measured/bounds.json")
endif()
execute_process(COMMAND python3 -c "print(repr(${measured} * (1 - 1e-9)))" OUTPUT_VARIABLE below
                OUTPUT_STRIP_TRAILING_WHITESPACE)
foreach(limit below measured)
  file(WRITE ${OUT}/${limit}.toml "[[case]]\nname = \"alpha-inviwo\"\nscene = \"${SRC}/studies/gate/ml-oblique.toml\"\n"
       "steps = [0.1, 0.05, 0.025, 0.0125]\nrender = { method = \"alpha\", strategy = \"inviwo\" }\n"
       "rms = { fail = ${${limit}} }\n")
  execute_process(COMMAND ${VRV} gate --bounds ${OUT}/${limit}.toml --out ${OUT}/${limit} ${common}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  file(READ ${OUT}/${limit}/bounds.json rows)
  string(JSON verdict GET "${rows}" 0 verdict)
  if(limit STREQUAL "below" AND (NOT rc EQUAL 1 OR NOT verdict STREQUAL "fail"))
    message(FATAL_ERROR "rms fail = ${below} < measured ${measured}: exit ${rc}, verdict ${verdict}\n${out}\n${err}")
  endif()
  if(limit STREQUAL "measured" AND (NOT rc EQUAL 0 OR NOT verdict STREQUAL "pass"))
    message(FATAL_ERROR "rms fail = measured ${measured}: exit ${rc}, verdict ${verdict}\n${out}\n${err}")
  endif()
endforeach()
