# Scalable avatars: animation-aware reduction against plain quadric decimation over a weight
# track, and the frame-budget controller (tables and plots for docs/reduction.md).
add_executable(ReductionStudy ${CMAKE_CURRENT_LIST_DIR}/ReductionStudy.cxx)
target_link_libraries(ReductionStudy PRIVATE MorphNode::MorphNode MorphNode::Core
  VTK::CommonCore VTK::CommonDataModel VTK::FiltersCore VTK::ChartsCore VTK::ViewsContext2D
  VTK::IOImage VTK::RenderingCore VTK::RenderingOpenGL2 VTK::RenderingContextOpenGL2
  VTK::RenderingFreeType)
target_compile_definitions(ReductionStudy PRIVATE MORPHNODE_FACEKIT_DIR="${MORPHNODE_FACEKIT_DIR}")
vtk_module_autoinit(TARGETS ReductionStudy MODULES VTK::RenderingOpenGL2
  VTK::RenderingContextOpenGL2 VTK::RenderingFreeType)
install(TARGETS ReductionStudy RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
