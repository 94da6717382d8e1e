# vrv verify and vrv gate on projection images, end to end (docs/projections.md, "Verifying
# projection images"); CTest `cli.projection_verify`.  -DVRV=<path to vrv> -DOUT=<scratch dir>
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})

include(${CMAKE_CURRENT_LIST_DIR}/vrv_run.cmake)

set(body "[volume]\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\n[field]\nkind = \"marschner_lobb\"\n[transfer]\nemission = [[0.0, 0.0], [1.0, 1.0]]\nextinction = [[0.0, 0.0], [1.0, 2.0]]\n[camera]\neye = [1.5, 1.0, -4.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 1.0, 0.0]\nfov = 40.0\nwidth = 32\nheight = 32\n")
file(WRITE ${OUT}/mip.toml "mode = \"mip\"\n${body}")
file(WRITE ${OUT}/bad.toml "mode = \"MIP\"\n${body}")

# vrv's MIP (the scene's mode: no --mode) at four steps, then verified against the MIP reference.
set(images "")
foreach(h 0.025 0.0125 0.00625 0.003125)
  run(render_${h} 0 render --scene ${OUT}/mip.toml --method max --strategy step --step ${h} -o ${OUT}/mip_${h}.exr --quiet)
  list(APPEND images ${OUT}/mip_${h}.exr)
endforeach()
run(verify_mip 0 verify --scene ${OUT}/mip.toml --no-cache --quiet ${images})
string(JSON mode GET "${LAST_OUT}" mode)
string(JSON verdict GET "${LAST_OUT}" verdict)
string(JSON expected GET "${LAST_OUT}" expected_order)
string(JSON note GET "${LAST_OUT}" notes 0)
string(JSON nearest GET "${LAST_OUT}" diagnosis 0 placement)
if(NOT mode STREQUAL "mip" OR NOT verdict STREQUAL "converges" OR NOT expected EQUAL 2 OR NOT note MATCHES "not run"
   OR NOT nearest STREQUAL "step")
  message(FATAL_ERROR "verify of vrv's own MIP: ${LAST_OUT}")
endif()
# The same images as X-ray images: they do not converge to the X-ray reference (exit 1).
run(verify_as_xray 1 verify --scene ${OUT}/mip.toml --mode xray --no-cache --no-diagnosis --quiet ${images})
string(JSON mode GET "${LAST_OUT}" mode)
if(NOT mode STREQUAL "xray")
  message(FATAL_ERROR "--mode overrides the scene's: ${LAST_OUT}")
endif()
# emission_absorption overrides the scene's mode: the report has no mode.
run(verify_as_ea 1 verify --scene ${OUT}/mip.toml --mode emission_absorption --expected-order 2 --no-cache --no-diagnosis --quiet ${images})
if(LAST_OUT MATCHES "\"mode\"")
  message(FATAL_ERROR "--mode emission_absorption: ${LAST_OUT}")
endif()
expect_error(bad_mode "^vrv: error: --mode: unknown value 'bogus'" verify --scene ${OUT}/mip.toml --mode bogus --no-cache ${images})
expect_error(bad_scene_mode "bad.toml: mode: unknown value \"MIP\"" verify --scene ${OUT}/bad.toml --no-cache ${images})
expect_error(bad_scene_mode_render "bad.toml: mode: unknown value \"MIP\"" render --scene ${OUT}/bad.toml --reference -o ${OUT}/x.exr)

# vrv gate: the case's scene gives the mode.
file(WRITE ${OUT}/bounds.toml "[defaults]\nmin_order = { fail = 1.75 }\n[[case]]\nname = \"mip\"\nscene = \"mip.toml\"\nimages = [\"mip_0.025.exr\", \"mip_0.0125.exr\", \"mip_0.00625.exr\", \"mip_0.003125.exr\"]\n")
run(gate_mip 0 gate --bounds ${OUT}/bounds.toml --no-cache --quiet)
file(WRITE ${OUT}/render_bounds.toml "[[case]]\nname = \"r\"\nscene = \"mip.toml\"\nsteps = [0.1, 0.05]\nrender = { method = \"alpha\", strategy = \"inviwo\" }\n")
# An RGB scene under a projection: refused naming its file (it said "scene:").
file(WRITE ${OUT}/rgb_mip.toml "mode = \"mip\"\n[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[field]\nkind = \"marschner_lobb\"\n[transfer]\nopacity = [[0, 0], [1, 0.5]]\ncolor = [[0, 1, 0, 0], [1, 0, 1, 0]]\nunit_length = 1\n")
expect_error(verify_rgb_mode "^vrv: error: [^ ]*rgb_mip.toml: transfer: the scene is RGB .*which vrv verify with a projection mode does not handle"
  verify --scene ${OUT}/rgb_mip.toml --no-cache ${images})
expect_error(gate_render_mode "case r: render: the scene has a projection mode" gate --bounds ${OUT}/render_bounds.toml --no-cache --quiet)
