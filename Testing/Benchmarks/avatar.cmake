# The paper's Figure 3: the whole avatar (morph + offscreen render) speaking a long text,
# frame rate against threshold per optimizer method (docs/benchmarks.md). Run it under
# `xvfb-run -a`; CI runs the smoke mode (a handful of frames, nothing timed asserted).
add_executable(BenchAvatarFrameRate ${CMAKE_CURRENT_LIST_DIR}/BenchAvatarFrameRate.cxx)
target_link_libraries(BenchAvatarFrameRate PRIVATE MorphNode::MorphNode MorphNode::Core
  VTK::CommonCore VTK::CommonDataModel VTK::CommonExecutionModel VTK::ChartsCore
  VTK::IOImage VTK::RenderingContext2D VTK::RenderingContextOpenGL2 VTK::RenderingCore
  VTK::RenderingOpenGL2 VTK::RenderingFreeType VTK::ViewsContext2D VTK::InteractionStyle)
# ExampleUtilities.h (WritePng), shared with the study programs.
target_include_directories(BenchAvatarFrameRate PRIVATE "${PROJECT_SOURCE_DIR}/Examples/Cxx")
target_compile_definitions(BenchAvatarFrameRate PRIVATE
  MORPHNODE_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
  MORPHNODE_FACEKIT_DIR="${MORPHNODE_FACEKIT_DIR}")
vtk_module_autoinit(TARGETS BenchAvatarFrameRate MODULES VTK::RenderingOpenGL2
  VTK::RenderingContextOpenGL2 VTK::RenderingFreeType VTK::InteractionStyle)
find_program(MORPHNODE_XVFB_RUN xvfb-run)
if (MORPHNODE_XVFB_RUN)
  add_test(NAME BenchAvatarFrameRate.smoke
    COMMAND ${MORPHNODE_XVFB_RUN} -a $<TARGET_FILE:BenchAvatarFrameRate> --smoke)
else ()
  add_test(NAME BenchAvatarFrameRate.smoke COMMAND BenchAvatarFrameRate --smoke)
endif ()
set_tests_properties(BenchAvatarFrameRate.smoke PROPERTIES LABELS benchmark-smoke)
