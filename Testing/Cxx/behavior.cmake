# vtkBehaviorTimeSource: the behaviour control as a temporal weight source.
morphnode_add_vtk_test(TestBehaviorTimeSource
  ${CMAKE_CURRENT_LIST_DIR}/TestBehaviorTimeSource.cxx LABELS behavior)
target_link_libraries(TestBehaviorTimeSource PRIVATE VTK::IOCore)

# The PlayScript example keeps working: a second of the greeting, a few frames.
if (TARGET PlayScript)
  add_test(NAME ExamplePlayScriptCxx COMMAND PlayScript
    "${PROJECT_SOURCE_DIR}/Data/scripts/greeting.txt" --duration 1.5 --frames 4 --size 200 200
    --out "${MORPHNODE_TEST_OUTPUT_DIR}/ExamplePlayScriptCxx")
  set_tests_properties(ExamplePlayScriptCxx PROPERTIES LABELS "examples;render;behavior")
endif ()
