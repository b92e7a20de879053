# Scalable avatars: animation-aware mesh reduction (OpenMesh's Decimater, kept out of the
# public headers) and the frame-budget controller over levels of detail.
find_package(OpenMesh REQUIRED)
target_sources(MorphNodeCore PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/AnimationAwareReduction.cpp
  ${CMAKE_CURRENT_LIST_DIR}/FrameBudgetController.cpp)
# OpenMeshTools holds the decimater; it links OpenMeshCore itself.
target_link_libraries(MorphNodeCore PRIVATE OpenMeshTools OpenMeshCore)
