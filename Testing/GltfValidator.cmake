# The Khronos glTF validator (npm package gltf-validator; .ci/install-npm-tools.sh installs
# it into .ci/npm-tools) checks MorphNode's glTF exports with ctest. Without it the tests
# skip with the reason; under CI (CI=true, as for ICT-FaceKit) a missing validator is a
# configure error, so that no export passes unchecked.
find_program(MORPHNODE_NODE_EXECUTABLE NAMES node nodejs)
find_path(MORPHNODE_GLTF_VALIDATOR_DIR package.json
  PATHS "${PROJECT_SOURCE_DIR}/.ci/npm-tools/node_modules/gltf-validator"
  NO_DEFAULT_PATH)
option(MORPHNODE_REQUIRE_GLTF_VALIDATOR "Fail instead of skipping when the glTF validator is missing"
  ${morphnode_require_facekit_default})
set(morphnode_gltf_validator_args "")
if (MORPHNODE_NODE_EXECUTABLE AND MORPHNODE_GLTF_VALIDATOR_DIR)
  get_filename_component(morphnode_node_path "${MORPHNODE_GLTF_VALIDATOR_DIR}" DIRECTORY)
  set(morphnode_gltf_validator_args
    "-DNODE=${MORPHNODE_NODE_EXECUTABLE}" "-DNODE_PATH=${morphnode_node_path}")
elseif (MORPHNODE_REQUIRE_GLTF_VALIDATOR)
  message(FATAL_ERROR "The Khronos glTF validator is missing (node: '${MORPHNODE_NODE_EXECUTABLE}', "
    "gltf-validator in .ci/npm-tools: '${MORPHNODE_GLTF_VALIDATOR_DIR}'). Run "
    ".ci/install-npm-tools.sh, or turn MORPHNODE_REQUIRE_GLTF_VALIDATOR off to let the tests skip.")
endif ()

# morphnode_add_gltf_validator_test(<name> [PRODUCER <target> [ARGS ...]] [FILES ...]
#   [WILL_FAIL]): runs PRODUCER (which writes into the test's own folder, passed as
# MORPHNODE_GLTF_EXPORT_DIR), then the validator on what it wrote and on FILES.
function(morphnode_add_gltf_validator_test name)
  cmake_parse_arguments(arg "WILL_FAIL" "PRODUCER" "ARGS;FILES;LABELS" ${ARGN})
  set(dir "${MORPHNODE_TEST_OUTPUT_DIR}/${name}")
  set(producer "")
  if (arg_PRODUCER)
    string(REPLACE ";" "\\;" producer_args "${arg_ARGS}")
    set(producer "-DPRODUCER=$<TARGET_FILE:${arg_PRODUCER}>" "-DPRODUCER_ARGS=${producer_args}"
      "-DDIR=${dir}")
  endif ()
  string(REPLACE ";" "\\;" files "${arg_FILES}")
  add_test(NAME ${name} COMMAND "${CMAKE_COMMAND}" ${morphnode_gltf_validator_args}
    "-DSCRIPT=${PROJECT_SOURCE_DIR}/Testing/Tools/validate-gltf.js" ${producer} "-DFILES=${files}"
    -P "${PROJECT_SOURCE_DIR}/Testing/Tools/RunGltfValidator.cmake")
  set_tests_properties(${name} PROPERTIES
    LABELS "gltf;${arg_LABELS}"
    ENVIRONMENT "MORPHNODE_GLTF_EXPORT_DIR=${dir}"
    SKIP_REGULAR_EXPRESSION "SKIP: the Khronos glTF validator")
  if (arg_WILL_FAIL AND morphnode_gltf_validator_args)
    set_tests_properties(${name} PROPERTIES WILL_FAIL ON)
  endif ()
endfunction()

# The validator itself must fail on a broken file (a POSITION max below its values).
morphnode_add_gltf_validator_test(GltfValidatorNegativeControl
  FILES "${PROJECT_SOURCE_DIR}/Testing/Tools/broken.gltf" WILL_FAIL)
# The core exporter's files: the default head in node frames (GLB) and world space (.gltf,
# STEP), the ICT head when present, each with a performance (weights, head and eye turns).
morphnode_add_gltf_validator_test(GltfValidatorCoreExport
  PRODUCER TestCoreGltfWriter ARGS "--gtest_filter=GltfWriter.*RoundTrip*:GltfWriter.*WorldSpace*"
  LABELS core)
# The avatar files MorphAvatar --serve sends browsers (stream::StreamAvatar): the default
# head and the ICT head through the ARKit rig, driven targets only, rotation nodes added.
morphnode_add_gltf_validator_test(GltfValidatorStreamAvatar
  PRODUCER TestCoreStream ARGS "--gtest_filter=StreamAvatar.*"
  LABELS "core;stream")
