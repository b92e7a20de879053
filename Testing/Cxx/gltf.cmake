# Cross-check against VTK's own glTF morphing (needs ICT-FaceKit beside the repository).
find_package(nlohmann_json 3 REQUIRED)
morphnode_add_vtk_test(TestMorphNodeGLTFCrossCheck
  ${CMAKE_CURRENT_LIST_DIR}/TestMorphNodeGLTFCrossCheck.cxx LABELS crosscheck)
target_link_libraries(TestMorphNodeGLTFCrossCheck PRIVATE nlohmann_json::nlohmann_json)
