# The layers of mfv, lowest first; folders of one layer separated by '|'.
set(MFV_LAYERS "methods/core" "methods|reports" "dynamics|stability" "problems" "analyses"
               "verify" "apps")

# The first of `folders` (sorted longest first) that is a prefix of `path`, or "" in `out`.
function(mfv_owner_folder path folders out)
  foreach(f IN LISTS folders)
    string(LENGTH "${f}/" n)
    string(SUBSTRING "${path}" 0 ${n} head)
    if(head STREQUAL "${f}/")
      set(${out} ${f} PARENT_SCOPE)
      return()
    endif()
  endforeach()
  set(${out} "" PARENT_SCOPE)
endfunction()

# mfv_check_layers(<root> <layer> ...): each argument after the root is one layer, lowest
# first, given as a |-separated list of folders. A source or header in a folder may include headers of its own
# layer and of the layers below; an #include "<folder>/..." of a higher layer stops the
# configure step with the file and the rule. Run at every configure; the ctest `layers`
# re-checks the tree on every test run (script mode: cmake -DROOT=<tree> -P CheckLayers.cmake).
function(mfv_check_layers root)
  set(rank 0)
  set(all_folders)
  foreach(layer IN LISTS ARGN)
    string(REPLACE "|" ";" folders "${layer}")
    foreach(folder IN LISTS folders)
      set(rank_of_${folder} ${rank})
      list(APPEND all_folders ${folder})
    endforeach()
    math(EXPR rank "${rank} + 1")
  endforeach()
  # Longest folder first, so methods/core matches before methods.
  list(SORT all_folders COMPARE STRING ORDER DESCENDING)
  set(violations)
  foreach(folder IN LISTS all_folders)
    # Re-globbed at every build (CONFIGURE_DEPENDS), so a new file is checked too; script mode
    # (the ctest) globs once.
    set(depends CONFIGURE_DEPENDS)
    if(CMAKE_SCRIPT_MODE_FILE)
      set(depends "")
    endif()
    file(GLOB_RECURSE sources ${depends} "${root}/${folder}/*.hpp" "${root}/${folder}/*.cpp")
    foreach(source IN LISTS sources)
      file(RELATIVE_PATH rel "${root}" "${source}")
      mfv_owner_folder("${rel}" "${all_folders}" owner)
      if(NOT owner STREQUAL folder)
        continue()
      endif()
      file(STRINGS "${source}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"[^\"]+\"")
      foreach(line IN LISTS includes)
        string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\".*" "\\1" target "${line}")
        mfv_owner_folder("${target}" "${all_folders}" target_owner)
        if(target_owner STREQUAL "")
          continue()
        endif()
        if(${rank_of_${target_owner}} GREATER ${rank_of_${owner}})
          list(APPEND violations "${rel} includes \"${target}\" (${target_owner} is above ${owner})")
        endif()
      endforeach()
    endforeach()
  endforeach()
  if(violations)
    list(JOIN violations "\n  " text)
    message(FATAL_ERROR "mfv layering: a header of a higher layer is included from a lower one "
                        "(see CMakeLists.txt for the order); move the code to the layer it "
                        "belongs to:\n  ${text}")
  endif()
endfunction()

# Script mode: check the tree at ROOT.
if(CMAKE_SCRIPT_MODE_FILE AND DEFINED ROOT)
  mfv_check_layers("${ROOT}" ${MFV_LAYERS})
  message(STATUS "mfv layering: no file includes a header of a higher layer")
endif()
