# Build a plugin against Debian's paraview-dev WITHOUT python3-paraview installed.
#
# python3-paraview conflicts with python3-vtk9 (both ship `vtkmodules`), which MorphNode
# needs, so it cannot be installed here. Two things of it are needed all the same:
#
# 1. At configure time: files it holds are referenced by paraview-dev's CMake package
#    (see morphnode_stub_paraview_python_targets below).
# 2. At build time: the wrapping hierarchy files of ParaView's VTK and ParaView modules,
#    lib/<arch>/vtk/hierarchy/ParaView/*-hierarchy.txt, which the client-server wrapping
#    of the plugin's module reads; Debian ships them in python3-paraview, not in
#    paraview-dev (see morphnode_redirect_paraview_hierarchy below). The package
#    extracted with `dpkg -x` into a private prefix provides them.
#
# --- 1. ------------------------------------------------------------------------------
#
# paraview-dev's CMake package imports files of python3-paraview: the Python extension
# modules of ParaView and of its VTK (VTKPython-targets.cmake,
# ParaViewPython-targets.cmake) and /usr/bin/pvpython (ParaViewTools-targets.cmake). CMake's generated import files stop with a fatal error
# when an imported file is missing ("The imported target VTK::vtkCommonCorePython
# references the file .../vtkmodules/vtkCommonCore.so but this file does not exist").
#
# The plugin uses none of these targets. A generated import file returns early, without
# checking anything, when every target it would define already exists. So, for each of
# those import files that references a missing file, this defines its targets
# beforehand: an executable whose file exists becomes an IMPORTED executable at that
# location (pvbatch, pvserver, ... stay usable), everything else an empty INTERFACE
# IMPORTED target. When python3-paraview is installed, nothing is stubbed.

# Parses the generated <dir>/<Name>-targets.cmake and its <Name>-targets-<config>.cmake:
# sets <prefix>_targets (all targets), <prefix>_location_<target as C identifier> (the
# imported file, with the install prefix computed as the import file computes it) and
# <prefix>_missing (TRUE when some imported file does not exist).
function (_morphnode_read_import_file targets_file prefix)
  file(STRINGS "${targets_file}" expected REGEX "^foreach\\(_cmake_expected_target IN ITEMS ")
  if (NOT expected MATCHES "IN ITEMS ([^)]+)\\)")
    message(FATAL_ERROR "MorphNode: cannot read the targets of ${targets_file}")
  endif ()
  string(REPLACE " " ";" targets "${CMAKE_MATCH_1}")
  set("${prefix}_targets" "${targets}" PARENT_SCOPE)
  file(STRINGS "${targets_file}" executables REGEX "^add_executable\\(")
  set("${prefix}_executables" "${executables}" PARENT_SCOPE)

  file(STRINGS "${targets_file}" prefix_lines REGEX "^get_filename_component\\(_IMPORT_PREFIX ")
  foreach (line IN LISTS prefix_lines)
    # (cmake_language(EVAL) would see this file as CMAKE_CURRENT_LIST_FILE)
    string(REPLACE "\${CMAKE_CURRENT_LIST_FILE}" "${targets_file}" line "${line}")
    cmake_language(EVAL CODE "${line}")
  endforeach ()
  if (_IMPORT_PREFIX STREQUAL "/")
    set(_IMPORT_PREFIX "")
  endif ()

  set(missing FALSE)
  get_filename_component(dir "${targets_file}" DIRECTORY)
  get_filename_component(base "${targets_file}" NAME_WE)
  file(GLOB config_files "${dir}/${base}-*.cmake")
  foreach (config_file IN LISTS config_files)
    file(STRINGS "${config_file}" checks REGEX "^list\\(APPEND _cmake_import_check_files_for_")
    foreach (line IN LISTS checks)
      if (line MATCHES "_cmake_import_check_files_for_([^ ]+) \"([^\"]+)\"")
        set(target "${CMAKE_MATCH_1}")
        string(REPLACE "\${_IMPORT_PREFIX}" "${_IMPORT_PREFIX}" path "${CMAKE_MATCH_2}")
        string(MAKE_C_IDENTIFIER "${target}" key)
        set("${prefix}_location_${key}" "${path}" PARENT_SCOPE)
        if (NOT EXISTS "${path}")
          set(missing TRUE)
        endif ()
      endif ()
    endforeach ()
  endforeach ()
  set("${prefix}_missing" "${missing}" PARENT_SCOPE)
endfunction ()

function (_morphnode_stub_import_file targets_file)
  if (NOT EXISTS "${targets_file}")
    return ()
  endif ()
  _morphnode_read_import_file("${targets_file}" _imp)
  if (NOT _imp_missing)
    return ()
  endif ()
  set(stubbed 0)
  foreach (target IN LISTS _imp_targets)
    if (TARGET "${target}")
      continue ()
    endif ()
    string(MAKE_C_IDENTIFIER "${target}" key)
    set(location "${_imp_location_${key}}")
    string(FIND "${_imp_executables}" "add_executable(${target} IMPORTED)" is_executable)
    if (location AND EXISTS "${location}" AND NOT is_executable EQUAL -1)
      add_executable("${target}" IMPORTED)
      set_target_properties("${target}" PROPERTIES IMPORTED_LOCATION "${location}")
    else ()
      add_library("${target}" INTERFACE IMPORTED)
      math(EXPR stubbed "${stubbed} + 1")
    endif ()
  endforeach ()
  get_filename_component(name "${targets_file}" NAME)
  message(STATUS "MorphNode: ${name} imports files of python3-paraview, which is not "
    "installed; defined its targets beforehand (${stubbed} as empty stubs, unused by the plugin)")
endfunction ()

# Defines the targets of ParaView's import files that reference missing files.
function (morphnode_stub_paraview_python_targets paraview_dir)
  _morphnode_stub_import_file("${paraview_dir}/vtk/VTKPython-targets.cmake")
  _morphnode_stub_import_file("${paraview_dir}/ParaViewPython-targets.cmake")
  _morphnode_stub_import_file("${paraview_dir}/ParaViewTools-targets.cmake")
endfunction ()

# --- 2. ------------------------------------------------------------------------------
# Points the INTERFACE_vtk_module_hierarchy property of every imported VTK:: / ParaView::
# module whose hierarchy file is missing at the file of the same name in <hierarchy_dir>
# (e.g. <python3-paraview extracted>/usr/lib/<arch>/vtk/hierarchy/ParaView). Fails when
# a module the plugin's module wraps against has no hierarchy file anywhere.
function (morphnode_redirect_paraview_hierarchy hierarchy_dir)
  get_property(imported DIRECTORY PROPERTY IMPORTED_TARGETS)
  set(redirected 0)
  set(unresolved)
  foreach (target IN LISTS imported)
    if (NOT target MATCHES "^(VTK|ParaView)::")
      continue ()
    endif ()
    get_property(type TARGET "${target}" PROPERTY TYPE)
    if (type STREQUAL "EXECUTABLE")
      continue ()
    endif ()
    get_property(hierarchy TARGET "${target}" PROPERTY INTERFACE_vtk_module_hierarchy)
    if (NOT hierarchy OR EXISTS "${hierarchy}")
      continue ()
    endif ()
    get_filename_component(name "${hierarchy}" NAME)
    if (hierarchy_dir AND EXISTS "${hierarchy_dir}/${name}")
      set_property(TARGET "${target}" PROPERTY INTERFACE_vtk_module_hierarchy
        "${hierarchy_dir}/${name}")
      math(EXPR redirected "${redirected} + 1")
    else ()
      list(APPEND unresolved "${target}")
    endif ()
  endforeach ()
  if (redirected)
    message(STATUS "MorphNode: wrapping hierarchy files of ${redirected} ParaView modules "
      "taken from ${hierarchy_dir}")
  endif ()
  set(morphnode_unresolved_hierarchies "${unresolved}" PARENT_SCOPE)
endfunction ()
