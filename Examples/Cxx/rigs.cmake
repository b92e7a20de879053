# Face rigs: the paper's Table 1 on the default face and on the ICT face through the ARKit
# rig (the markdown table in docs/rigs.md).
add_executable(RigTable ${CMAKE_CURRENT_LIST_DIR}/RigTable.cxx)
target_link_libraries(RigTable PRIVATE MorphNode::MorphNode VTK::CommonCore VTK::CommonDataModel)
target_compile_definitions(RigTable PRIVATE MORPHNODE_DATA_DIR="${PROJECT_SOURCE_DIR}/Data"
  MORPHNODE_FACEKIT_DIR="${MORPHNODE_FACEKIT_DIR}")
install(TARGETS RigTable RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if (BUILD_TESTING)
  add_test(NAME ExampleRigTable COMMAND RigTable)
  set_tests_properties(ExampleRigTable PROPERTIES LABELS "examples;rigs"
    PASS_REGULAR_EXPRESSION "\\| O \\| 1.00 \\| 12 \\|")
endif ()
