# Shared target settings and the layering rule of docs/architecture.md.

set_property(GLOBAL PROPERTY SULCUS_CORE_TARGETS "")

# Warnings for Sulcus's own code; errors when SULCUS_WERROR is on (CI).
function(sulcus_target_defaults target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  if(SULCUS_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# A core module: a library under core/ that may depend on other core modules and
# on engine libraries, never on Qt or VTK.
function(sulcus_core_library target)
  add_library(${target} ${ARGN})
  target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR})
  sulcus_target_defaults(${target})
  set_property(GLOBAL APPEND PROPERTY SULCUS_CORE_TARGETS ${target})
endfunction()

function(_sulcus_collect_links target out_var)
  set(seen ${${out_var}})
  if(NOT TARGET ${target} OR ${target} IN_LIST seen)
    set(${out_var} ${seen} PARENT_SCOPE)
    return()
  endif()
  list(APPEND seen ${target})
  get_target_property(type ${target} TYPE)
  set(links "")
  if(NOT type STREQUAL "INTERFACE_LIBRARY")
    get_target_property(direct ${target} LINK_LIBRARIES)
    if(direct)
      list(APPEND links ${direct})
    endif()
  endif()
  get_target_property(iface ${target} INTERFACE_LINK_LIBRARIES)
  if(iface)
    list(APPEND links ${iface})
  endif()
  foreach(link IN LISTS links)
    string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" link "${link}")
    if(TARGET ${link})
      _sulcus_collect_links(${link} seen)  # records the target itself
    else()
      list(APPEND seen "${link}")
    endif()
  endforeach()
  list(REMOVE_DUPLICATES seen)
  set(${out_var} ${seen} PARENT_SCOPE)
endfunction()

# Fails the configure step if any core target links Qt or VTK, even indirectly.
function(sulcus_check_core_layering)
  get_property(core_targets GLOBAL PROPERTY SULCUS_CORE_TARGETS)
  foreach(target IN LISTS core_targets)
    set(reached "")
    _sulcus_collect_links(${target} reached)
    foreach(link IN LISTS reached)
      if(link MATCHES "^(Qt5|Qt6|Qt)::|^VTK::|^vtk|Qt5(Core|Gui|Widgets)")
        message(FATAL_ERROR
          "Layering violation: core target '${target}' links '${link}'. "
          "core/ must never depend on Qt or VTK (see docs/architecture.md); put this code in ui/.")
      endif()
    endforeach()
  endforeach()
endfunction()
