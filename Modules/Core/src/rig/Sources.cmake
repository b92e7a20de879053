# Face rigs (semantic shapes as combinations of a face's targets) and OBJ-set loading.
target_sources(MorphNodeCore PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/ObjSet.cpp
  ${CMAKE_CURRENT_LIST_DIR}/Rig.cpp)
