# Offscreen render tests against Testing/Baseline/*.png (run under xvfb-run -a).
morphnode_add_vtk_test(TestMorphNodeRender
  ${CMAKE_CURRENT_LIST_DIR}/TestMorphNodeRender.cxx LABELS render)
morphnode_add_vtk_test(TestMorphDistanceRender
  ${CMAKE_CURRENT_LIST_DIR}/TestMorphDistanceRender.cxx LABELS render)
