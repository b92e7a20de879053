# cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DPYTHON=... [-DCONSUMER_FLAGS=...] -P RunInstallTest.cmake
# Installs the build into WORK_DIR/prefix, builds a consumer project against it with
# find_package(MorphNode), runs it, and imports the installed Python package.
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if (NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif ()
  message(STATUS "${out}")
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}")
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/Testing/Install/Consumer" -B "${WORK_DIR}/consumer"
  -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release
  "-DCMAKE_CXX_FLAGS=${CONSUMER_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${CONSUMER_FLAGS}")
run(${CMAKE_COMMAND} --build "${WORK_DIR}/consumer")
set(ENV{LD_LIBRARY_PATH} "${prefix}/lib:$ENV{LD_LIBRARY_PATH}")
run("${WORK_DIR}/consumer/consumer")
if (PYTHON)
  file(GLOB_RECURSE init "${prefix}/*.py")
  list(FILTER init INCLUDE REGEX "/morphnode/__init__.py$")
  list(LENGTH init found)
  if (NOT found EQUAL 1)
    message(FATAL_ERROR "expected one installed morphnode/__init__.py, found: ${init}")
  endif ()
  get_filename_component(package_dir "${init}" DIRECTORY)
  get_filename_component(site_dir "${package_dir}" DIRECTORY)
  set(ENV{PYTHONPATH} "${site_dir}")
  run("${PYTHON}" -c "from morphnode import vtkMorphNodeFilter; f = vtkMorphNodeFilter(); print(f.GetClassName(), f.GetWeightModeAsString())")
endif ()
