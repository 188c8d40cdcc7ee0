# qp-gen writes each kind; qp-bench solves it with zero failures, prints the
# machine-readable line with every field, and writes every frame's solution
# (6 float64 per frame) where --solutions asks.
file(MAKE_DIRECTORY ${OUT})
foreach(kind slot wedge plane cluster random)
  execute_process(COMMAND ${CLI} qp-gen ${kind} --m 32 --sequences 3 --frames 40 -o ${OUT}/${kind}.qp
                  RESULT_VARIABLE s OUTPUT_VARIABLE o ERROR_VARIABLE e)
  if(NOT s EQUAL 0)
    message(FATAL_ERROR "qp-gen ${kind} failed (${s}): ${o}${e}")
  endif()
  file(REMOVE ${OUT}/${kind}.sol)
  execute_process(COMMAND ${CLI} qp-bench ${OUT}/${kind}.qp --solutions ${OUT}/${kind}.sol
                  RESULT_VARIABLE s OUTPUT_VARIABLE o ERROR_VARIABLE e)
  if(NOT s EQUAL 0 OR NOT o MATCHES "qp-bench frames=120 median_us=[0-9.]+ p99_us=[0-9.]+ max_us=[0-9.]+ mean_iters=[0-9.]+ max_iters=[0-9]+ failures=0 mean_active=[0-9.]+\n")
    message(FATAL_ERROR "qp-bench ${kind} (${s}): ${o}${e}")
  endif()
  file(SIZE ${OUT}/${kind}.sol size)
  if(NOT size EQUAL 5760)  # 120 frames x 6 x 8 bytes
    message(FATAL_ERROR "qp-bench ${kind} --solutions wrote ${size} bytes, expected 5760")
  endif()
endforeach()
