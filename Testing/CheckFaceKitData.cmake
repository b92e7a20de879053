# ctest -P script: are the shared data files the tests read there (ICT-FaceKit, or what
# WHAT names)? Fails when REQUIRED (under CI), skips with the reason otherwise.
if (NOT WHAT)
  set(WHAT "ICT-FaceKit")
endif ()
set(missing "")
foreach (file IN LISTS FILES)
  if (NOT EXISTS "${DIR}/${file}")
    list(APPEND missing "${file}")
  endif ()
endforeach ()
if (NOT missing)
  message(STATUS "${WHAT} data present in ${DIR}")
  return()
endif ()
if (REQUIRED)
  message(FATAL_ERROR "${WHAT} data missing in ${DIR}: ${missing}. Tests that need it "
    "would skip; CI requires it (MORPHNODE_REQUIRE_FACEKIT).")
endif ()
# Not required: report it as a skip (SKIP_REGULAR_EXPRESSION of the test).
message("SKIP: ${WHAT} data missing in ${DIR}: ${missing}; the tests that need it are skipped")
