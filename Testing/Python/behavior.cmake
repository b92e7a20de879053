# vtkBehaviorTimeSource from Python: the default face animated through UpdateTimeStep.
morphnode_add_python_test(TestBehaviorTimeSourcePython
  ${CMAKE_CURRENT_SOURCE_DIR}/TestBehaviorTimeSource.py -v)
set_property(TEST TestBehaviorTimeSourcePython APPEND PROPERTY LABELS behavior)
