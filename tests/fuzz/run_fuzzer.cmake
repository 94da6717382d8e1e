# Runs one fuzz target for RUNS inputs, seeded from CORPUS (read only), in a fresh WORK folder
# that takes the new inputs and any crash file (its path is printed on failure).
if(NOT DEFINED SEED)
  set(SEED 1)
endif()
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/new)
execute_process(
  COMMAND ${FUZZER} ${WORK}/new ${CORPUS} -dict=${DICT} -runs=${RUNS} -seed=${SEED}
    -max_len=${MAX_LEN} -timeout=30 -rss_limit_mb=3072 -artifact_prefix=${WORK}/ -print_final_stats=1
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  file(GLOB crashes ${WORK}/crash-* ${WORK}/leak-* ${WORK}/timeout-* ${WORK}/oom-*)
  message(FATAL_ERROR "${FUZZER} failed (${rc}); inputs: ${crashes}")
endif()
