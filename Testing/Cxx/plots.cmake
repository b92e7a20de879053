# Plots (vtkChartXY) rendered offscreen against baseline PNGs.
morphnode_add_vtk_test(TestWeightPlotRender ${CMAKE_CURRENT_LIST_DIR}/TestWeightPlotRender.cxx LABELS render plots)
target_link_libraries(TestWeightPlotRender PRIVATE
  VTK::ChartsCore VTK::ViewsContext2D VTK::RenderingContextOpenGL2)
vtk_module_autoinit(TARGETS TestWeightPlotRender MODULES VTK::RenderingContextOpenGL2)
