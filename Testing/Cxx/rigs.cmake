# Face rigs: vtkMorphRigFilter and vtkMorphRigBaker (ICT parts skip without ICT-FaceKit),
# and the contact sheets of the paper's 13 shapes (render tests, run under xvfb-run -a).
morphnode_add_vtk_test(TestMorphRig ${CMAKE_CURRENT_LIST_DIR}/TestMorphRig.cxx LABELS rigs)
if (EXISTS "${CMAKE_CURRENT_LIST_DIR}/TestMorphRigContactSheet.cxx")
  morphnode_add_vtk_test(TestMorphRigContactSheet
    ${CMAKE_CURRENT_LIST_DIR}/TestMorphRigContactSheet.cxx LABELS "rigs;render")
endif ()
