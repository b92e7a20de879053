# The behaviour control (VTK-free): idle behaviour, gestures, moods, speech scheduling,
# the blackboard and the script parser. See docs/behavior.md.
target_sources(MorphNodeCore PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/BehaviorTypes.cpp
  ${CMAKE_CURRENT_LIST_DIR}/Timeline.cpp
  ${CMAKE_CURRENT_LIST_DIR}/IdleSchedule.cpp
  ${CMAKE_CURRENT_LIST_DIR}/Blackboard.cpp
  ${CMAKE_CURRENT_LIST_DIR}/BehaviorScript.cpp
  ${CMAKE_CURRENT_LIST_DIR}/BehaviorController.cpp)
