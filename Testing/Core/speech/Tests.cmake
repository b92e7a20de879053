# The speech core: .pho, eSpeak NG synthesis, viseme tables, coarticulation, nonverbal
# cues, Rhubarb files. eSpeak NG and its data must be installed (espeak-ng, libespeak-ng-dev).
morphnode_add_core_test(TestCoreSpeech
  ${CMAKE_CURRENT_LIST_DIR}/TestPho.cpp
  ${CMAKE_CURRENT_LIST_DIR}/TestSynthesis.cpp
  ${CMAKE_CURRENT_LIST_DIR}/TestVisemeMap.cpp
  ${CMAKE_CURRENT_LIST_DIR}/TestCoarticulation.cpp
  ${CMAKE_CURRENT_LIST_DIR}/TestNonverbal.cpp
  ${CMAKE_CURRENT_LIST_DIR}/TestRhubarb.cpp)
target_compile_definitions(TestCoreSpeech PRIVATE
  MORPHNODE_TEST_OUTPUT_DIR="${MORPHNODE_TEST_OUTPUT_DIR}")
