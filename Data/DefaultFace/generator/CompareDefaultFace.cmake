# Runs GenerateDefaultFace into the build tree and fails unless the result is
# byte-identical to the committed Data/DefaultFace/default_head.glb.
# Arguments: -DGENERATOR=<exe> -DOUTPUT=<regenerated.glb> -DCOMMITTED=<committed.glb>
foreach (var IN ITEMS GENERATOR OUTPUT COMMITTED)
  if (NOT DEFINED ${var})
    message(FATAL_ERROR "CompareDefaultFace.cmake needs -D${var}=...")
  endif ()
endforeach ()
get_filename_component(name "${COMMITTED}" NAME)
if (NOT EXISTS "${COMMITTED}")
  message(FATAL_ERROR "the committed default head '${COMMITTED}' is missing")
endif ()
execute_process(COMMAND "${GENERATOR}" "${OUTPUT}" RESULT_VARIABLE result)
if (NOT result EQUAL 0)
  message(FATAL_ERROR "GenerateDefaultFace failed (${result})")
endif ()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${OUTPUT}" "${COMMITTED}"
  RESULT_VARIABLE different)
if (different)
  file(SHA256 "${OUTPUT}" new_hash)
  file(SHA256 "${COMMITTED}" old_hash)
  message(FATAL_ERROR "the regenerated head differs from the committed one:\n"
    "  ${OUTPUT} (sha256 ${new_hash})\n  ${COMMITTED} (sha256 ${old_hash})\n"
    "If the generator changed on purpose, regenerate Data/DefaultFace/${name}.")
endif ()
message(STATUS "${name} is reproducible")
