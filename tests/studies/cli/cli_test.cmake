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

# Runs vrv with `input` on stdin ("" for none) and expects exit code `code`; when `pattern` is
# not empty, stderr's last line must match it.  Leaves stdout in LAST_OUT.
function(expect_exit name code pattern input)
  if(input STREQUAL "")
    execute_process(COMMAND ${VRV} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  else()
    execute_process(COMMAND ${VRV} ${ARGN} INPUT_FILE ${input} RESULT_VARIABLE rc
      OUTPUT_VARIABLE out ERROR_VARIABLE err)
  endif()
  if(NOT rc EQUAL ${code})
    message(FATAL_ERROR "${name}: expected exit ${code}, got ${rc}\n${out}\n${err}")
  endif()
  string(STRIP "${err}" err)
  if(NOT pattern STREQUAL "")
    # An error (2, 4) is the only line; after a result (3) the last line names what was missed.
    string(REGEX REPLACE "^.*\n" "" last "${err}")
    if(NOT last MATCHES "${pattern}")
      message(FATAL_ERROR "${name}: stderr does not match '${pattern}':\n${err}")
    endif()
    if(NOT code EQUAL 3 AND err MATCHES "\n")
      message(FATAL_ERROR "${name}: stderr is more than one line:\n${err}")
    endif()
  endif()
  set(LAST_OUT "${out}" PARENT_SCOPE)
endfunction()

# Negative components, both spellings, give the same full-precision JSON line.
expect_success(negative_space ray --origin -3,0.5,0 --direction 1,0,0 --json)
set(a "${LAST_OUT}")
expect_success(negative_equals ray --origin=-3,0.5,0 --direction=1,0,0 --json)
if(NOT a STREQUAL LAST_OUT)
  message(FATAL_ERROR "--origin -3,.. and --origin=-3,.. differ:\n${a}\n${LAST_OUT}")
endif()
foreach(key value error_estimate evaluations t_entry t_exit optical_depth tolerance_met)
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

string(JSON met GET "${a}" tolerance_met)
if(NOT met STREQUAL "ON")
  message(FATAL_ERROR "tolerance_met should be true on the default ray: ${a}")
endif()

expect_success(help_ray ray --help)
expect_success(help_demo demo --help)

# --tol means one thing in every command that takes it (lib/shared_options.h), each with its own
# default shown; and plan's --tol, which had its own check, is refused with the same words as the others'.
foreach(cmd ray demo render plan verify)
  expect_success(help_tol_${cmd} ${cmd} --help)
  # (CLI11 may put plan's "Needs: --check" between the flag and its help.)
  if(NOT LAST_OUT MATCHES "--tol[^\n]*(\n +)?The reference's absolute tolerance on I, per ray")
    message(FATAL_ERROR "${cmd} --help does not give --tol the shared help:\n${LAST_OUT}")
  endif()
endforeach()
expect_failure(plan_bad_tol "--tol: must be a positive finite number, got -1$" plan --target 1e-3 --check --tol -1)
expect_failure(plan_rule_twice "--rules: 'riemann' listed twice$" plan --target 1e-3 --rules riemann,alpha,riemann)
expect_failure(plan_tol_without_check "--tol requires --check" plan --target 1e-3 --tol 1e-9)
# An optional size with a default of its own shows it (plan's 32 x 32; render's has none: the scene's).
expect_success(help_plan_size plan --help)
if(NOT LAST_OUT MATCHES "--width INT=32 " OR NOT LAST_OUT MATCHES "--height INT=32 ")
  message(FATAL_ERROR "plan --help does not show its 32 x 32 default:\n${LAST_OUT}")
endif()

# vrv --help lists the subcommands in a newcomer's order: demo, ray, render, study.
expect_success(help --help)
string(REGEX MATCH "demo[^\n]*\n[ ]*ray[^\n]*\n[ ]*render[^\n]*\n[ ]*study" help_order "${LAST_OUT}")
if(NOT help_order)
  message(FATAL_ERROR "vrv --help does not list demo, ray, render, study in that order:\n${LAST_OUT}")
endif()

# vrv demo, the front door: a row per segment rule whose observed order matches the expected one
# ("ok" yes: within the band the studies use, lib/order_estimate.h) and is within 0.25 of it, the
# reference's cost and error estimate, and where to go next.
expect_success(demo demo)
foreach(rule riemann alpha trapezoid exact_linear moreland)
  # | rule | errors ... | expected | observed | ok |
  string(REGEX MATCH "\n\\| ${rule} +\\|[^\n]*\\| +([^ |]+) +\\| +([^ |]+) +\\| +([^ |]+) +\\|" row "${LAST_OUT}")
  set(ok "${CMAKE_MATCH_3}")
  if(NOT row)
    message(FATAL_ERROR "demo: no row for ${rule}:\n${LAST_OUT}")
  endif()
  set(expected "${CMAKE_MATCH_1}")
  set(observed "${CMAKE_MATCH_2}")
  if(NOT observed MATCHES "^-?[0-9]+\\.[0-9]+$")
    message(FATAL_ERROR "demo: ${rule}: observed order '${observed}' is not a number:\n${row}")
  endif()
  if(NOT expected MATCHES "^[0-9]+$")
    message(FATAL_ERROR "demo: ${rule}: expected order '${expected}' is not a whole number:\n${row}")
  endif()
  math(EXPR below "${expected} - 1")  # bounds expected -/+ 0.25, as decimals for if()
  if(observed LESS "${below}.75" OR observed GREATER "${expected}.25")
    message(FATAL_ERROR "demo: ${rule}: observed order ${observed}, expected ${expected}:\n${LAST_OUT}")
  endif()
  if(NOT ok STREQUAL "yes")
    message(FATAL_ERROR "demo: ${rule}: ok is '${ok}':\n${row}")
  endif()
endforeach()
foreach(text "field evaluations per ray" "error estimate" "vrv study --list" "docs/architecture.md")
  string(FIND "${LAST_OUT}" "${text}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "demo: the output lacks '${text}':\n${LAST_OUT}")
  endif()
endforeach()
# 0 is not a way to ask for the default (it was read as "not given").
expect_failure(render_memory_zero "--max-memory: must be a positive number of GiB, got 0$" render --reference --width 4 --height 4 --max-memory 0 -o ${OUT}/memory_zero.exr)
expect_failure(export_memory_zero "--max-memory: must be a positive number of GiB, got 0$" export --max-memory 0 --out ${OUT}/memory_zero_export)
expect_failure(demo_halvings "--halvings: must be in" demo --halvings 0)
# Two steps leave the order's band no spread to be derived from (lib/order_estimate.h).
expect_failure(demo_two_steps "--halvings: must be in \\[2, 8\\]" demo --halvings 1)
expect_failure(demo_step "--step: must be positive" demo --step -1)

# Bad input: one line naming the file, key or option, and a non-zero exit.
# A volume file without end (here /dev/zero) is refused naming it: ray had no memory limit and
# read until std::bad_alloc, which named no file.  Every command that loads a scene takes --max-memory.
file(CREATE_LINK /dev/zero ${OUT}/endless.vti SYMBOLIC)
file(WRITE ${OUT}/endless.toml "[field]\nkind = \"volume\"\nfile = \"endless.vti\"\n[transfer]\nemission = [[0.0, 0.0], [1.0, 1.0]]\nextinction = [[0.0, 0.0], [1.0, 1.0]]\n")
expect_failure(ray_endless_volume "endless.vti: \\(file\\): its XML text, held while its arrays are read, is longer than the 1073741 bytes allowed \\(--max-memory\\)$"
  ray --scene ${OUT}/endless.toml --origin -3,0,0 --direction 1,0,0 --max-memory 0.001)
expect_failure(scene_endless_volume "endless.vti: \\(file\\): its XML text, held while its arrays are read, is longer than the 1073741 bytes allowed \\(--max-memory\\)$"
  scene ${OUT}/endless.toml --max-memory 0.001)
foreach(cmd verify plan demo gate)
  expect_success(help_max_memory_${cmd} ${cmd} --help)
  if(NOT LAST_OUT MATCHES "--max-memory")
    message(FATAL_ERROR "${cmd} --help has no --max-memory")
  endif()
endforeach()
# A box the default camera cannot frame in double is named as the box ("[camera]: camera.eye"
# named a table the scene does not have).
file(WRITE ${OUT}/far_box.toml "[volume]\nmin = [1e308, 0, 0]\nmax = [1.1e308, 1, 1]\n[field]\nkind = \"marschner_lobb\"\n[transfer]\nemission = [[0.0, 0.0], [1.0, 1.0]]\nextinction = [[0.0, 0.0], [1.0, 1.0]]\n")
expect_failure(far_box_camera "^vrv: error: the scene's box \\[1e\\+308, 0, 0\\] to \\[1.1e\\+308, 1, 1\\] is too far out or too large for the default camera in double .*give the scene a \\[camera\\]$"
  render --reference --scene ${OUT}/far_box.toml --width 4 --height 4 -o ${OUT}/far_box.exr)
expect_failure(zero_direction "direction.*zero" ray --origin 0,0,0 --direction 0,0,0)
expect_failure(bad_vector "--origin" ray --origin 1,2 --direction 1,0,0)
expect_failure(nan_vector "--origin" ray --origin nan,0,0 --direction 1,0,0)
expect_failure(bad_tol "--tol" ray --origin 0,0,0 --direction 1,0,0 --tol -1)
expect_failure(missing_scene "nope.toml" ray --scene ${OUT}/nope.toml --origin 0,0,0 --direction 1,0,0)
file(WRITE ${OUT}/bad.toml "[volume]\nmin = [1, -1, -1]\nmax = [1, 1, 1]\n[field]\nkind = \"marschner_lobb\"\n[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n")
expect_failure(bad_box "bad.toml.*volume" ray --scene ${OUT}/bad.toml --origin 0,0,0 --direction 1,0,0)
# Control points whose span overflows (a line of slope 1/inf = 0) gave the value 0 with the
# tolerance met: refused, naming the key (found by probing bad input).
file(WRITE ${OUT}/span.toml "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[field]\nkind = \"linear_ramp\"\ngradient = [0.3, 0.2, 0.1]\n[transfer]\nemission = [[-1e308, 0], [1e308, 1]]\nextinction = [[-1e308, 0], [1e308, 0.5]]\n")
expect_failure(overflowing_span "span.toml: transfer.emission.*too far apart" ray --scene ${OUT}/span.toml --origin -3,0,0 --direction 1,0,0)
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
# REF.exr and REF.f64.tiff are one render's pair: a stale .f64.tiff beside it (another render's)
# is refused, where its float EXR was quietly used instead.
file(MAKE_DIRECTORY ${OUT}/pair)
expect_success(pair_loose render --reference --tol 1e-6 --width 8 --height 8 --quiet -o ${OUT}/pair/loose.exr)
file(COPY_FILE ${OUT}/render_ref.f64.tiff ${OUT}/pair/loose.f64.tiff)
expect_failure(stale_double "--error-against: .*loose.exr: loose.f64.tiff beside it is not the same render \\(reference tol=1e-12 scene [0-9a-f]+; the EXR: reference tol=1e-06 scene [0-9a-f]+\\), so one of the pair is stale"
  render --method riemann --width 8 --height 8 -o ${OUT}/pair/never.exr --error-against ${OUT}/pair/loose.exr)
file(REMOVE ${OUT}/pair/loose.f64.tiff)
expect_success(pair_exr_only render --method riemann --width 8 --height 8 --quiet -o ${OUT}/pair/r.exr
  --error-against ${OUT}/pair/loose.exr)
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
# --bound: the a-priori error bound and the estimate beside the value (their own tests hold them
# against the reference, tests/lib/discrete_error_bound_test.cpp, discrete_error_estimate_test.cpp);
# refused, naming why, where none is derived; its work (about 41 evaluations per sample) counts
# against --max-work.
expect_success(bound_json ray --origin -3,0.5,0 --direction 1,0,0 --method trapezoid --step 0.01 --bound --json)
if(NOT LAST_OUT MATCHES "^\\{\"value\":[-0-9.e]+,\"samples\":[0-9]+,\"error_bound\":[0-9.]+(e-?[0-9]+)?,\"error_estimate\":-?[0-9.]+(e-?[0-9]+)?,\"asymptotic\":(true|false)\\}")
  message(FATAL_ERROR "--bound: ${LAST_OUT}")
endif()
expect_success(bound_text ray --origin -3,0.5,0 --direction 1,0,0 --method alpha --step 0.01 --bound)
if(NOT LAST_OUT MATCHES "error_bound    [0-9].*error_estimate -?[0-9]")
  message(FATAL_ERROR "--bound (text): ${LAST_OUT}")
endif()
expect_success(bound_rays ray --rays ${OUT}/rays.jsonl --method exact_linear --step 0.02 --bound)
string(REGEX MATCHALL "\"error_bound\":[0-9]" bounds "${LAST_OUT}")
list(LENGTH bounds n)
if(NOT n EQUAL 2)
  message(FATAL_ERROR "--rays --bound: expected a bound per ray:\n${LAST_OUT}")
endif()
expect_failure(bound_needs_method "--bound: applies to a discrete raycast" ray --origin -3,0.5,0 --direction 1,0,0 --bound)
expect_failure(bound_partial "--bound: no a-priori bound is derived for a strategy with a partial step" ray
  --origin -3,0.5,0 --direction 1,0,0 --method alpha --strategy partial --step 0.01 --bound)
# Oversampling with a correction: the analysed configuration's bound plus the exact difference.
expect_success(bound_oversample ray --origin -3,0.5,0 --direction 1,0,0 --method alpha --step 0.01 --oversample 4
  --correction lacroute --bound --json)
if(NOT LAST_OUT MATCHES "\"error_bound\":[0-9]")
  message(FATAL_ERROR "--bound --oversample: ${LAST_OUT}")
endif()
expect_success(bound_work_without ray --origin -3,0.5,0 --direction 1,0,0 --method trapezoid --step 0.01 --max-work 1000)
expect_failure(bound_work "above the work limit" ray --origin -3,0.5,0 --direction 1,0,0 --method trapezoid --step 0.01
  --max-work 1000 --bound)
# vrv plan: the chosen raycast meets the target when rendered (--check), JSON whole; bad options named.
expect_success(plan_check plan --target 1e-3 --width 8 --height 8 --check --json)
if(NOT LAST_OUT MATCHES "^\\{\"target\":0.001,\"metric\":\"max\",\"pixels\":64,\"ranked\":\\[.*\"check\":\\{\"measured_error\":[0-9.e-]+,\"met\":true\\}\\}")
  message(FATAL_ERROR "vrv plan --check --json: ${LAST_OUT}")
endif()
expect_success(plan_text plan --target 1e-4 --metric rms --rules exact_linear,riemann --width 8 --height 8)
if(NOT LAST_OUT MATCHES "chosen: --method (exact_linear|riemann) --strategy step --step [0-9.e-]+")
  message(FATAL_ERROR "vrv plan: ${LAST_OUT}")
endif()
expect_failure(plan_no_target "--target" plan)
expect_failure(plan_bad_target "--target: must be a positive finite error" plan --target -1)
expect_failure(plan_bad_metric "--metric: unknown value 'p99'" plan --target 1e-3 --metric p99)
expect_failure(plan_bad_rule "--rules: unknown rule 'simpson'" plan --target 1e-3 --rules alpha,simpson)
# moreland: estimated through exact_linear's nodes plus the exact difference (docs/error-bounds.md).
expect_success(plan_moreland plan --target 1e-3 --rules moreland --width 8 --height 8 --check)
expect_failure(plan_rate_strategy "--strategy: a step-based placement" plan --target 1e-3 --strategy entry_exit_corner)
expect_failure(plan_work "--max-work" plan --target 1e-3 --max-work 10)
file(WRITE ${OUT}/plan_opacity.toml "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[field]\nkind = \"marschner_lobb\"\n[transfer]\nopacity = [[0, 0], [1, 0.5]]\ncolor = [[0, 1], [1, 1]]\n")
expect_failure(plan_opacity_scene "the scene: no estimate is made for an opacity/colour transfer function" plan
  --scene ${OUT}/plan_opacity.toml --target 1e-3)
expect_failure(correction_needs_alpha "--correction" ray --origin 0,0,0 --direction 1,0,0 --method riemann --correction lacroute)
expect_failure(unknown_method "--method" ray --origin 0,0,0 --direction 1,0,0 --method simpson)
expect_failure(vtk_needs_step "--step" ray --origin 0,0,0 --direction 1,0,0 --method riemann --strategy vtk)
expect_failure(pre_needs_grid "--classification" ray --origin 0,0,0 --direction 1,0,0 --method riemann --classification pre)
# A value with braces is shown as typed, not taken as a format string ("vrv: error: invalid format
# string" was the whole message).
expect_failure(brace_value "^vrv: error: --compositing: unknown value '[{]' " ray --origin 0,0,-3 --direction 0,0,1 --method alpha --compositing "{")
expect_failure(brace_value_mentions "--precision: unknown value '[{]x[}]' " ray --origin 0,0,-3 --direction 0,0,1 --method alpha --precision "{x}")

# An empty text option would read as not given (--method "" ran the reference, --mode "" the
# scene's mode): refused.  A NaN unit distance was replaced by verify's default.
# (execute_process directly: an empty argument does not survive a function's ARGN.)
foreach(flag --method --mode)
  execute_process(COMMAND ${VRV} ray --origin -3,0,0 --direction 1,0,0 ${flag} ""
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(STRIP "${err}" err)
  if(NOT rc EQUAL 2 OR NOT err STREQUAL "vrv: error: ${flag}: must not be empty" OR NOT out STREQUAL "")
    message(FATAL_ERROR "ray_empty${flag}: exit ${rc}, stdout '${out}', stderr '${err}'")
  endif()
endforeach()
expect_failure(verify_nan_unit_distance "^vrv: error: --unit-distance: must be positive and finite" verify ${OUT}/t1.exr --steps 0.1 --unit-distance nan)

# A negative thread count is refused by every command that takes one (verify and gate took it).
expect_failure(verify_negative_threads "^vrv: error: --threads: must not be negative" verify ${OUT}/t1.exr --steps 0.1 --threads -1)
expect_failure(gate_negative_threads "^vrv: error: --threads: must not be negative" gate --bounds ${OUT}/no_bounds.toml --threads -1)

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
expect_failure(bad_study "bad_study.toml: method\\[0\\]\\.rule: unknown value 'simpson'" study ${OUT}/bad_study.toml --quiet)
file(WRITE ${OUT}/bad_kind.toml "kind = \"no_such_kind\"\n")
expect_failure(bad_study_kind "bad_kind.toml: kind: unknown kind" study ${OUT}/bad_kind.toml)
expect_failure(unknown_study "no study named 'nope'" study nope)
expect_failure(all_and_name "--all: takes no study name" study --all convergence)
# Driver kinds read their own keys with the same one-line errors (speed_vs_error as the example).
file(READ ${SRC}/studies/speed-vs-error/speed-vs-error.toml sve)
string(REPLACE "repeats = 3" "repeats = 3\nrepeat = 3" sve_key "${sve}")
file(WRITE ${OUT}/bad_sve_key.toml "${sve_key}")
expect_failure(bad_sve_key "bad_sve_key.toml: repeat: unknown key" study ${OUT}/bad_sve_key.toml --quiet)
string(REPLACE "quick_steps = [0.05," "quick_steps = [0.07," sve_quick "${sve}")
file(WRITE ${OUT}/bad_sve_quick.toml "${sve_quick}")
expect_failure(bad_sve_quick "bad_sve_quick.toml: method\\[1\\]\\.quick_steps\\[0\\]: 0.07 is not in steps" study ${OUT}/bad_sve_quick.toml --quiet)
string(REPLACE "strategy = \"inviwo\"" "strategy = \"entry\"" sve_strategy "${sve}")
file(WRITE ${OUT}/bad_sve_strategy.toml "${sve_strategy}")
# Named as a strategy the study does not take (it was "method[1].rate: missing").
expect_failure(bad_sve_strategy "bad_sve_strategy.toml: method\\[1\\]\\.strategy: 'entry' is not taken here \\(one of step, vtk, inviwo\\)"
  study ${OUT}/bad_sve_strategy.toml --quiet)
# The CI gate: a method missing its expected order exits 1 with one line on stderr.
file(READ ${SRC}/studies/convergence/convergence.toml gate)
string(REPLACE "expected_order = 1" "expected_order = 3" gate "${gate}")
file(WRITE ${OUT}/gate.toml "${gate}")
expect_failure(study_gate "gate: FAILED: order riemann" study ${OUT}/gate.toml --quick --out ${OUT}/studies --quiet)

# vrv study hard-cases: passes (quick runs the same cases), writes its four files, no "nan" text;
# a case with an unknown method fails with one line naming the file and key.
expect_success(study_hard_cases study hard-cases --quick --out ${OUT}/studies --quiet --threads 2)
expect_json_line(study_hard_cases)
if(NOT LAST_OUT MATCHES "\"study\":\"hard-cases\"" OR NOT LAST_OUT MATCHES "\"pass\":true")
  message(FATAL_ERROR "study_hard_cases: ${LAST_OUT}")
endif()
foreach(f cases.csv cases.md cases.tex meta.json)
  if(NOT EXISTS ${OUT}/studies/hard-cases/${f})
    message(FATAL_ERROR "study_hard_cases: ${OUT}/studies/hard-cases/${f} was not written")
  endif()
endforeach()
file(READ ${OUT}/studies/hard-cases/cases.csv hard_csv)
if(hard_csv MATCHES "[Nn][Aa][Nn]")
  message(FATAL_ERROR "study_hard_cases: cases.csv has nan:\n${hard_csv}")
endif()
file(WRITE ${OUT}/bad_hard.toml "kind = \"hard_cases\"\n[[case]]\nname = \"c\"\norigin = [-3, 0, 0]\ndirection = [1, 0, 0]\n[case.scene.volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[case.scene.field]\nkind = \"marschner_lobb\"\n[case.scene.transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n[[case.method]]\nmethod = \"simpson\"\n")
expect_failure(bad_hard_case "bad_hard.toml: case\\[0\\]\\.method\\[0\\]\\.method: unknown method 'simpson'" study ${OUT}/bad_hard.toml --quiet)

# ---------------------------------------------------------------------------------------------
# Exit codes (README, "Exit codes"): 2 bad input, 3 a reference value missed --tol, 4 non-finite.

# A tolerance below what a double can resolve is missed on every ray: the value is printed with
# "tolerance_met": false, stderr names it in one line, exit 3.  A linear ramp makes it cheap.
file(WRITE ${OUT}/ramp.toml "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[field]\nkind = \"linear_ramp\"\ngradient = [0.2, 0.1, 0]\noffset = 0.5\n[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n[camera]\nprojection = \"orthographic\"\neye = [0, 0, -4]\ntarget = [0, 0, 0]\nup = [0, 1, 0]\nextent = 1.5\nwidth = 4\nheight = 3\n")
expect_exit(tol_missed 3 "^vrv ray: tolerance missed: error estimate .* > --tol 1e-30" ""
  ray --scene ${OUT}/ramp.toml --origin -3,0.1,0.2 --direction 1,0,0 --tol 1e-30 --json)
if(NOT LAST_OUT MATCHES "\"tolerance_met\":false" OR NOT LAST_OUT MATCHES "\"value\":0\\.")
  message(FATAL_ERROR "tol_missed: ${LAST_OUT}")
endif()
file(REMOVE ${OUT}/tol.exr ${OUT}/tol.png)
expect_exit(render_tol_missed 3 "^vrv render: 12 of 12 pixels missed --tol 1e-30" ""
  render --scene ${OUT}/ramp.toml --reference --tol 1e-30 --quiet -o ${OUT}/tol.exr)
string(JSON missed GET "${LAST_OUT}" tolerance_missed)
if(NOT missed EQUAL 12 OR NOT EXISTS ${OUT}/tol.exr OR NOT EXISTS ${OUT}/tol.png)
  message(FATAL_ERROR "render_tol_missed: images and a count of 12 expected: ${LAST_OUT}")
endif()
expect_success(render_tol_met render --scene ${OUT}/ramp.toml --reference --quiet -o ${OUT}/tol.exr)
string(JSON missed GET "${LAST_OUT}" tolerance_missed)
if(NOT missed EQUAL 0)
  message(FATAL_ERROR "render_tol_met: ${LAST_OUT}")
endif()

# A NaN is never printed as a number: float precision overflows at extinction 1e300.
file(WRITE ${OUT}/huge.toml "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[field]\nkind = \"marschner_lobb\"\n[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 1e300]]\n[camera]\nprojection = \"orthographic\"\neye = [0, 0, -4]\ntarget = [0, 0, 0]\nup = [0, 1, 0]\nextent = 1.5\nwidth = 4\nheight = 4\n")
expect_exit(float_nan 4 "^vrv: error: the discrete raycast gave a non-finite value" ""
  ray --scene ${OUT}/huge.toml --origin -3,0.1,0.2 --direction 1,0,0 --method exact_linear --precision float --json)
if(NOT LAST_OUT STREQUAL "")
  message(FATAL_ERROR "float_nan: printed ${LAST_OUT}")
endif()
# Samples of +-1.7e308 give finite values whose error estimates are NaN: counted as not finite, not
# dropped from the largest estimate (it said "largest error estimate 0" and wrote the images).
file(WRITE ${OUT}/huge_samples.nrrd "NRRD0004\ntype: double\ndimension: 3\nsizes: 3 3 3\nspacings: 1 1 1\nencoding: ascii\n\n1.7e308 -1.7e308 1.7e308 -1.7e308 1.7e308 -1.7e308 1.7e308 -1.7e308 1.7e308 -1.7e308 1.7e308 -1.7e308 1.7e308 -1.7e308 1.7e308 -1.7e308 1.7e308 -1.7e308 1.7e308 -1.7e308 1.7e308 -1.7e308 1.7e308 -1.7e308 1.7e308 -1.7e308 1.7e308\n")
file(WRITE ${OUT}/huge_samples.toml "[field]\nkind = \"volume\"\nfile = \"huge_samples.nrrd\"\n[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n[camera]\nprojection = \"orthographic\"\neye = [1, 1, -6]\ntarget = [1, 1, 1]\nup = [0, 1, 0]\nextent = 3\nwidth = 4\nheight = 4\n")
file(REMOVE ${OUT}/nan_estimate.exr ${OUT}/nan_estimate.png ${OUT}/nan_estimate.f64.tiff)
expect_exit(render_nan_estimate 4 "^vrv: error: [0-9]+ of 16 pixels are NaN or infinite in value or error estimate .*nothing written" ""
  render --scene ${OUT}/huge_samples.toml --reference --quiet -o ${OUT}/nan_estimate.exr)
if(EXISTS ${OUT}/nan_estimate.exr OR EXISTS ${OUT}/nan_estimate.png OR EXISTS ${OUT}/nan_estimate.f64.tiff)
  message(FATAL_ERROR "render_nan_estimate: wrote an image whose error estimates are NaN")
endif()
file(REMOVE ${OUT}/nan.exr ${OUT}/nan.png)
expect_exit(render_nan 4 "^vrv: error: [0-9]+ of 16 pixels are NaN or infinite .*nothing written" ""
  render --scene ${OUT}/huge.toml --method exact_linear --precision float --quiet -o ${OUT}/nan.exr)
if(EXISTS ${OUT}/nan.exr OR EXISTS ${OUT}/nan.png)
  message(FATAL_ERROR "render_nan: wrote an image with NaN pixels")
endif()

# --rays from standard input, with ids passed through, in input order, bitwise the same for 1 and
# 2 threads; a later bad line prints nothing (the whole input is checked first).
file(WRITE ${OUT}/rays_id.jsonl "{\"id\": \"a\", \"origin\": [-3, 0.1, 0.2], \"direction\": [1, 0, 0]}\n\n{\"origin\": [0, 0, -5], \"direction\": [0.1, 0.2, 1], \"id\": 7}\n{\"origin\": [-3, 5, 0], \"direction\": [1, 0, 0]}\n{\"id\": {\"k\": [1]}, \"origin\": [0.3, -4, 0.1], \"direction\": [0, 1, 0.05]}\n")
expect_exit(rays_stdin 0 "" ${OUT}/rays_id.jsonl ray --rays - --threads 1)
set(one_thread "${LAST_OUT}")
string(REGEX MATCHALL "[^\n]+" lines "${LAST_OUT}")
list(LENGTH lines n)
list(GET lines 0 l0)
list(GET lines 1 l1)
list(GET lines 2 l2)
list(GET lines 3 l3)
if(NOT n EQUAL 4 OR NOT l0 MATCHES "^\\{\"id\":\"a\",\"value\"" OR NOT l1 MATCHES "^\\{\"id\":7,"
   OR NOT l2 MATCHES "^\\{\"value\"" OR NOT l3 MATCHES "^\\{\"id\":\\{\"k\":\\[1\\]\\},")
  message(FATAL_ERROR "rays_stdin: ids or order wrong:\n${LAST_OUT}")
endif()
expect_exit(rays_two_threads 0 "" "" ray --rays ${OUT}/rays_id.jsonl --threads 2)
if(NOT LAST_OUT STREQUAL one_thread)
  message(FATAL_ERROR "--rays: 1 and 2 threads differ:\n${one_thread}\n${LAST_OUT}")
endif()
foreach(case "nan|[NaN, 0, 0]|column [0-9]+: NaN is not a JSON number"
              "inf|[-Infinity, 0, 0]|column [0-9]+: -Infinity is not a JSON number"
              "huge|[1e999, 0, 0]|1e999 is beyond the range of a double"
              "cut|[1, 0, 0]|truncated: the line ends before its JSON object is complete")
  string(REPLACE "|" ";" parts "${case}")
  list(GET parts 0 tag)
  list(GET parts 1 origin)
  list(GET parts 2 reason)
  set(line "{\"origin\": ${origin}, \"direction\": [1, 0, 0]}")
  if(tag STREQUAL "cut")
    set(line "{\"origin\": ${origin}, \"direction\": [1, 0")
  endif()
  file(WRITE ${OUT}/rays_${tag}.jsonl "{\"origin\": [-3, 0, 0], \"direction\": [1, 0, 0]}\n${line}\n")
  expect_exit(rays_${tag} 2 "^vrv: error: .*rays_${tag}.jsonl:2: ${reason}" "" ray --rays ${OUT}/rays_${tag}.jsonl)
  if(NOT LAST_OUT STREQUAL "")
    message(FATAL_ERROR "rays_${tag}: printed results before failing:\n${LAST_OUT}")
  endif()
endforeach()
file(WRITE ${OUT}/rays_key.jsonl "{\"origin\": [-3, 0, 0], \"direction\": [1, 0, 0], \"dir\": 1}\n")
expect_exit(rays_unknown_key 2 "rays_key.jsonl:1: unknown key 'dir'" "" ray --rays ${OUT}/rays_key.jsonl)
file(WRITE ${OUT}/rays_array.jsonl "[1, 2, 3]\n")
expect_exit(rays_not_object 2 "rays_array.jsonl:1: expected a JSON object .*got array" "" ray --rays ${OUT}/rays_array.jsonl)
file(MAKE_DIRECTORY ${OUT}/rays_dir)
expect_exit(rays_directory 2 "^vrv: error: --rays: .*rays_dir: is a directory" "" ray --rays ${OUT}/rays_dir)
expect_exit(rays_stdin_bad 2 "<stdin>:2: column" ${OUT}/rays_nan.jsonl ray --rays -)
# Tolerance missed on some rays: all printed, the lines named, exit 3.
file(WRITE ${OUT}/rays_ramp.jsonl "{\"origin\": [-3, 0.1, 0.2], \"direction\": [1, 0, 0]}\n{\"origin\": [-3, 5, 0], \"direction\": [1, 0, 0]}\n")
expect_exit(rays_tol_missed 3 "rays_ramp.jsonl: 1 of 2 rays missed --tol 1e-30 .*: line 1$" ""
  ray --scene ${OUT}/ramp.toml --rays ${OUT}/rays_ramp.jsonl --tol 1e-30)

# Options that would do nothing are refused.
foreach(opt "--rate;2" "--oversample;4" "--correction;lacroute" "--step;0.1" "--precision;float"
            "--termination;0.9")
  list(GET opt 0 name)
  expect_exit(no_method${name} 2 "^vrv: error: ${name}: applies to a discrete raycast only" ""
    ray --origin -3,0,0 --direction 1,0,0 ${opt})
endforeach()
expect_exit(render_no_method_rate 2 "^vrv: error: --rate: applies to a discrete raycast only" ""
  render --reference --rate 2 -o ${OUT}/render_never.exr)
expect_exit(tol_with_method 2 "^vrv: error: --tol: applies to the reference only" ""
  ray --origin -3,0,0 --direction 1,0,0 --method riemann --tol 1e-6)
expect_exit(threads_one_ray 2 "^vrv: error: --threads: applies to --rays only" ""
  ray --origin -3,0,0 --direction 1,0,0 --threads 2)
# --threads -3: refused by every command that takes it, with the same words.
expect_exit(threads_ray 2 "^vrv: error: --threads: must not be negative, got -3$" ""
  ray --rays ${OUT}/rays.jsonl --threads -3)
expect_exit(threads_render 2 "^vrv: error: --threads: must not be negative, got -3$" ""
  render --reference --threads -3 -o ${OUT}/render_never.exr)
expect_exit(threads_study 2 "^vrv: error: --threads: must not be negative, got -3$" ""
  study convergence --threads -3)

# CLI11's own words and exit codes (104, 106, 109) never reach the user.
expect_exit(unknown_option 2 "^vrv: error: unknown option or argument --frobnicate" ""
  ray --origin -3,0,0 --direction 1,0,0 --frobnicate)
expect_exit(width_not_int 2 "^vrv: error: --width: '1e9' is not a valid integer$" ""
  render --reference --width 1e9 -o ${OUT}/render_never.exr)
expect_exit(no_command 2 "^vrv: error: a command is required" "")
expect_exit(unknown_command 2 "^vrv: error: unknown command 'bogus'" "" bogus)
expect_exit(missing_value 2 "^vrv: error: --origin: a value is required$" "" ray --origin)
expect_exit(tol_not_number 2 "^vrv: error: --tol: 'abc' is not a valid number$" ""
  ray --origin -3,0,0 --direction 1,0,0 --tol abc)

# Work without bound is refused before anything runs, naming the estimate and --max-work.
expect_exit(work_step 2 "^vrv: error: --step 1e-9: about 2e\\+09 samples on 1 ray, above the work limit of 1e\\+09.*--max-work" ""
  ray --origin -3,0,0 --direction 1,0,0 --method riemann --step 1e-9)
expect_exit(work_rate 2 "^vrv: error: --rate 1e9: about .* samples on 1 ray.*--max-work" ""
  ray --origin -3,0,0 --direction 1,0,0 --method riemann --rate 1e9)
expect_exit(work_oversample 2 "^vrv: error: --step 1e-5, --oversample 65536: about 1.3.e\\+10 samples.*--max-work" ""
  ray --origin -3,0,0 --direction 1,0,0 --method alpha --oversample 65536 --step 1e-5)
expect_exit(work_render 2 "^vrv: error: --rate 1e4: about .* samples on 65536 rays.*--max-work" ""
  render --method riemann --rate 1e4 -o ${OUT}/render_never.exr)
expect_exit(work_limit_low 2 "^vrv: error: --step 1e-5: about 2e\\+05 samples.*--max-work 2" ""
  ray --origin -3,0,0 --direction 1,0,0 --method riemann --step 1e-5 --max-work 1e5)
expect_exit(work_limit_raised 0 "" ""
  ray --origin -3,0,0 --direction 1,0,0 --method riemann --step 1e-5 --max-work 1e6 --json)
if(NOT LAST_OUT MATCHES "\"samples\":200000")
  message(FATAL_ERROR "work_limit_raised: ${LAST_OUT}")
endif()
# The reference's work too (issue 12: fM = 1e6 ran for minutes with no word): its field
# evaluations, estimated per ray from the field's bandwidth and capped at its work cap.
file(WRITE ${OUT}/fast.toml "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[field]\nkind = \"marschner_lobb\"\nfM = 1e6\n[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n")
expect_exit(work_reference_render 2 "^vrv: error: --max-work: about 8.46e\\+09 field evaluations of the reference on 65536 rays, above the work limit of 1e\\+09; loosen --tol, make the image smaller, simplify the field or allow it with --max-work 8.5e\\+09$" ""
  render --scene ${OUT}/fast.toml --reference -o ${OUT}/render_never.exr)
expect_exit(work_reference_rays 2 "^vrv: error: --rays ${OUT}/rays_ramp.jsonl: about 2 rays, 1e\\+06 field evaluations of the reference, above the work limit of 5e\\+05; split the file or allow it with --max-work 1e\\+06$" ""
  ray --scene ${OUT}/fast.toml --rays ${OUT}/rays_ramp.jsonl --max-work 5e5)
# --max-work applies to the reference as well, so it is not refused without --method.
expect_success(work_reference_allowed ray --origin -3,0,0 --direction 1,0,0 --max-work 1e12 --json)
if(EXISTS ${OUT}/render_never.exr)
  message(FATAL_ERROR "a refused render wrote ${OUT}/render_never.exr")
endif()

# Partial outputs: every output path is checked before anything is written.
file(REMOVE_RECURSE ${OUT}/pe)
file(MAKE_DIRECTORY ${OUT}/pe/r_error.png)
expect_exit(partial_outputs 2 "^vrv: error: -o: .*pe/r_error.png: is a directory" ""
  render --method riemann --width 8 --height 8 -o ${OUT}/pe/r.exr --error-against ${OUT}/render_ref.exr)
foreach(f r.exr r.png r_error.exr)
  if(EXISTS ${OUT}/pe/${f})
    message(FATAL_ERROR "partial_outputs: ${OUT}/pe/${f} was written")
  endif()
endforeach()
file(SHA256 ${OUT}/render_ref.exr ref_hash)
expect_exit(own_input 2 "^vrv: error: -o: .*render_ref.exr would overwrite the --error-against input" ""
  render --reference --width 8 --height 8 -o ${OUT}/render_ref.exr --error-against ${OUT}/render_ref.exr)
get_filename_component(out_name ${OUT} NAME)
expect_exit(own_input_other_name 2 "would overwrite the --error-against input" ""
  render --reference --width 8 --height 8 -o ${OUT}/../${out_name}/render_ref.exr --error-against ${OUT}/render_ref.exr)
file(SHA256 ${OUT}/render_ref.exr ref_hash_after)
if(NOT ref_hash STREQUAL ref_hash_after)
  message(FATAL_ERROR "own_input: render_ref.exr changed")
endif()

# Image I/O is a module loaded on first use: vrv itself does not link OpenImageIO, a ray never
# loads the module, and a render without it fails with one line.
execute_process(COMMAND ldd ${VRV} OUTPUT_VARIABLE libs RESULT_VARIABLE rc)
if(rc EQUAL 0 AND libs MATCHES "OpenImageIO")
  message(FATAL_ERROR "vrv links OpenImageIO directly:\n${libs}")
endif()
set(ENV{VRV_IMAGE_MODULE} ${OUT}/no_such_module.so)
expect_exit(ray_without_module 0 "" "" ray --origin -3,0.5,0 --direction 1,0,0 --json)
expect_exit(render_without_module 2 "^vrv: error: .*image module .*no_such_module.so" ""
  render --reference --width 2 --height 2 --quiet -o ${OUT}/nomodule.exr)
# A module that is there but cannot be loaded: the render ran beside the load (lines before the
# error are the render's own), then exit 2 naming the file, and nothing written.
file(WRITE ${OUT}/not_a_module.so "not a shared library")
set(ENV{VRV_IMAGE_MODULE} ${OUT}/not_a_module.so)
execute_process(COMMAND ${VRV} render --reference --width 2 --height 2 --quiet -o ${OUT}/badmodule.exr
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(STRIP "${err}" err)
string(REGEX REPLACE "^.*\n" "" last "${err}")
if(NOT rc EQUAL 2 OR NOT last MATCHES "^vrv: error: image I/O: cannot load the image module .*not_a_module.so"
   OR EXISTS ${OUT}/badmodule.exr OR EXISTS ${OUT}/badmodule.png)
  message(FATAL_ERROR "render_unloadable_module: expected exit 2 naming the module and nothing written, got ${rc}:\n${err}")
endif()
unset(ENV{VRV_IMAGE_MODULE})
