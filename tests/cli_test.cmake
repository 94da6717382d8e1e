# End-to-end checks of the vrv command line; run by CTest as `cli`.
# -DVRV=<path to vrv> -DSRC=<source dir> -DOUT=<scratch dir>
file(MAKE_DIRECTORY ${OUT})

function(expect_success name)
  execute_process(COMMAND ${VRV} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name}: exit ${rc}\n${out}\n${err}")
  endif()
  set(LAST_OUT "${out}" PARENT_SCOPE)
endfunction()

function(expect_failure name pattern)
  execute_process(COMMAND ${VRV} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0)
    message(FATAL_ERROR "${name}: expected a non-zero exit, got 0\n${out}")
  endif()
  string(STRIP "${err}" err)
  if(NOT err MATCHES "${pattern}")
    message(FATAL_ERROR "${name}: stderr does not match '${pattern}':\n${err}")
  endif()
  if(err MATCHES "\n")
    message(FATAL_ERROR "${name}: the error is more than one line:\n${err}")
  endif()
endfunction()

# Negative components, both spellings, give the same full-precision JSON line.
expect_success(negative_space ray --origin -3,0.5,0 --direction 1,0,0 --json)
set(a "${LAST_OUT}")
expect_success(negative_equals ray --origin=-3,0.5,0 --direction=1,0,0 --json)
if(NOT a STREQUAL LAST_OUT)
  message(FATAL_ERROR "--origin -3,.. and --origin=-3,.. differ:\n${a}\n${LAST_OUT}")
endif()
foreach(key value error_estimate evaluations t_entry t_exit optical_depth)
  if(NOT a MATCHES "\"${key}\":")
    message(FATAL_ERROR "JSON line lacks ${key}: ${a}")
  endif()
endforeach()
string(JSON t_entry GET "${a}" t_entry)
if(NOT t_entry EQUAL 2)
  message(FATAL_ERROR "t_entry should be 2 for origin x = -3: ${a}")
endif()

# A ray that misses returns the background with null entry and exit.
expect_success(miss ray --origin -3,5,0 --direction 1,0,0 --json)
if(NOT LAST_OUT MATCHES "\"t_entry\":null")
  message(FATAL_ERROR "miss: ${LAST_OUT}")
endif()

# --rays: one JSON line per ray.
file(WRITE ${OUT}/rays.jsonl "{\"origin\": [-3, 0.1, 0.2], \"direction\": [1, 0, 0]}\n{\"origin\": [0, 0, -5], \"direction\": [0.1, 0.2, 1]}\n")
expect_success(rays_file ray --rays ${OUT}/rays.jsonl)
string(REGEX MATCHALL "\n" lines "${LAST_OUT}")
list(LENGTH lines n)
if(NOT n EQUAL 2)
  message(FATAL_ERROR "--rays: expected 2 lines, got ${n}:\n${LAST_OUT}")
endif()

expect_success(help_ray ray --help)
expect_success(help_demo demo --help)
expect_success(demo demo --rays 3)

# Bad input: one line naming the file, key or option, and a non-zero exit.
expect_failure(zero_direction "direction.*zero" ray --origin 0,0,0 --direction 0,0,0)
expect_failure(bad_vector "--origin" ray --origin 1,2 --direction 1,0,0)
expect_failure(nan_vector "--origin" ray --origin nan,0,0 --direction 1,0,0)
expect_failure(bad_tol "--tol" ray --origin 0,0,0 --direction 1,0,0 --tol -1)
expect_failure(missing_scene "nope.toml" ray --scene ${OUT}/nope.toml --origin 0,0,0 --direction 1,0,0)
file(WRITE ${OUT}/bad.toml "[volume]\nmin = [1, -1, -1]\nmax = [1, 1, 1]\n[field]\nkind = \"marschner_lobb\"\n[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n")
expect_failure(bad_box "bad.toml.*volume" ray --scene ${OUT}/bad.toml --origin 0,0,0 --direction 1,0,0)
file(WRITE ${OUT}/bad_rays.jsonl "{\"origin\": [0, 0], \"direction\": [1, 0, 0]}\n")
expect_failure(bad_rays "bad_rays.jsonl:1: origin" ray --rays ${OUT}/bad_rays.jsonl)

# vrv render: a tiny image of the default scene by the reference and by a discrete raycast,
# then the error of one against the other.  stdout is exactly one JSON line.
function(expect_json_line name)
  string(REGEX MATCHALL "\n" lines "${LAST_OUT}")
  list(LENGTH lines n)
  if(NOT n EQUAL 1)
    message(FATAL_ERROR "${name}: stdout should be one JSON line:\n${LAST_OUT}")
  endif()
endfunction()
function(expect_files name)
  foreach(f ${ARGN})
    if(NOT EXISTS ${OUT}/${f})
      message(FATAL_ERROR "${name}: ${OUT}/${f} was not written")
    endif()
    if(EXISTS ${OUT}/${f}.tmp)
      message(FATAL_ERROR "${name}: ${OUT}/${f}.tmp left behind")
    endif()
  endforeach()
endfunction()

file(REMOVE ${OUT}/render_ref.exr ${OUT}/render_ref.png ${OUT}/render_riemann.exr
  ${OUT}/render_riemann.png ${OUT}/render_riemann_error.exr ${OUT}/render_riemann_error.png
  ${OUT}/render_never.exr)
expect_success(render_reference render --reference --width 8 --height 8 -o ${OUT}/render_ref.exr)
expect_json_line(render_reference)
expect_files(render_reference render_ref.exr render_ref.png)
string(JSON w GET "${LAST_OUT}" width)
string(JSON h GET "${LAST_OUT}" height)
string(JSON output GET "${LAST_OUT}" output)
if(NOT w EQUAL 8 OR NOT h EQUAL 8 OR NOT output STREQUAL "${OUT}/render_ref.exr")
  message(FATAL_ERROR "render_reference: JSON line: ${LAST_OUT}")
endif()

expect_success(render_riemann render --method riemann --width 8 --height 8
  -o ${OUT}/render_riemann.exr --error-against ${OUT}/render_ref.exr)
expect_json_line(render_riemann)
expect_files(render_riemann render_riemann.exr render_riemann.png render_riemann_error.exr
  render_riemann_error.png)
foreach(key output width height max_abs_error mean_abs_error rms_error)
  string(JSON value ERROR_VARIABLE missing GET "${LAST_OUT}" ${key})
  if(missing)
    message(FATAL_ERROR "render_riemann: JSON line lacks ${key}: ${LAST_OUT}")
  endif()
endforeach()
string(JSON max_abs GET "${LAST_OUT}" max_abs_error)
if(NOT max_abs GREATER 0 OR NOT max_abs LESS 0.5)
  message(FATAL_ERROR "render_riemann: implausible max_abs_error ${max_abs}")
endif()

# The reference is deterministic: against itself the error is exactly zero.
expect_success(render_self render --reference --width 8 --height 8 -o ${OUT}/render_self.exr
  --error-against ${OUT}/render_ref.exr)
string(JSON max_abs GET "${LAST_OUT}" max_abs_error)
if(NOT max_abs EQUAL 0)
  message(FATAL_ERROR "render_self: max_abs_error should be 0, got ${max_abs}")
endif()

# A fan camera from the scene file: the sampling paper's 120 rays over 30 degrees.
file(WRITE ${OUT}/fan.toml "[volume]\nmin = [-1.5, -1.5, -1.5]\nmax = [1.5, 1.5, 1.5]\n[field]\nkind = \"linear_ramp\"\ngradient = [0.2, 0.1, 0]\noffset = 0.5\n[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n[camera]\nprojection = \"fan\"\neye = [-9, 0, 0]\nangle = 0\nfov = 30\nrays = 120\n")
expect_success(render_fan render --scene ${OUT}/fan.toml --method trapezoid -o ${OUT}/render_fan.exr)
string(JSON w GET "${LAST_OUT}" width)
string(JSON h GET "${LAST_OUT}" height)
if(NOT w EQUAL 120 OR NOT h EQUAL 1)
  message(FATAL_ERROR "render_fan: expected 120 x 1: ${LAST_OUT}")
endif()

expect_success(help_render render --help)
if(NOT LAST_OUT MATCHES "2.5 box diagonals")
  message(FATAL_ERROR "render --help does not document the default camera:\n${LAST_OUT}")
endif()

expect_failure(render_bad_error_against "^vrv: error: --error-against: .*nope.exr" render --reference
  --width 8 --height 8 -o ${OUT}/render_never.exr --error-against ${OUT}/nope.exr)
if(EXISTS ${OUT}/render_never.exr)
  message(FATAL_ERROR "render_bad_error_against: rendered although the reference is missing")
endif()
expect_failure(render_size_mismatch "render_ref.exr: size 8 x 8 differs" render --reference
  --width 4 --height 8 -o ${OUT}/render_never.exr --error-against ${OUT}/render_ref.exr)
expect_failure(render_no_output "-o: an output file" render --reference --width 8 --height 8)
expect_failure(render_not_exr "-o: .*must name an .exr" render --reference -o ${OUT}/x.png)
expect_failure(render_missing_dir "-o: .*does not exist" render --reference -o ${OUT}/no_dir/x.exr)
expect_failure(render_no_method "--reference or --method" render -o ${OUT}/render_never.exr)
expect_failure(render_both "--reference" render --reference --method riemann -o ${OUT}/render_never.exr)
expect_failure(render_tol_discrete "--tol" render --method riemann --tol 1e-6 -o ${OUT}/render_never.exr)
expect_failure(render_bad_width "--width" render --reference --width 0 -o ${OUT}/render_never.exr)
expect_failure(render_fan_height "--height.*must be 1" render --scene ${OUT}/fan.toml --reference
  --height 2 -o ${OUT}/render_never.exr)
file(WRITE ${OUT}/bad_camera.toml "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[field]\nkind = \"marschner_lobb\"\n[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n[camera]\nprojection = \"perspective\"\nrays = 4\n")
expect_failure(render_bad_camera "bad_camera.toml: camera.rays: does not apply" render
  --scene ${OUT}/bad_camera.toml --reference -o ${OUT}/render_never.exr)

# Discrete raycasts from the command line: value and samples, every method.
foreach(method riemann alpha trapezoid exact_linear moreland)
  expect_success(discrete_${method} ray --origin -3,0.5,0 --direction 1,0.1,0 --method ${method} --rate 2 --json)
  if(NOT LAST_OUT MATCHES "^\\{\"value\":[-0-9.e]+,\"samples\":[0-9]+\\}")
    message(FATAL_ERROR "discrete ${method}: ${LAST_OUT}")
  endif()
endforeach()
expect_success(discrete_options ray --origin -3,0.5,0 --direction 1,0.1,0 --method alpha --strategy eye --rate 1.5
  --oversample 5 --correction lee_newman --termination 0.95 --skip 0.01 --precision float --json)
expect_success(discrete_step ray --origin -3,0.5,0 --direction 1,0.1,0 --method trapezoid --step 0.01 --compositing back_to_front)
expect_failure(correction_needs_alpha "--correction" ray --origin 0,0,0 --direction 1,0,0 --method riemann --correction lacroute)
expect_failure(unknown_method "--method" ray --origin 0,0,0 --direction 1,0,0 --method simpson)
expect_failure(vtk_needs_step "--step" ray --origin 0,0,0 --direction 1,0,0 --method riemann --strategy vtk)
expect_failure(pre_needs_grid "--classification" ray --origin 0,0,0 --direction 1,0,0 --method riemann --classification pre)

# Renders do not depend on the thread count.
expect_success(render_one_thread render --reference --width 16 --height 16 --threads 1 --quiet -o ${OUT}/t1.exr)
expect_success(render_two_threads render --reference --width 16 --height 16 --threads 2 --quiet -o ${OUT}/t2.exr --error-against ${OUT}/t1.exr)
if(NOT LAST_OUT MATCHES "\"max_abs_error\":0(\\.0)?,")
  message(FATAL_ERROR "1 and 2 threads differ: ${LAST_OUT}")
endif()

# vrv study: --list finds the studies next to the source tree, the quick convergence study passes
# and writes its five files, and a bad study file fails with one line naming the file and key.
set(ENV{VRV_STUDY_PATH} ${SRC}/studies)
expect_success(study_list study --list)
if(NOT LAST_OUT MATCHES "(^|\n)convergence\t")
  message(FATAL_ERROR "study --list does not list convergence:\n${LAST_OUT}")
endif()
file(REMOVE_RECURSE ${OUT}/studies)
expect_success(study_quick study convergence --quick --out ${OUT}/studies --quiet --threads 2)
expect_json_line(study_quick)
if(NOT LAST_OUT MATCHES "\"study\":\"convergence\"" OR NOT LAST_OUT MATCHES "\"pass\":true")
  message(FATAL_ERROR "study_quick: ${LAST_OUT}")
endif()
foreach(f errors.csv orders.csv orders.md orders.tex meta.json)
  if(NOT EXISTS ${OUT}/studies/convergence/${f})
    message(FATAL_ERROR "study_quick: ${OUT}/studies/convergence/${f} was not written")
  endif()
endforeach()
file(WRITE ${OUT}/bad_study.toml "kind = \"convergence\"\n[scene.volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[scene.field]\nkind = \"marschner_lobb\"\n[scene.transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n[[method]]\nrule = \"simpson\"\nexpected_order = 2\n[sampling]\nstrategy = \"inviwo\"\nsteps = [0.1, 0.05]\n[rays]\ncount = 2\n")
expect_failure(bad_study "bad_study.toml: method\\[0\\]\\.rule: unknown method" study ${OUT}/bad_study.toml --quiet)
file(WRITE ${OUT}/bad_kind.toml "kind = \"visibility\"\n")
expect_failure(bad_study_kind "bad_kind.toml: kind: unknown kind" study ${OUT}/bad_kind.toml)
expect_failure(unknown_study "no study named 'nope'" study nope)
# The CI gate: a method missing its expected order exits 1 with one line on stderr.
file(READ ${SRC}/studies/convergence.toml gate)
string(REPLACE "expected_order = 1" "expected_order = 3" gate "${gate}")
file(WRITE ${OUT}/gate.toml "${gate}")
expect_failure(study_gate "gate: FAILED: riemann" study ${OUT}/gate.toml --quick --out ${OUT}/studies --quiet)
