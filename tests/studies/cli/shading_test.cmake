# End-to-end checks of a shaded scene ([shading], docs/shading.md); run by CTest as `cli.shading`.
# The reference and the discrete raycaster shade (vrv ray, vrv render), and vrv verify judges shaded
# images; what does not shade yet refuses the scene in one line with exit 2, never ignoring the table.  -DVRV=<path to vrv> -DOUT=<scratch dir>
file(MAKE_DIRECTORY ${OUT})

include(${CMAKE_CURRENT_LIST_DIR}/vrv_run.cmake)

set(base "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[field]\nkind = \"marschner_lobb\"\n[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n")
file(WRITE ${OUT}/plain.toml "${base}")
file(WRITE ${OUT}/ambient.toml "${base}[shading]\nambient = 0.5\ndiffuse = 0.0\nspecular = 0.0\n")
file(WRITE ${OUT}/lit.toml "${base}[shading]\nlight = [0.0, 0.3, 1.0]\nmodel = \"phong\"\n")
file(WRITE ${OUT}/lit_bad.toml "${base}[shading]\nshininess = 0.5\n")

# Ambient alone halves the emission (checked to the digit by the unit tests; here: it is not the
# unshaded value), and a light changes it again.
run(plain 0 ray --scene ${OUT}/plain.toml --origin 0.1,0.2,-3 --direction 0,0,1 --json)
string(JSON plain GET "${LAST_OUT}" value)
run(ambient 0 ray --scene ${OUT}/ambient.toml --origin 0.1,0.2,-3 --direction 0,0,1 --json)
string(JSON half GET "${LAST_OUT}" value)
if(half STREQUAL plain)
  message(FATAL_ERROR "ambient 0.5 gave the unshaded value ${plain}")
endif()
run(lit 0 ray --scene ${OUT}/lit.toml --origin 0.1,0.2,-3 --direction 0,0,1 --json)
string(JSON lit GET "${LAST_OUT}" value)
string(JSON met GET "${LAST_OUT}" tolerance_met)
if(NOT met OR lit STREQUAL plain OR lit STREQUAL half)
  message(FATAL_ERROR "a lit scene: ${LAST_OUT} (unshaded ${plain}, ambient ${half})")
endif()

# A shaded reference image.
run(render 0 render --scene ${OUT}/lit.toml --reference --width 8 --height 8 -o ${OUT}/lit.exr --quiet)
if(NOT EXISTS ${OUT}/lit.exr)
  message(FATAL_ERROR "render --reference of a shaded scene wrote nothing")
endif()

# The discrete raycaster shades too, with the gradient scheme asked for.
run(ray_method 0 ray --scene ${OUT}/lit.toml --method trapezoid --step 0.01 --gradient analytic --origin 0.1,0.2,-3 --direction 0,0,1 --json)
string(JSON discrete GET "${LAST_OUT}" value)
if(discrete STREQUAL plain)
  message(FATAL_ERROR "a shaded discrete ray gave the unshaded reference value ${plain}")
endif()
run(render_method 0 render --scene ${OUT}/lit.toml --method trapezoid --step 0.05 --width 8 --height 8
  -o ${OUT}/lit_trapezoid.exr --error-against ${OUT}/lit.exr --quiet)
expect_error(gradient_unshaded "--gradient: applies to a shaded scene only"
  ray --scene ${OUT}/plain.toml --method trapezoid --step 0.1 --gradient analytic --origin 0,0,-3 --direction 0,0,1)
expect_error(gradient_nodes "--gradient: nodes .*needs a grid field"
  ray --scene ${OUT}/lit.toml --method trapezoid --step 0.1 --gradient nodes --origin 0,0,-3 --direction 0,0,1)
expect_error(gradient_unknown "--gradient: unknown value 'sobel'"
  render --scene ${OUT}/lit.toml --method trapezoid --step 0.1 --gradient sobel --width 4 --height 4 -o ${OUT}/no.exr)
if(EXISTS ${OUT}/no.exr)
  message(FATAL_ERROR "a refused render wrote its image")
endif()

# vrv verify judges shaded images: vrv's own raycast with central differences one voxel apart
# (the default offset, 2 / 16 here) is nearest its own model, whose gradient the diagnosis names,
# and the floor that scheme leaves against the exact-gradient reference is named (exit 1: it does
# not converge to the reference at order 2).
file(WRITE ${OUT}/lit16.toml "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\ndims = [16, 16, 16]\n[field]\nkind = \"marschner_lobb\"\n[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n[shading]\nlight = [0.0, 0.3, 1.0]\n")
set(images "")
foreach(h 0.1 0.05 0.025)
  run(render_shaded_${h} 0 render --scene ${OUT}/lit16.toml --method alpha --strategy inviwo --step ${h}
      --width 10 --height 10 --quiet -o ${OUT}/shaded_${h}.exr)
  list(APPEND images ${OUT}/shaded_${h}.exr)
endforeach()
run(verify_shaded 1 verify --scene ${OUT}/lit16.toml ${images} --steps 0.1,0.05,0.025 --expected-order 2 --quiet)
string(JSON gradient GET "${LAST_OUT}" diagnosis 0 gradient)
string(JSON rms GET "${LAST_OUT}" diagnosis 0 rms)
string(JSON fault_count LENGTH "${LAST_OUT}" faults)
set(named OFF)
math(EXPR last "${fault_count} - 1")
foreach(k RANGE ${last})
  string(JSON name GET "${LAST_OUT}" faults ${k} name)
  if(name STREQUAL "gradient floor")
    set(named ON)
  endif()
endforeach()
if(NOT gradient STREQUAL "central" OR rms GREATER 1e-6 OR NOT named)
  message(FATAL_ERROR "verify of shaded images: nearest gradient '${gradient}' (RMS ${rms}), gradient floor named: ${named}\n${LAST_OUT}")
endif()

# vrv gate on a shaded scene: vrv's own render case with the exact gradient passes its bound; with
# the default central differences it crosses a bound below their floor (exit 1); a gradient on an
# unshaded scene is refused by name (exit 2).
set(case "[[case]]\nname = \"shaded\"\nscene = \"lit16.toml\"\nsteps = [0.1, 0.05]\nwidth = 8\nheight = 8\n")
file(WRITE ${OUT}/gate_exact.toml "${case}render = { method = \"alpha\", strategy = \"inviwo\", gradient = \"analytic\" }\nrms = { fail = 2e-3 }\n")
file(WRITE ${OUT}/gate_central.toml "${case}render = { method = \"alpha\", strategy = \"inviwo\" }\nrms = { fail = 2e-3 }\n")
file(WRITE ${OUT}/gate_plain.toml "[[case]]\nname = \"plain\"\nscene = \"plain.toml\"\nsteps = [0.1, 0.05]\nwidth = 8\nheight = 8\nrender = { method = \"alpha\", gradient = \"analytic\" }\n")
run(gate_exact 0 gate --bounds ${OUT}/gate_exact.toml --out ${OUT}/gate_exact --no-cache --quiet)
run(gate_central 1 gate --bounds ${OUT}/gate_central.toml --out ${OUT}/gate_central --no-cache --quiet)
expect_error(gate_plain "gate_plain.toml: case plain: render: gradient: applies to a shaded scene only"
  gate --bounds ${OUT}/gate_plain.toml --out ${OUT}/gate_plain --no-cache)

# vrv export writes a shaded scene: export.json states S for the renderer, and scene.toml keeps the
# [shading] table, so that the renderer's images are verified against the shaded reference.
run(export 0 export --scene ${OUT}/lit16.toml --out ${OUT}/export --formats nrrd)
file(READ ${OUT}/export/export.json manifest)
string(JSON light GET "${manifest}" shading light)
string(JSON model GET "${manifest}" shading model)
string(JSON diffuse GET "${manifest}" shading diffuse)
file(READ ${OUT}/export/scene.toml exported)
if(NOT model STREQUAL "blinn_phong" OR diffuse LESS 0.6999 OR diffuse GREATER 0.7001 OR NOT light MATCHES "^\\[" OR NOT exported MATCHES "\\[shading\\]")
  message(FATAL_ERROR "export of a shaded scene: shading ${model} ${diffuse} ${light}\n${exported}")
endif()
# --gradient is refused on an unshaded scene: accepted here, the exported scene shades.
run(exported_ray 0 ray --scene ${OUT}/export/scene.toml --method trapezoid --step 0.05 --gradient analytic
    --origin 0.1,0.2,-3 --direction 0,0,1 --json)

# Shading at the nodes (a grid, pre-classified, node gradients) from the command line, and refused
# without its pipeline.
file(WRITE ${OUT}/grid_lit.toml "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[field]\nkind = \"grid\"\nsource = { kind = \"marschner_lobb\" }\nresolution = [17, 17, 17]\nlayout = \"node\"\ninterpolation = \"trilinear\"\n[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n[shading]\nlight = [0.0, 0.3, 1.0]\n")
set(pre --scene ${OUT}/grid_lit.toml --method trapezoid --step 0.01 --classification pre --gradient nodes --origin 0.1,0.2,-3 --direction 0,0,1 --json)
run(at_nodes 0 ray ${pre} --shade-at nodes)
string(JSON at_nodes GET "${LAST_OUT}" value)
run(at_samples 0 ray ${pre} --shade-at samples)
string(JSON at_samples GET "${LAST_OUT}" value)
if(at_nodes STREQUAL at_samples)
  message(FATAL_ERROR "--shade-at nodes gave the value shaded at the samples, ${at_samples}")
endif()
expect_error(shade_at_post "--shade-at: nodes shades each node's classified colour .*needs --classification pre and --gradient nodes"
  ray --scene ${OUT}/grid_lit.toml --method trapezoid --step 0.01 --gradient nodes --shade-at nodes --origin 0,0,-3 --direction 0,0,1)
expect_error(shade_at_analytic "--shade-at: nodes .*needs a grid field"
  ray --scene ${OUT}/lit.toml --method trapezoid --step 0.01 --shade-at nodes --origin 0,0,-3 --direction 0,0,1)
expect_error(shade_at_unshaded "--shade-at: applies to a shaded scene only"
  ray --scene ${OUT}/plain.toml --method trapezoid --step 0.01 --shade-at nodes --origin 0,0,-3 --direction 0,0,1)

# Refused, naming the scene and what does not shade yet.
expect_error(verify_mode "lit.toml: shading: .*vrv verify with a projection mode" verify --scene ${OUT}/lit.toml ${OUT}/lit.exr --steps 0.1 --mode mip)
expect_error(plan "lit.toml: shading: .*vrv plan" plan --scene ${OUT}/lit.toml --target 1e-3)
expect_error(bad_key "lit_bad.toml: shading.shininess: must be a finite number >= 1, got 0.5"
  ray --scene ${OUT}/lit_bad.toml --origin 0,0,-3 --direction 0,0,1)

# The shading study's schemes are the gradient schemes' table and shaded_nodes: an unknown one is
# refused offering them.
file(READ ${CMAKE_CURRENT_LIST_DIR}/../../../studies/shading/shading.toml study)
string(REGEX REPLACE "\nschemes = [^\n]*" "\nschemes = [\"analytic\", \"sobel\"]" study "${study}")
file(WRITE ${OUT}/bad_schemes.toml "${study}")
expect_error(study_scheme "bad_schemes.toml: schemes\\[1\\]: unknown scheme 'sobel' \\(analytic, central, nodes, shaded_nodes\\)$"
  study ${OUT}/bad_schemes.toml --out ${OUT}/bad_schemes_out)
if(EXISTS ${OUT}/bad_schemes_out)
  message(FATAL_ERROR "a refused study wrote ${OUT}/bad_schemes_out")
endif()
