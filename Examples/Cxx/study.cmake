# The optimizer study on a real, long animation: MakeSpeechTrack speaks
# Data/scripts/long-text.txt with behaviour and expands it through the ARKit rig onto a
# face's targets; OptimizerStudy (CMakeLists.txt) runs it through every method
# (docs/optimizer-study.md).
find_package(nlohmann_json 3 REQUIRED)
add_executable(MakeSpeechTrack ${CMAKE_CURRENT_LIST_DIR}/MakeSpeechTrack.cxx)
target_link_libraries(MakeSpeechTrack PRIVATE MorphNode::Core nlohmann_json::nlohmann_json)
target_compile_definitions(MakeSpeechTrack PRIVATE MORPHNODE_DATA_DIR="${PROJECT_SOURCE_DIR}/Data")
install(TARGETS MakeSpeechTrack RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
