# Study files refused before anything runs (issue 12), end to end: exit 2, one line naming the
# file, the key and the reason.  Run by CTest as `study_input`.
# -DVRV=<path to vrv> -DSRC=<source dir> -DOUT=<scratch dir>
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})

function(expect_bad_input name pattern)
  execute_process(COMMAND ${VRV} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(STRIP "${err}" err)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "${pattern}" OR err MATCHES "\n")
    message(FATAL_ERROR "${name}: expected exit 2 and one line matching '${pattern}', got exit ${rc}:\n${err}")
  endif()
endfunction()

file(READ ${SRC}/studies/convergence/convergence.toml convergence)
file(READ ${SRC}/studies/hard-cases/hard-cases.toml hard_cases)

# A step too fine is reported in the file's terms, not as --step.
string(REGEX REPLACE "\nsteps = [^\n]*" "\nsteps = [1e-300, 0.01]" text "${convergence}")
file(WRITE ${OUT}/fine.toml "${text}")
expect_bad_input(fine_step "fine.toml: sampling.steps\\[0\\]: step 1e-300 takes about .* samples per ray" study ${OUT}/fine.toml --quick)

# A gate's tolerance is bounded.
string(REPLACE "floor = 0.05" "floor = 1e308" text "${convergence}")
file(WRITE ${OUT}/wide.toml "${text}")
expect_bad_input(wide_tolerance "wide.toml: order_tolerance.floor: must be in \\[0, 0.5\\]" study ${OUT}/wide.toml --quick)

# scene = "FILE" is a scene file next to the study file; a missing one is named.
file(WRITE ${OUT}/nofile.toml "kind = \"hard_cases\"\n[[case]]\nname = \"a\"\nscene = \"my.toml\"\norigin = [-3, 0, 0]\ndirection = [1, 0, 0]\n[[case.method]]\nmethod = \"reference\"\ntol = 1e-10\n")
expect_bad_input(missing_scene "nofile.toml: case\\[0\\]\\.scene: 'my.toml' is not a scene file" study ${OUT}/nofile.toml --quick)

# Twelve 512^3 grid cases: refused with the figure and the limit, before any grid is built.
set(text "kind = \"hard_cases\"\n")
foreach(i RANGE 1 12)
  string(APPEND text "[[case]]\nname = \"g${i}\"\norigin = [-3, 0, 0]\ndirection = [1, 0, 0]\n"
    "[case.scene.volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[case.scene.field]\nkind = \"grid\"\n"
    "resolution = [512, 512, 512]\n[case.scene.field.source]\nkind = \"marschner_lobb\"\n"
    "[case.scene.transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n"
    "[[case.method]]\nmethod = \"reference\"\ntol = 1e-10\n")
endforeach()
file(WRITE ${OUT}/big.toml "${text}")
expect_bad_input(memory "big.toml: \\(memory\\): its grids need about 12.0 GiB \\(12 grids, the largest 512x512x512\\), more than the limit of 4.0 GiB \\(raise it with --max-memory GIB\\)"
  study ${OUT}/big.toml --quick --max-memory 4)
expect_bad_input(memory_negative "^vrv: error: --max-memory: must be a positive number of GiB, got -1$"
  study ${OUT}/big.toml --quick --max-memory -1)
expect_bad_input(memory_zero "^vrv: error: --max-memory: must be a positive number of GiB, got 0$"
  study ${OUT}/big.toml --quick --max-memory 0)
expect_bad_input(memory_negative_list "^vrv: error: --max-memory: must be a positive number of GiB, got -1$"
  study --list --max-memory -1)

# Work (issue 12): a million rays at fine steps is refused before anything runs, with the
# estimate, its largest part and the --max-work that allows it; --estimate prints it and runs nothing.
string(REGEX REPLACE "\ncount = [0-9]+" "\ncount = 1000000" text "${convergence}")
string(REGEX REPLACE "\nsteps = [^\n]*" "\nsteps = [1e-4, 2e-4, 4e-4]" text "${text}")
file(WRITE ${OUT}/many.toml "${text}")
expect_bad_input(work "many.toml: \\(work\\): about 3.1e\\+11 field evaluations \\(the largest part: trapezoid at step 0.0001, 1000000 rays x 3.5e\\+04\\), above the work limit of 1e\\+10; allow it with --max-work 3.2e\\+11$"
  study ${OUT}/many.toml --out ${OUT}/never)
execute_process(COMMAND ${VRV} study ${OUT}/many.toml --estimate --out ${OUT}/never RESULT_VARIABLE rc OUTPUT_VARIABLE out)
string(JSON evaluations GET "${out}" evaluations)
string(JSON within GET "${out}" within_limits)
if(NOT rc EQUAL 0 OR NOT within STREQUAL "OFF" OR evaluations LESS 2.6e11 OR EXISTS ${OUT}/never)
  message(FATAL_ERROR "estimate: exit ${rc}: ${out}")
endif()
# The limit is the study's own variant's: --quick is checked as --quick, and --max-work raises it.
expect_bad_input(work_quick "hard-cases.toml: \\(work\\): --quick: about 3e\\+06 field evaluations .*--max-work 3.1e\\+06$"
  study hard-cases --quick --max-work 1e5 --out ${OUT}/never)
execute_process(COMMAND ${VRV} study hard-cases --quick --max-work 4e6 --no-plots --quiet --out ${OUT}/allowed RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS ${OUT}/allowed/hard-cases/meta.json)
  message(FATAL_ERROR "work_allowed: exit ${rc}: ${err}")
endif()
expect_bad_input(work_option "--max-work: must be a positive number of field evaluations, got -1$" study hard-cases --max-work -1)

# A 10 MB table name: the line is cut.
string(REPEAT "k" 1000000 name)
string(REPEAT "${name}" 10 name)
file(WRITE ${OUT}/huge.toml "kind = \"hard_cases\"\n[${name}]\nx = 1\n")
execute_process(COMMAND ${VRV} study ${OUT}/huge.toml RESULT_VARIABLE rc ERROR_VARIABLE err)
string(LENGTH "${err}" n)
if(NOT rc EQUAL 2 OR n GREATER 1200 OR NOT err MATCHES "\\(10000000 bytes\\): unknown key")
  message(FATAL_ERROR "huge_name: exit ${rc}, ${n} bytes on stderr")
endif()

# Two studies with one name in --all would overwrite each other's folder.
file(MAKE_DIRECTORY ${OUT}/dup/studies/a ${OUT}/dup/studies/b)
file(WRITE ${OUT}/dup/studies/a/a.toml "name = \"same\"\n${hard_cases}")
file(WRITE ${OUT}/dup/studies/b/b.toml "name = \"same\"\n${hard_cases}")
execute_process(COMMAND ${VRV} study --all --quick --out ${OUT}/dup/out WORKING_DIRECTORY ${OUT}/dup
  RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "b.toml: name: 'same' is also the name of .*a.toml")
  message(FATAL_ERROR "duplicate_names: exit ${rc}:\n${err}")
endif()
if(EXISTS ${OUT}/dup/out/same)
  message(FATAL_ERROR "duplicate_names: a study ran")
endif()
