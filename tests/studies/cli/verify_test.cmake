# `vrv verify` and `vrv gate` end to end; run by CTest as `cli.verify`.
# -DVRV=<path to vrv> -DSRC=<source dir> -DOUT=<scratch dir>
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
set(SCENE ${SRC}/studies/gate/ml-oblique.toml)

include(${CMAKE_CURRENT_LIST_DIR}/vrv_run.cmake)

# vrv's own alpha raycast at four steps, 16 x 16, as a renderer would write them.
set(images "")
foreach(h 0.1 0.05 0.025 0.0125)
  run(render_${h} 0 render --scene ${SCENE} --method alpha --strategy inviwo --step ${h}
          --width 16 --height 16 --quiet -o ${OUT}/alpha_${h}.exr)
  list(APPEND images ${OUT}/alpha_${h}.exr)
endforeach()
set(steps 0.1,0.05,0.025,0.0125)
# render names its scene-and-camera hash as export.json does.
string(JSON render_hash ERROR_VARIABLE no_hash GET "${LAST_OUT}" scene_camera_hash)
if(no_hash OR NOT render_hash MATCHES "^[0-9a-f]+$")
  message(FATAL_ERROR "render: no scene_camera_hash in its JSON line:\n${LAST_OUT}")
endif()

# Converges at order 2: exit 0, the JSON names the verdict and the nearest model; the files exist.
run(verify_pass 0 verify --scene ${SCENE} ${images} --steps ${steps} --expected-order 2
        --out ${OUT}/v --cache-dir ${OUT}/cache --quiet)
string(JSON verdict GET "${LAST_OUT}" verdict)
string(JSON placement GET "${LAST_OUT}" diagnosis 0 placement)
string(JSON rule GET "${LAST_OUT}" diagnosis 0 rule)
string(JSON rms GET "${LAST_OUT}" diagnosis 0 rms)
if(NOT verdict STREQUAL "converges" OR NOT placement STREQUAL "inviwo" OR NOT rule STREQUAL "alpha" OR rms GREATER 1e-6)
  message(FATAL_ERROR "verify_pass: ${verdict}, nearest ${placement}/${rule} at ${rms}:\n${LAST_OUT}")
endif()
foreach(f errors.csv errors.md errors.tex errors.json orders.csv diagnosis.json faults.md conventions.md points.csv
          reference.exr 3_alpha_0.0125_Y_error.exr 3_alpha_0.0125_Y_error.png plots.json meta.json)
  if(NOT EXISTS ${OUT}/v/${f})
    message(FATAL_ERROR "verify_pass: ${f} was not written")
  endif()
endforeach()
# The plot is drawn only with --plots (a Python process, ~1 CPU s); the two flags exclude each other.
if(EXISTS ${OUT}/v/error_vs_step.png OR EXISTS ${OUT}/v/error_vs_step.pdf)
  message(FATAL_ERROR "verify_pass: the plot was drawn without --plots")
endif()
# No fault named: faults.md says so instead of a header over no rows.
string(JSON fault_count LENGTH "${LAST_OUT}" faults)
file(READ ${OUT}/v/faults.md faults_md)
if(NOT fault_count EQUAL 0 OR NOT faults_md STREQUAL "none: no fault named\n")
  message(FATAL_ERROR "verify_pass: faults.md with no fault:\n${faults_md}")
endif()
run(verify_plots_conflict 2 verify --scene ${SCENE} ${images} --steps ${steps} --plots --no-plots --quiet)
if(NOT LAST_ERR MATCHES "--plots|--no-plots")
  message(FATAL_ERROR "verify_plots_conflict: the message does not name the flags:\n${LAST_ERR}")
endif()
# The plot goes into --out: without it --plots was accepted and nothing drawn.
run(verify_plots_no_out 2 verify --scene ${SCENE} ${images} --steps ${steps} --plots --quiet)
if(NOT LAST_ERR MATCHES "--plots requires --out")
  message(FATAL_ERROR "verify_plots_no_out: the message does not name --out:\n${LAST_ERR}")
endif()
# The second run reads the reference from the cache.
run(verify_cached 0 verify --scene ${SCENE} ${images} --steps ${steps} --cache-dir ${OUT}/cache --no-diagnosis --quiet)
string(JSON cached GET "${LAST_OUT}" reference from_cache)
if(NOT cached)
  message(FATAL_ERROR "verify_cached: the reference was not read from the cache:\n${LAST_OUT}")
endif()

# Without --steps the steps come from the images' provenance (vrv render writes vrv:step): the
# same report as with them; an image without a step in its provenance is refused.
run(verify_steps_given 0 verify --scene ${SCENE} ${images} --steps ${steps} --cache-dir ${OUT}/cache --no-diagnosis --quiet)
string(JSON given GET "${LAST_OUT}" orders)
run(verify_provenance 0 verify --scene ${SCENE} ${images} --cache-dir ${OUT}/cache --no-diagnosis --quiet)
string(JSON from_provenance GET "${LAST_OUT}" orders)
string(JSON finest GET "${LAST_OUT}" images 3 step)
if(NOT given STREQUAL from_provenance OR NOT finest EQUAL 0.0125)
  message(FATAL_ERROR "verify_provenance: steps ${finest}, orders\n${from_provenance}\nagainst --steps\n${given}")
endif()
expect_error(no_provenance_step "^vrv: error: --steps: not given, and .*/v/reference.exr has no step in its provenance"
  verify --scene ${SCENE} ${OUT}/alpha_0.1.exr ${OUT}/v/reference.exr --no-cache)

# Expecting order 3 fails with exit 1 (a failed check, not bad input).
run(verify_order 1 verify --scene ${SCENE} ${images} --steps ${steps} --expected-order 3
        --cache-dir ${OUT}/cache --no-diagnosis --quiet)

# Bad input: one line naming the file or option, exit 2.
run(render_small 0 render --scene ${SCENE} --method alpha --strategy inviwo --step 0.1
        --width 8 --height 8 --quiet -o ${OUT}/small.exr)
expect_error(wrong_size "small.exr: size 8 x 8 differs"
  verify --scene ${SCENE} ${OUT}/alpha_0.1.exr ${OUT}/small.exr --steps 0.1,0.05 --no-cache)
expect_error(missing_file "nothing.exr: cannot read: no such file"
  verify --scene ${SCENE} ${OUT}/alpha_0.1.exr ${OUT}/nothing.exr --steps 0.1,0.05 --no-cache)
expect_error(step_count "--steps: 1 steps for 2 images"
  verify --scene ${SCENE} ${OUT}/alpha_0.1.exr ${OUT}/alpha_0.05.exr --steps 0.1 --no-cache)
expect_error(bad_alpha "--alpha: 'sideways'"
  verify --scene ${SCENE} ${OUT}/alpha_0.1.exr --steps 0.1 --alpha sideways --no-cache)
# An order that is not positive passed any convergent images ("observed 0.681, expected -1").
expect_error(expected_order_negative "--expected-order: must be a positive finite order, got -1"
  verify --scene ${SCENE} ${OUT}/alpha_0.1.exr --steps 0.1 --expected-order -1 --no-cache)
expect_error(alpha_without_alpha "--alpha: straight: the images have no alpha channel"
  verify --scene ${SCENE} ${OUT}/alpha_0.1.exr --steps 0.1 --alpha straight --no-cache)
file(WRITE ${OUT}/bad_bounds.toml "[defaults]\nrms = { warn = 1, fail = 0.5 }\n")
expect_error(bad_bounds "bad_bounds.toml: defaults.rms: levels must be ordered"
  verify --scene ${SCENE} ${OUT}/alpha_0.1.exr --steps 0.1 --bounds ${OUT}/bad_bounds.toml --no-cache)

# Bounds with verify: a generous limit passes, the same limit tightened below the measured value fails.
file(WRITE ${OUT}/loose.toml "[defaults]\nrms = { warn = 1e-3, fail = 1e-2 }\nmin_order = { fail = 1.75 }\n")
run(bounds_loose 0 verify --scene ${SCENE} ${images} --steps ${steps} --bounds ${OUT}/loose.toml
        --cache-dir ${OUT}/cache --no-diagnosis --quiet)
string(JSON measured GET "${LAST_OUT}" bounds 0 measured)
string(JSON bound GET "${LAST_OUT}" bounds 0 bound)
file(WRITE ${OUT}/tight.toml "[defaults]\n${bound} = { fail = ${measured} }\n")  # equal: still passes
run(bounds_equal 0 verify --scene ${SCENE} ${images} --steps ${steps} --bounds ${OUT}/tight.toml
        --cache-dir ${OUT}/cache --no-diagnosis --quiet)
execute_process(COMMAND python3 -c "print(${measured} * 0.999)" OUTPUT_VARIABLE tighter OUTPUT_STRIP_TRAILING_WHITESPACE)
file(WRITE ${OUT}/tight.toml "[defaults]\n${bound} = { fail = ${tighter} }\n")
run(bounds_tight 1 verify --scene ${SCENE} ${images} --steps ${steps} --bounds ${OUT}/tight.toml
        --cache-dir ${OUT}/cache --no-diagnosis --quiet)
string(JSON verdict GET "${LAST_OUT}" bounds 0 verdict)
if(NOT verdict STREQUAL "fail")
  message(FATAL_ERROR "bounds_tight: ${bound} fail = ${tighter} below the measured ${measured} gave '${verdict}'")
endif()

# A gate images case without steps takes them from the images' provenance, as verify does: the
# same bound rows as the case with its steps written out; an image without a step is refused,
# naming the bounds file, the case and the image.
set(case_images "images = [\"alpha_0.1.exr\", \"alpha_0.05.exr\", \"alpha_0.025.exr\", \"alpha_0.0125.exr\"]")
set(case_bounds "scene = \"${SCENE}\"\nexpected_order = 2\nrms = { fail = 1e-2 }\nmin_order = { fail = 1.75 }\n")
file(WRITE ${OUT}/gate_steps.toml "[[case]]\nname = \"c\"\n${case_bounds}${case_images}\nsteps = [0.1, 0.05, 0.025, 0.0125]\n")
file(WRITE ${OUT}/gate_provenance.toml "[[case]]\nname = \"c\"\n${case_bounds}${case_images}\n")
foreach(kind steps provenance)
  run(gate_${kind} 0 gate --bounds ${OUT}/gate_${kind}.toml --out ${OUT}/gate_${kind} --cache-dir ${OUT}/cache
          --no-diagnosis --no-plots --quiet)
  file(READ ${OUT}/gate_${kind}/bounds.json rows_${kind})
endforeach()
string(JSON rows_length LENGTH "${rows_provenance}")
if(NOT rows_steps STREQUAL rows_provenance OR NOT rows_length EQUAL 2)
  message(FATAL_ERROR "gate_provenance: bound rows\n${rows_provenance}\nagainst the case with steps\n${rows_steps}")
endif()
file(WRITE ${OUT}/gate_nostep.toml "[[case]]\nname = \"p\"\n${case_bounds}images = [\"alpha_0.1.exr\", \"v/reference.exr\"]\n")
expect_error(gate_no_provenance_step
  "^vrv: error: .*gate_nostep.toml: case p: steps: not given, and .*v/reference.exr has no step in its provenance"
  gate --bounds ${OUT}/gate_nostep.toml --out ${OUT}/gate_nostep --no-cache --quiet)
if(EXISTS ${OUT}/gate_nostep/bounds.json)
  message(FATAL_ERROR "gate_no_provenance_step: wrote bounds.json though the case was refused")
endif()

# A gate case naming a study that does not exist is bad input (exit 2), not a failed bound.
file(WRITE ${OUT}/nostudy.toml "[[case]]\nname = \"s\"\nstudy = \"no_such_study\"\n")
expect_error(gate_no_study "case\\[0\\]\\.study: 'no_such_study' is not a study vrv knows"
  gate --bounds ${OUT}/nostudy.toml --out ${OUT}/nostudy --quiet)

# --report: one self-contained HTML page (docs/verify.md, "The HTML report"), the verdict first;
# its path checked before any work (one line, exit 2, nothing written); vrv gate --report writes
# one per case.  The page in a real browser: tests/lib/verify/verify_report_html_browser_test.py.
run(verify_report 0 verify --scene ${SCENE} ${images} --steps ${steps} --expected-order 2
        --cache-dir ${OUT}/cache --report ${OUT}/report/r.html --quiet)
file(READ ${OUT}/report/r.html page)
string(JSON report_path GET "${LAST_OUT}" report)
if(NOT page MATCHES "^<!DOCTYPE html>" OR NOT page MATCHES "<span id=\"verdict-text\">converges</span>"
   OR NOT page MATCHES "No fault named" OR NOT page MATCHES "</body></html>\n$" OR NOT report_path MATCHES "r.html$")
  message(FATAL_ERROR "verify_report: the page does not start with the verdict or is not whole:\n${LAST_OUT}")
endif()
expect_error(report_directory "^vrv: error: --report: .*: is a directory"
  verify --scene ${SCENE} ${images} --steps ${steps} --report ${OUT} --no-cache)
expect_error(report_input "^vrv: error: --report: .*alpha_0.1.exr: is the input"
  verify --scene ${SCENE} ${images} --steps ${steps} --report ${OUT}/alpha_0.1.exr --no-cache)
expect_error(report_in_out "^vrv: error: --report: .*: lies in --out"
  verify --scene ${SCENE} ${images} --steps ${steps} --out ${OUT}/v --report ${OUT}/v/r.html --no-cache)
expect_error(report_bad_image "small.exr: size 8 x 8 differs"
  verify --scene ${SCENE} ${OUT}/alpha_0.1.exr ${OUT}/small.exr --steps 0.1,0.05 --report ${OUT}/never.html --no-cache)
if(EXISTS ${OUT}/never.html)
  message(FATAL_ERROR "report_bad_image: the report was written though the input was refused")
endif()
run(gate_report 0 gate --bounds ${OUT}/gate_steps.toml --out ${OUT}/gate_report --report --cache-dir ${OUT}/cache
        --no-diagnosis --quiet)
file(READ ${OUT}/gate_report/c/report.html case_page)
if(NOT case_page MATCHES "vrv gate: case c" OR NOT case_page MATCHES "<table id=\"bounds-table\">")
  message(FATAL_ERROR "gate_report: OUT/c/report.html lacks the case or its bounds")
endif()
run(gate_report_needs_out 2 gate --bounds ${OUT}/gate_steps.toml --report --quiet)
