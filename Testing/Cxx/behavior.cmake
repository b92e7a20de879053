# vtkBehaviorTimeSource: the behaviour control as a temporal weight source.
morphnode_add_vtk_test(TestBehaviorTimeSource
  ${CMAKE_CURRENT_LIST_DIR}/TestBehaviorTimeSource.cxx LABELS behavior)
target_link_libraries(TestBehaviorTimeSource PRIVATE VTK::IOCore)
