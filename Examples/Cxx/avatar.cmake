# MorphAvatar: the running system of the paper's Figure 6. An avatar speaks a sentence or
# a behaviour script with idle behaviour; the optimizer is switched by keys; offscreen it
# renders PNG frames and a video (docs/avatar.md).
add_executable(MorphAvatar ${CMAKE_CURRENT_LIST_DIR}/MorphAvatar.cxx)
target_link_libraries(MorphAvatar PRIVATE MorphNode::MorphNode
  VTK::CommonCore VTK::CommonDataModel VTK::CommonExecutionModel VTK::CommonTransforms
  VTK::IOImage VTK::IOOggTheora VTK::IOXML VTK::RenderingCore VTK::RenderingOpenGL2
  VTK::RenderingFreeType VTK::InteractionStyle VTK::TestingRendering)
target_compile_definitions(MorphAvatar PRIVATE MORPHNODE_DATA_DIR="${PROJECT_SOURCE_DIR}/Data")
vtk_module_autoinit(TARGETS MorphAvatar MODULES VTK::RenderingOpenGL2 VTK::RenderingFreeType
  VTK::InteractionStyle)
install(TARGETS MorphAvatar RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
