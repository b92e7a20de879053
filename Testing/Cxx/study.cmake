# The optimizer study on the ICT face: the error bound on every frame of a long speech-driven
# animation, adjusted against fixed thresholds (docs/optimizer-study.md).
morphnode_add_vtk_test(TestOptimizerStudy ${CMAKE_CURRENT_LIST_DIR}/TestOptimizerStudy.cxx LABELS optimizer)
