# ctest -P script: are the ICT-FaceKit files the tests read there? Fails when REQUIRED
# (under CI), skips (exit 77) with the reason otherwise.
set(missing "")
foreach (file IN LISTS FILES)
  if (NOT EXISTS "${DIR}/${file}")
    list(APPEND missing "${file}")
  endif ()
endforeach ()
if (NOT missing)
  message(STATUS "ICT-FaceKit data present in ${DIR}")
  return()
endif ()
if (REQUIRED)
  message(FATAL_ERROR "ICT-FaceKit data missing in ${DIR}: ${missing}. Tests that need it "
    "would skip; CI requires it (MORPHNODE_REQUIRE_FACEKIT).")
endif ()
# Not required: report it as a skip (SKIP_REGULAR_EXPRESSION of the test).
message("SKIP: ICT-FaceKit data missing in ${DIR}: ${missing}; the tests that need it are skipped")
