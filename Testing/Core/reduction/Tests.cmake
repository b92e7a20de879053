# Scalable avatars: animation-aware reduction and the frame-budget controller.
morphnode_add_core_test(TestCoreReduction
  ${CMAKE_CURRENT_LIST_DIR}/TestAnimationAwareReduction.cpp
  ${CMAKE_CURRENT_LIST_DIR}/TestFrameBudgetController.cpp)
