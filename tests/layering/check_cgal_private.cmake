# CGAL stays out of every interface: under core/, only .cpp files and the private
# headers named *_internal.h include CGAL, and no header includes a private one
# (so no CGAL type reaches a header another module or the window reads).
# CORE_DIR: the core/ folder.
file(GLOB_RECURSE headers ${CORE_DIR}/*.h)
set(bad "")
set(private 0)
foreach(f IN LISTS headers)
  get_filename_component(name ${f} NAME)
  file(STRINGS ${f} cgal REGEX "^[ \t]*#[ \t]*include[ \t]*<CGAL/")
  file(STRINGS ${f} internal REGEX "^[ \t]*#[ \t]*include[ \t]*\"[^\"]*_internal\\.h\"")
  if(name MATCHES "_internal\\.h$")
    math(EXPR private "${private} + 1")
  elseif(cgal)
    string(APPEND bad "\n  ${f} includes CGAL: ${cgal}")
  endif()
  if(internal)
    string(APPEND bad "\n  ${f} includes a private header: ${internal}")
  endif()
endforeach()
if(bad)
  message(FATAL_ERROR "CGAL in an interface:${bad}")
endif()
if(private LESS 1)
  message(FATAL_ERROR
    "no *_internal.h header found under ${CORE_DIR}: the scan is broken")
endif()
list(LENGTH headers n)
message(STATUS
  "checked ${n} headers under core/: CGAL only in ${private} private header(s)")
