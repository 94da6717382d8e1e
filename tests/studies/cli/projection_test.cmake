# End-to-end checks of --mode (X-ray and MIP projections, docs/projections.md); run by CTest as
# `cli.projection`.  -DVRV=<path to vrv> -DOUT=<scratch dir>
file(MAKE_DIRECTORY ${OUT})

include(${CMAKE_CURRENT_LIST_DIR}/vrv_run.cmake)

# The reference MIP of a ramp peaks at the exit face (t = 4), X-ray is its line integral.
file(WRITE ${OUT}/ramp.toml "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[field]\nkind = \"linear_ramp\"\ngradient = [0.5, 0, 0]\noffset = 0.5\n[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [0.3, 1.0], [1, 0.5]]\n")
run(mip 0 ray --scene ${OUT}/ramp.toml --mode mip --origin -3,0.2,0.1 --direction 1,0,0 --json)
string(JSON mode GET "${LAST_OUT}" mode)
string(JSON value GET "${LAST_OUT}" value)
string(JSON position GET "${LAST_OUT}" position)
string(JSON ambiguous GET "${LAST_OUT}" ambiguous)
if(NOT mode STREQUAL "mip" OR NOT value EQUAL 1 OR NOT position EQUAL 4 OR ambiguous)
  message(FATAL_ERROR "mip of the ramp: ${LAST_OUT}")
endif()
run(xray 0 ray --scene ${OUT}/ramp.toml --mode xray --origin -3,0.2,0.1 --direction 1,0,0 --json)
string(JSON value GET "${LAST_OUT}" value)
if(NOT value EQUAL 1)  # int_0^2 s / 2 ds = 1
  message(FATAL_ERROR "xray of the ramp: ${LAST_OUT}")
endif()
if(LAST_OUT MATCHES "position")
  message(FATAL_ERROR "xray has no position: ${LAST_OUT}")
endif()
# Classified: the extinction's peak (1.0 at f = 0.3, s = 0.6), not tau(max f) = 0.5.
run(mip_classified 0 ray --scene ${OUT}/ramp.toml --mode mip_classified --origin -3,0.2,0.1 --direction 1,0,0 --json)
string(JSON value GET "${LAST_OUT}" value)
string(JSON position GET "${LAST_OUT}" position)
if(value LESS 0.999999999999 OR value GREATER 1.000000000001 OR position LESS 2.599999999 OR position GREATER 2.600000001)
  message(FATAL_ERROR "mip_classified of the ramp: ${LAST_OUT}")
endif()
# Discrete: the largest sample, and Simpson's X-ray (exact on a line).
run(mip_max 0 ray --scene ${OUT}/ramp.toml --mode mip --method max --step 0.5 --origin -3,0.2,0.1 --direction 1,0,0 --json)
string(JSON value GET "${LAST_OUT}" value)
string(JSON samples GET "${LAST_OUT}" samples)
if(NOT value EQUAL 0.875 OR NOT samples EQUAL 4)
  message(FATAL_ERROR "mip --method max: ${LAST_OUT}")
endif()
run(xray_simpson 0 ray --scene ${OUT}/ramp.toml --mode xray --method simpson --strategy vtk --step 0.3 --origin -3,0.2,0.1 --direction 1,0,0 --json)
string(JSON value GET "${LAST_OUT}" value)
if(value LESS 0.99999999999999 OR value GREATER 1.00000000000001)
  message(FATAL_ERROR "xray --method simpson: ${LAST_OUT}")
endif()
# A miss: hit nothing, value 0, position null.
run(miss 0 ray --mode mip --origin -3,5,0 --direction 1,0,0 --json)
if(NOT LAST_OUT MATCHES "\"value\":0.0" OR NOT LAST_OUT MATCHES "\"position\":null" OR NOT LAST_OUT MATCHES "\"t_entry\":null")
  message(FATAL_ERROR "miss: ${LAST_OUT}")
endif()
# Text output and --rays.
run(text 0 ray --mode xray --origin -3,0.5,0 --direction 1,0,0)
if(NOT LAST_OUT MATCHES "mode +xray" OR NOT LAST_OUT MATCHES "error_estimate")
  message(FATAL_ERROR "text: ${LAST_OUT}")
endif()
file(WRITE ${OUT}/rays.jsonl "{\"origin\": [-3, 0.1, 0.2], \"direction\": [1, 0, 0], \"id\": 7}\n{\"origin\": [0, 0, -5], \"direction\": [0.1, 0.2, 1]}\n")
run(rays 0 ray --mode mip --rays ${OUT}/rays.jsonl --quiet)
if(NOT LAST_OUT MATCHES "^{\"id\":7,\"mode\":\"mip\"")
  message(FATAL_ERROR "rays: ${LAST_OUT}")
endif()

# Bad input: one line naming the option, exit 2.
# plan and demo draw emission-absorption only: a scene's projection is refused, not ignored.
file(READ ${OUT}/ramp.toml ramp)
file(WRITE ${OUT}/ramp_mip.toml "mode = \"mip\"\n${ramp}")
expect_error(plan_scene_mode "^vrv: error: .*ramp_mip.toml: mode: the scene asks for the mip projection \\(its key mode\\), which vrv plan does not draw"
  plan --scene ${OUT}/ramp_mip.toml --target 1e-3)
expect_error(demo_scene_mode "^vrv: error: .*ramp_mip.toml: mode: the scene asks for the mip projection \\(its key mode\\), which vrv demo does not draw"
  demo --scene ${OUT}/ramp_mip.toml)
expect_error(bad_mode "^vrv: error: --mode: unknown value 'maximum' \\(one of xray, xray_classified, mip, mip_classified\\)"
  ray --mode maximum --origin -3,0.5,0 --direction 1,0,0)
expect_error(bad_method "--method: unknown value 'alpha' for --mode xray" ray --mode xray --method alpha --step 0.1 --origin -3,0.5,0 --direction 1,0,0)
expect_error(bad_mip_method "--method: unknown value 'riemann' for --mode mip" ray --mode mip --method riemann --step 0.1 --origin -3,0.5,0 --direction 1,0,0)
expect_error(brace_method "--method: unknown value '[{]0[}]' for --mode mip" ray --mode mip --method "{0}" --step 0.1 --origin -3,0.5,0 --direction 1,0,0)
expect_error(ea_option "--oversample: applies to emission-absorption raycasts, not to --mode mip"
  ray --mode mip --method max --step 0.1 --oversample 2 --origin -3,0.5,0 --direction 1,0,0)
expect_error(no_method "--step: applies to a discrete projection only" ray --mode mip --step 0.1 --origin -3,0.5,0 --direction 1,0,0)
expect_error(render_bad_mode "--mode: unknown value 'x'" render --mode x --reference --width 2 --height 2 -o ${OUT}/bad.exr)

# vrv render --mode: the reference and a discrete MIP against it; an emission-absorption image is
# refused as the reference of a MIP.
run(render_mip 0 render --mode mip --reference --width 6 --height 6 --quiet -o ${OUT}/mip_ref.exr)
if(NOT LAST_OUT MATCHES "\"mode\":\"mip\"" OR NOT EXISTS ${OUT}/mip_ref.exr)
  message(FATAL_ERROR "render_mip: ${LAST_OUT}")
endif()
run(render_mip_max 0 render --mode mip --method max --step 0.01 --width 6 --height 6 --quiet -o ${OUT}/mip_h.exr
  --error-against ${OUT}/mip_ref.exr)
string(JSON max_abs GET "${LAST_OUT}" max_abs_error)
if(max_abs GREATER 0.01 OR max_abs LESS 0)
  message(FATAL_ERROR "render_mip_max: implausible max_abs_error ${max_abs}: ${LAST_OUT}")
endif()
run(render_ea 0 render --reference --width 6 --height 6 --quiet -o ${OUT}/ea_ref.exr)
expect_error(render_other_mode "--error-against: .*ea_ref.exr: rendered from another scene"
  render --mode mip --method max --step 0.01 --width 6 --height 6 --quiet -o ${OUT}/mip_h2.exr --error-against ${OUT}/ea_ref.exr)
