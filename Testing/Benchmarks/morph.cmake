# The morph-stage suite: a harness reporting ratios measured in one run (see
# docs/benchmarks.md). `BenchMorph --markdown build-bench/benchmarks-latest.md` writes the
# figures that docs/benchmarks.md carries verbatim (the one place for them).
add_executable(BenchMorph ${CMAKE_CURRENT_LIST_DIR}/BenchMorph.cxx)
target_link_libraries(BenchMorph PRIVATE MorphNode::MorphNode MorphNode::Core
  VTK::CommonCore VTK::CommonDataModel Threads::Threads)
target_compile_definitions(BenchMorph PRIVATE MORPHNODE_FACEKIT_DIR="${MORPHNODE_FACEKIT_DIR}")
add_test(NAME BenchMorph.smoke COMMAND BenchMorph --smoke)
set_tests_properties(BenchMorph.smoke PROPERTIES LABELS benchmark-smoke)
