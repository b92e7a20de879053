# More parser fuzz targets (rig JSON, OBJ, viseme table, weight track CSV): a replay test
# of each seed corpus always, a <name>_libfuzzer binary with MORPHNODE_BUILD_FUZZERS=ON
# and clang. Included from CMakeLists.txt, which defines morphnode_add_fuzz_target.
morphnode_add_fuzz_target(FuzzRig ${CMAKE_CURRENT_LIST_DIR}/FuzzRig.cpp
  ${CMAKE_CURRENT_LIST_DIR}/corpus/rig)
morphnode_add_fuzz_target(FuzzObj ${CMAKE_CURRENT_LIST_DIR}/FuzzObj.cpp
  ${CMAKE_CURRENT_LIST_DIR}/corpus/obj)
morphnode_add_fuzz_target(FuzzVisemeTable ${CMAKE_CURRENT_LIST_DIR}/FuzzVisemeTable.cpp
  ${CMAKE_CURRENT_LIST_DIR}/corpus/viseme_table)
morphnode_add_fuzz_target(FuzzWeightTrackCsv ${CMAKE_CURRENT_LIST_DIR}/FuzzWeightTrackCsv.cpp
  ${CMAKE_CURRENT_LIST_DIR}/corpus/weight_track)
