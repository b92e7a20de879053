# The examples keep working: each renders a face offscreen to a PNG (run under xvfb-run).
set(example_face "${MORPHNODE_FACEKIT_DIR}/ict_face11248_sparse53.glb")
if (EXISTS "${PROJECT_SOURCE_DIR}/Data/DefaultFace/default_face.glb")
  set(example_face "${PROJECT_SOURCE_DIR}/Data/DefaultFace/default_face.glb")
  set(example_weights --weight O=0.8 --weight BrowsUp=0.6)
else ()
  set(example_weights --mode relative --weight jawOpen=0.6 --weight browInnerUp_L=0.8)
endif ()
morphnode_add_python_test(ExampleMorphFacePython
  ${PROJECT_SOURCE_DIR}/Examples/Python/morph_face.py "${example_face}" ${example_weights}
  --color AnimatedRegion --png ${MORPHNODE_TEST_OUTPUT_DIR}/ExampleMorphFacePython.png)
set_property(TEST ExampleMorphFacePython APPEND PROPERTY LABELS examples render)
if (TARGET MorphFace)
  add_test(NAME ExampleMorphFaceCxx COMMAND MorphFace "${example_face}" ${example_weights}
    --png ${MORPHNODE_TEST_OUTPUT_DIR}/ExampleMorphFaceCxx.png)
  set_tests_properties(ExampleMorphFaceCxx PROPERTIES LABELS "examples;render")
endif ()
