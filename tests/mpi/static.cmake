# A static solve split over MPI ranks (docs/design.md "Static solves on several ranks"):
# tests/mpi/static.yaml (LPS block, 2,000 particles, Newton with the matrix-free CG on
# distributed vectors) on 1, 2 and 3 ranks: the same state_crc32, history.csv and
# displacement field, bit for bit; that field within 1e-8 of the serial program's and its
# elongation against the analytic sigma L / E (tests/mpi/static_check.py). ADR on 1 and 2
# ranks: the same bits. And clear errors on 2 ranks for what is not split: an assembled
# tangent (linear_solver cholesky) and the implicit dynamic solver.
# cmake -DHORIZON=horizon-mpi -DSERIAL=horizon -DMPIEXEC=... -DPYTHON=... -DSOURCE=... -DWORK=... -P static.cmake
set(deck ${SOURCE}/tests/mpi/static.yaml)
file(REMOVE_RECURSE ${WORK})
if(NOT PYTHON)
  set(PYTHON python3)
endif()
execute_process(COMMAND ${SERIAL} run ${deck} -q -o ${WORK}/serial --threads 1
                RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "serial run: exit ${rc}\n${log}")
endif()

# Runs `deck` on each rank count of `counts`; fails unless history.csv and state_crc32 are
# the same on all; sets `frames` to the last frame of each run.
function(run_on_ranks tag deck counts)
  set(reference "")
  set(frames "")
  foreach(ranks ${counts})
    set(out ${WORK}/${tag}_n${ranks})
    execute_process(COMMAND ${MPIEXEC} --oversubscribe -n ${ranks} ${HORIZON} run ${deck} -q -o ${out} --threads 1
                    RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${tag} on ${ranks} ranks: exit ${rc}\n${log}")
    endif()
    file(READ ${out}/history.csv history)
    file(READ ${out}/summary.json summary)
    string(JSON crc GET "${summary}" state_crc32)
    string(JSON nranks GET "${summary}" ranks)
    string(JSON status GET "${summary}" status)
    string(JSON iterations GET "${summary}" solver iterations)
    string(JSON linear GET "${summary}" solver linear_iterations)
    if(NOT nranks EQUAL ranks OR NOT status STREQUAL "completed")
      message(FATAL_ERROR "${tag} on ${ranks} ranks: summary.json says ${nranks} ranks, status ${status}")
    endif()
    set(result "${history}\n${crc}")
    if(reference STREQUAL "")
      set(reference "${result}")
    elseif(NOT result STREQUAL reference)
      file(WRITE ${WORK}/${tag}_expected.txt "${reference}")
      file(WRITE ${WORK}/${tag}_found.txt "${result}")
      message(FATAL_ERROR "${tag} on ${ranks} ranks differs from 1 rank: see ${WORK}/${tag}_expected.txt and found.txt")
    endif()
    message(STATUS "${tag} on ${ranks} ranks: state_crc32 ${crc}, ${iterations} iterations, ${linear} CG iterations")
    list(APPEND frames ${out}/frames/frame_00001.vtu)
  endforeach()
  set(frames "${frames}" PARENT_SCOPE)
endfunction()

run_on_ranks(newton ${deck} "1;2;3")
execute_process(COMMAND ${PYTHON} ${SOURCE}/tests/mpi/static_check.py ${WORK}/serial/frames/frame_00001.vtu ${frames}
                RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
message(STATUS "${log}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "static_check.py failed (exit ${rc})")
endif()

# ADR (distributed vectors, GridSum damping quotient): the same bits on 1 and 2 ranks.
file(READ ${deck} text)
string(REPLACE "method: newton, linear_solver: matrix_free, tolerance: 1.0e-12" "method: adr, tolerance: 1.0e-6" adr "${text}")
file(WRITE ${WORK}/adr.yaml "${adr}")
run_on_ranks(adr ${WORK}/adr.yaml "1;2")

# What is not split: a clear error naming what to use instead.
foreach(case "cholesky;linear_solver: cholesky;linear_solver: matrix_free"
             "newmark;assembles|Newmark;type: implicit_dynamic, time_step: 1.0e-7, end_time: 2.0e-7, linear_solver: cg")
  list(GET case 0 tag)
  list(GET case 1 expected)
  list(GET case 2 replacement)
  if(tag STREQUAL "cholesky")
    string(REPLACE "linear_solver: matrix_free" "linear_solver: cholesky" bad "${text}")
  else()
    string(REPLACE "type: static, method: newton, linear_solver: matrix_free, tolerance: 1.0e-12" "${replacement}" bad "${text}")
  endif()
  file(WRITE ${WORK}/${tag}.yaml "${bad}")
  execute_process(COMMAND ${MPIEXEC} --oversubscribe -n 2 ${HORIZON} run ${WORK}/${tag}.yaml -q -o ${WORK}/${tag}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
  if(rc EQUAL 0 OR NOT log MATCHES "cannot run on 2 MPI ranks yet")
    message(FATAL_ERROR "${tag} on 2 ranks: expected a clear error, got exit ${rc}\n${log}")
  endif()
  if(tag STREQUAL "cholesky" AND NOT log MATCHES "use linear_solver: matrix_free")
    message(FATAL_ERROR "cholesky on 2 ranks: the error must say what to use instead\n${log}")
  endif()
  if(tag STREQUAL "newmark" AND NOT log MATCHES "Newmark")
    message(FATAL_ERROR "implicit dynamics on 2 ranks: the error must name the solver\n${log}")
  endif()
  message(STATUS "${tag} on 2 ranks refused as expected")
endforeach()
