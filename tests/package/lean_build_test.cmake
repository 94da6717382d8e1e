# -DVRV_BUILD_TESTS=OFF -DVRV_BUILD_BENCHMARKS=OFF configures only the program, the image module
# and the Python module (README, "Two commands"); run by CTest as `build.lean`.
# -DSRC=<source dir> -DOUT=<scratch build dir>
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SRC} -B ${OUT} -DCMAKE_BUILD_TYPE=Release
                -DVRV_BUILD_TESTS=OFF -DVRV_BUILD_BENCHMARKS=OFF
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configure: exit ${rc}\n${out}\n${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${OUT} --target help OUTPUT_VARIABLE targets RESULT_VARIABLE rc)
foreach(wanted vrv vrv_image vrv_python)
  if(NOT targets MATCHES "\\.\\.\\. ${wanted}\n")
    message(FATAL_ERROR "the lean build has no target ${wanted}:\n${targets}")
  endif()
endforeach()
foreach(unwanted vrv_tests vrv_verify_tests vrv_image_tests bench_)
  if(targets MATCHES "\\.\\.\\. ${unwanted}")
    message(FATAL_ERROR "the lean build still has ${unwanted}:\n${targets}")
  endif()
endforeach()
file(REMOVE_RECURSE ${OUT})
