# vtkBehaviorTimeSource from Python: the default face animated through UpdateTimeStep.
morphnode_add_python_test(TestBehaviorTimeSourcePython
  ${CMAKE_CURRENT_SOURCE_DIR}/TestBehaviorTimeSource.py -v)
set_property(TEST TestBehaviorTimeSourcePython APPEND PROPERTY LABELS behavior)

# The play_script.py example keeps working: a second of the greeting, a few frames.
morphnode_add_python_test(ExamplePlayScriptPython
  ${PROJECT_SOURCE_DIR}/Examples/Python/play_script.py
  "${PROJECT_SOURCE_DIR}/Data/scripts/greeting.txt" --duration 1.5 --frames 4 --size 200 200
  --out "${MORPHNODE_TEST_OUTPUT_DIR}/ExamplePlayScriptPython")
set_property(TEST ExamplePlayScriptPython APPEND PROPERTY LABELS examples render behavior)
