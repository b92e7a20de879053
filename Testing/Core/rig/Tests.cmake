# Rig files, the shipped ARKit rig, OBJ parsing and OBJ sets (ICT-FaceKit when present).
morphnode_add_core_test(TestCoreRig
  ${CMAKE_CURRENT_LIST_DIR}/TestRig.cpp
  ${CMAKE_CURRENT_LIST_DIR}/TestArkitRig.cpp
  ${CMAKE_CURRENT_LIST_DIR}/TestObjSet.cpp)
