# Speech: text to viseme weight track, eSpeak NG synthesis included (goal: >= 50x real time).
morphnode_add_benchmark(BenchSpeech ${CMAKE_CURRENT_LIST_DIR}/BenchSpeech.cpp)
