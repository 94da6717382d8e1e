# End-to-end checks of a shaded scene ([shading], docs/shading.md); run by CTest as `cli.shading`.
# The reference and the discrete raycaster shade (vrv ray, vrv render); what does not shade yet
# refuses the scene in one line with exit 2, never ignoring the table.  -DVRV=<path to vrv> -DOUT=<scratch dir>
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

# Refused, naming the scene and what does not shade yet.
expect_error(export "lit.toml: shading: .*vrv export" export --scene ${OUT}/lit.toml --out ${OUT}/export)
expect_error(verify "lit.toml: shading: .*vrv verify" verify --scene ${OUT}/lit.toml ${OUT}/lit.exr --steps 0.1)
expect_error(plan "lit.toml: shading: .*vrv plan" plan --scene ${OUT}/lit.toml --target 1e-3)
expect_error(bad_key "lit_bad.toml: shading.shininess: must be a finite number >= 1, got 0.5"
  ray --scene ${OUT}/lit_bad.toml --origin 0,0,-3 --direction 0,0,1)
