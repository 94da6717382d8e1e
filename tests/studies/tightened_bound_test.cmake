# A study gate can fail: runs `vrv study` (--quick) on a copy of a study file with one bound
# tightened past the value the study measures, and expects exit 1 with the named check among the
# failures on stderr.  Run by CTest as study.<name>.tightened (label study).
#   -DVRV=<vrv> -DSTUDY=<studies/NAME/NAME.toml> -DOUT=<scratch dir>
#   -DFROM=<text in the file> -DTO=<its replacement> -DCHECK=<regex naming the failing check>
foreach(var VRV STUDY OUT FROM TO CHECK)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "tightened_bound_test.cmake: -D${var}=... is required")
  endif()
endforeach()
file(READ ${STUDY} text)
string(FIND "${text}" "${FROM}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "${STUDY}: '${FROM}' not found: the test no longer tightens anything")
endif()
string(REPLACE "${FROM}" "${TO}" tightened "${text}")
get_filename_component(name ${STUDY} NAME)
file(MAKE_DIRECTORY ${OUT})
file(WRITE ${OUT}/${name} "${tightened}")
execute_process(COMMAND ${VRV} study ${OUT}/${name} --quick --quiet --no-plots --out ${OUT}/results
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 1)
  message(FATAL_ERROR "${name} with '${TO}': expected exit 1 (a check failed), got ${rc}\n${out}\n${err}")
endif()
if(NOT err MATCHES "FAILED: .*${CHECK}")
  message(FATAL_ERROR "${name} with '${TO}': the failures do not name '${CHECK}':\n${err}")
endif()
message(STATUS "${name} with '${TO}': exit 1, ${err}")
