# Scalable avatars: vtkAnimationAwareDecimation (on the ICT face when available).
morphnode_add_vtk_test(TestAnimationAwareDecimation ${CMAKE_CURRENT_LIST_DIR}/TestAnimationAwareDecimation.cxx LABELS reduction)
