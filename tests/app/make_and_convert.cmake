# `mesh make` writes a solid that `mesh convert` turns into every format, each of
# which `mesh info` accepts as a valid solid with the same face count.
file(MAKE_DIRECTORY ${OUT})
execute_process(COMMAND ${CLI} mesh make sphere --size 4 --detail 2 -o ${OUT}/sphere.off
                RESULT_VARIABLE s OUTPUT_VARIABLE o)
if(NOT s EQUAL 0 OR NOT o MATCHES "320 faces")
  message(FATAL_ERROR "make failed (${s}): ${o}")
endif()
foreach(target sphere.stl sphere.obj sphere.ply)
  execute_process(COMMAND ${CLI} mesh convert ${OUT}/sphere.off ${OUT}/${target} --binary
                  RESULT_VARIABLE s OUTPUT_VARIABLE o ERROR_VARIABLE e)
  if(NOT s EQUAL 0)
    message(FATAL_ERROR "convert to ${target} failed (${s}): ${o}${e}")
  endif()
  execute_process(COMMAND ${CLI} mesh info ${OUT}/${target} RESULT_VARIABLE s OUTPUT_VARIABLE o)
  if(NOT s EQUAL 0 OR NOT o MATCHES "faces +320")
    message(FATAL_ERROR "info on ${target} failed (${s}): ${o}")
  endif()
endforeach()
