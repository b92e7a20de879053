# The behaviour script parser (text and JSON formats of docs/behavior.md).
morphnode_add_fuzz_target(fuzz_script ${CMAKE_CURRENT_LIST_DIR}/fuzz_script.cpp ${CMAKE_CURRENT_LIST_DIR}/corpus/script)
