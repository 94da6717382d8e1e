# End-to-end checks of `vrv export` and of the trust checks of `vrv render --error-against`;
# run by CTest as `cli.export`.  -DVRV=<path to vrv> -DOUT=<scratch dir>
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})

include(${CMAKE_CURRENT_LIST_DIR}/vrv_run.cmake)

# Export: every file, and the manifest's grid.
run(export 0 export --out ${OUT}/exp --resolution 5,6,7)
foreach(f field_f32.nrrd field_f64.nrrd field_f32.vti field_f64.vti transfer_function.csv
          transfer_function.json camera.json rays.npy export.json)
  if(NOT EXISTS ${OUT}/exp/${f})
    message(FATAL_ERROR "export: ${f} missing")
  endif()
endforeach()
file(READ ${OUT}/exp/export.json manifest)
string(JSON nx GET "${manifest}" grid nodes 0)
string(JSON nz GET "${manifest}" grid nodes 2)
if(NOT nx EQUAL 5 OR NOT nz EQUAL 7)
  message(FATAL_ERROR "export: grid ${manifest}")
endif()
# A refused export leaves nothing behind: the folder its checks created is removed again (an empty
# folder was left), and a unit distance that cannot be exported is named as the option.
set(unit_reason_0 "must be positive and finite")
set(unit_reason_nan "${unit_reason_0}")
set(unit_reason_inf "${unit_reason_0}")
set(unit_reason_1e308 "1e\\+308: at value .* the opacity per this distance rounds to 1, which a scene cannot state; ")
# ... and one so short that an opacity underflows to 0 where the extinction is positive (it wrote
# opacities 0 everywhere: the exported scene integrated to 0).
set(unit_reason_5e-324 "4.94066e-324: at value .* the opacity per this distance underflows to 0 where the extinction is positive; ")
foreach(u 0 nan inf 1e308 5e-324)
  expect_error(export_unit_${u} "^vrv: error: --unit-distance: ${unit_reason_${u}}"
    export --out ${OUT}/refused_${u} --unit-distance ${u})
  if(EXISTS ${OUT}/refused_${u})
    message(FATAL_ERROR "export_unit_${u}: left ${OUT}/refused_${u} behind")
  endif()
endforeach()
run(export_detached 0 export --out ${OUT}/det --nrrd detached --vti ascii --resolution 3,3,3)
foreach(f field_f64.nhdr field_f64.raw field_f32.nhdr field_f32.raw)
  if(NOT EXISTS ${OUT}/det/${f})
    message(FATAL_ERROR "export_detached: ${f} missing")
  endif()
endforeach()
file(SIZE ${OUT}/det/field_f64.raw bytes)
if(NOT bytes EQUAL 216)
  message(FATAL_ERROR "export_detached: field_f64.raw has ${bytes} bytes, expected 27 * 8")
endif()

# Bad input: nothing written.
expect_error(export_bad_resolution "--resolution" export --out ${OUT}/never --resolution 1,4,4)
expect_error(export_no_parent "--out: .*does not exist" export --out ${OUT}/no/such/dir)
file(WRITE ${OUT}/a_file "x")
expect_error(export_out_is_file "--out: .*not a directory" export --out ${OUT}/a_file)
expect_error(export_bad_nrrd "--nrrd" export --out ${OUT}/never --nrrd zipped)
# An option that would be ignored is refused: a layout without its format, a unit distance where
# the scene keeps its own.
expect_error(export_nrrd_without_nrrd "^vrv: error: --nrrd: detached: --formats 'vti' writes no nrrd file$"
  export --out ${OUT}/never --formats vti --nrrd detached)
expect_error(export_vti_without_vti "^vrv: error: --vti: ascii: --formats 'nrrd,nifti' writes no vti file$"
  export --out ${OUT}/never --formats nrrd,nifti --vti ascii)
file(WRITE ${OUT}/opacity.toml "[volume]\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\n[field]\nkind = \"linear_ramp\"\n"
     "gradient = [0.3, 0.2, 0.1]\n[transfer]\nopacity = [[0.0, 0.0], [1.0, 0.3]]\n"
     "color = [[0.0, 1.0], [1.0, 0.2]]\nunit_length = 0.05\n")
expect_error(export_unit_distance_ignored "^vrv: error: --unit-distance: .*opacity.toml gives its opacity per unit_length = 0.05"
  export --scene ${OUT}/opacity.toml --out ${OUT}/never --unit-distance 2)
expect_error(export_bad_formats "^vrv: error: --formats: unknown value 'dicom' " export --out ${OUT}/never --formats nrrd,dicom)
expect_error(export_empty_formats "^vrv: error: --formats: unknown value .." export --out ${OUT}/never --formats ,)
if(EXISTS ${OUT}/never)
  message(FATAL_ERROR "a refused export wrote ${OUT}/never")
endif()
# --formats: only the formats asked for.
run(export_formats 0 export --out ${OUT}/formats --resolution 3,4,5 --formats nifti,metaimage)
foreach(f field_f32.nii field_f64.nii field_f32.mha field_f64.mha)
  if(NOT EXISTS ${OUT}/formats/${f})
    message(FATAL_ERROR "export_formats: ${f} missing")
  endif()
endforeach()
foreach(f field_f64.nrrd field_f64.vti)
  if(EXISTS ${OUT}/formats/${f})
    message(FATAL_ERROR "export_formats: ${f} written though not asked for")
  endif()
endforeach()
if(EXISTS ${OUT}/never)
  message(FATAL_ERROR "export: wrote although the input was bad")
endif()

# Render: double image with provenance; the reference must be of this scene and camera.
run(ref 0 render --reference --width 6 --height 5 --quiet -o ${OUT}/ref.exr)
if(NOT EXISTS ${OUT}/ref.f64.tiff)
  message(FATAL_ERROR "render: no ref.f64.tiff")
endif()
file(WRITE ${OUT}/camera.toml "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[field]\nkind = \"marschner_lobb\"\n[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n[camera]\nprojection = \"perspective\"\neye = [0, 0, -5]\nwidth = 6\nheight = 5\n")
run(other_camera 0 render --scene ${OUT}/camera.toml --reference --quiet -o ${OUT}/other_camera.exr)
run(err_ok 0 render --method alpha --step 0.05 --width 6 --height 5 --quiet -o ${OUT}/a.exr --error-against ${OUT}/ref.exr)
# A discrete render is no reference: the difference of two raycasts was reported as an error.
expect_error(err_discrete "--error-against: .*a.exr: a discrete render \\(alpha .*\\), not a reference"
  render --method riemann --step 0.05 --width 6 --height 5 --quiet -o ${OUT}/c.exr --error-against ${OUT}/a.exr)
file(WRITE ${OUT}/other.toml "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n[field]\nkind = \"marschner_lobb\"\n[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.6]]\n")
expect_error(err_other_scene "--error-against: .*ref.exr: rendered from another scene \\(scene hash"
  render --scene ${OUT}/other.toml --method alpha --step 0.05 --width 6 --height 5 --quiet -o ${OUT}/b.exr --error-against ${OUT}/ref.exr)
expect_error(err_other_camera "--error-against: .*other_camera.exr: rendered with another camera"
  render --method alpha --step 0.05 --width 6 --height 5 --quiet -o ${OUT}/b.exr --error-against ${OUT}/other_camera.exr)
expect_error(err_png "--error-against: .*ref.png: 8-bit uint8 pixels"
  render --method alpha --step 0.05 --width 6 --height 5 --quiet -o ${OUT}/b.exr --error-against ${OUT}/ref.png)
expect_error(err_self "-o: .*would overwrite the --error-against input"
  render --reference --width 6 --height 5 --quiet -o ${OUT}/ref.exr --error-against ${OUT}/ref.exr)
if(EXISTS ${OUT}/b.exr)
  message(FATAL_ERROR "render: wrote although the reference was refused")
endif()

# The renderer conventions on the command line.
run(conventions 0 ray --scene ${OUT}/opacity.toml --origin -3,0.5,0 --direction 1,0.1,0 --method alpha --step 0.02
  --color premultiplied --table-size 256 --table-lookup uncentred --json)
# Premultiplied colour acts on an emission/extinction scene too: with an opacity correction the
# colour keeps the stored opacity while alpha is corrected (docs/discrete-raycasts.md).
run(premultiplied_emission_extinction 0 ray --origin -3,0.5,0 --direction 1,0.1,0 --method alpha --step 0.05
  --oversample 2 --correction lacroute --color premultiplied --json)
expect_error(centred_without_oversampling "^vrv: error: --centred-oversamples: needs --oversample N > 1"
  ray --origin -3,0.5,0 --direction 1,0.1,0 --method alpha --strategy vtk --step 0.02 --centred-oversamples)
expect_error(opacity_unit_needs_opacity "--opacity-unit" ray --origin -3,0.5,0 --direction 1,0,0
  --method alpha --step 0.02 --opacity-unit distance)
expect_error(table_size_bad "--table-size" ray --origin -3,0.5,0 --direction 1,0,0 --method alpha --step 0.02 --table-size 1)
