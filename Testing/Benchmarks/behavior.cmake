# The behaviour control: samples per second of the whole behaviour state (target >= 100k).
morphnode_add_benchmark(BenchBehavior ${CMAKE_CURRENT_LIST_DIR}/BenchBehavior.cpp)
