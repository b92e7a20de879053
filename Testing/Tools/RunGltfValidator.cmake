# SPDX-License-Identifier: BSD-3-Clause
# ctest driver of the Khronos glTF validator over MorphNode's exports:
#   cmake -DNODE=... -DNODE_PATH=... -DSCRIPT=validate-gltf.js -DDIR=<output folder>
#         [-DPRODUCER=<program> -DPRODUCER_ARGS=<args;...>] [-DFILES=<files;...>] -P RunGltfValidator.cmake
# Runs PRODUCER (which writes .glb/.gltf files into DIR), then the validator on every
# .glb/.gltf in DIR and on FILES; fails on any validator error, or when nothing was written.
# Without NODE (the validator is not installed) it prints "SKIP: ..." (the test's skip
# expression).
if (NOT NODE OR NOT NODE_PATH)
  message("SKIP: the Khronos glTF validator is not installed (run .ci/install-npm-tools.sh, "
    "then configure again; it needs node and npm)")
  return ()
endif ()
if (DIR)
  file(REMOVE_RECURSE "${DIR}")
  file(MAKE_DIRECTORY "${DIR}")
endif ()
if (PRODUCER)
  execute_process(COMMAND ${PRODUCER} ${PRODUCER_ARGS} RESULT_VARIABLE rc)
  if (NOT rc EQUAL 0)
    message(FATAL_ERROR "the program writing the files failed (${rc}): ${PRODUCER} ${PRODUCER_ARGS}")
  endif ()
endif ()
set(files ${FILES})
if (DIR)
  file(GLOB written "${DIR}/*.glb" "${DIR}/*.gltf")
  if (NOT written)
    message(FATAL_ERROR "nothing was written into ${DIR}")
  endif ()
  list(APPEND files ${written})
endif ()
execute_process(COMMAND "${CMAKE_COMMAND}" -E env "NODE_PATH=${NODE_PATH}" "${NODE}" "${SCRIPT}" ${files}
  RESULT_VARIABLE rc)
if (NOT rc EQUAL 0)
  message(FATAL_ERROR "the glTF validator found errors (exit code ${rc})")
endif ()
