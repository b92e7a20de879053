# Lip sync measured on a real face's geometry (eSpeak NG -> visemes -> ARKit rig -> morph).
morphnode_add_vtk_test(TestLipSyncOnFace ${CMAKE_CURRENT_LIST_DIR}/TestLipSyncOnFace.cxx)
