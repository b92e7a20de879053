# The rig filters from Python.
morphnode_add_python_test(TestMorphRigPython ${CMAKE_CURRENT_SOURCE_DIR}/TestMorphRig.py -v)
set_property(TEST TestMorphRigPython APPEND PROPERTY LABELS rigs)
