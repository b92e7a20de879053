# The MorphAvatar application (Examples/Cxx/MorphAvatar.cxx) run as a program: the render
# regression of one frame against Baseline/TestMorphAvatar.png, the offscreen mode (PNG
# frames, Theora video, WAV) and its argument errors. Run under `xvfb-run -a`.
if (TARGET MorphAvatar)
  morphnode_add_vtk_test(TestMorphAvatar
    ${CMAKE_CURRENT_LIST_DIR}/TestMorphAvatar.cxx LABELS render examples avatar)
  target_compile_definitions(TestMorphAvatar PRIVATE
    MORPHNODE_AVATAR_EXE="$<TARGET_FILE:MorphAvatar>")
  add_dependencies(TestMorphAvatar MorphAvatar)
endif ()
