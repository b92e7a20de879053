# PlayScript: a behaviour script played on a face, offscreen, to PNG frames, CSV and WAV
# (tested in Testing/Cxx/behavior.cmake).
add_executable(PlayScript ${CMAKE_CURRENT_LIST_DIR}/PlayScript.cxx)
target_link_libraries(PlayScript PRIVATE MorphNode::MorphNode
  VTK::CommonCore VTK::CommonDataModel VTK::IOCore VTK::IOImage VTK::RenderingCore
  VTK::RenderingOpenGL2 VTK::InteractionStyle)
target_compile_definitions(PlayScript PRIVATE MORPHNODE_DATA_DIR="${PROJECT_SOURCE_DIR}/Data")
vtk_module_autoinit(TARGETS PlayScript MODULES VTK::RenderingOpenGL2 VTK::InteractionStyle)
install(TARGETS PlayScript RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
