# Unit tests of the behaviour control (idle behaviour, gestures, moods, speech, scripts).
morphnode_add_core_test(TestCoreBehavior
  ${CMAKE_CURRENT_LIST_DIR}/TestBehaviorIdle.cpp
  ${CMAKE_CURRENT_LIST_DIR}/TestBehaviorController.cpp
  ${CMAKE_CURRENT_LIST_DIR}/TestBehaviorScript.cpp)
