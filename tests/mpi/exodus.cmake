# The Exodus output (output.format: exodus; driver/exodus_output.hpp) on MPI ranks: rank 0
# writes it from every particle streamed to it in global order, so the file is the same
# bytes as the serial program's:
#  - tests/mpi/bar_local.yaml (explicit, local particles, a crack) on 2 and 3 ranks;
#  - tests/mpi/static.yaml (Newton on distributed vectors) on 2 ranks, against 1 MPI rank.
# cmake -DHORIZON=... -DSERIAL=... -DMPIEXEC=... -DSOURCE=... -DWORK=... -P exodus.cmake
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

# deck(name source end_time): the source deck with Exodus output (and a shorter run).
function(deck name source)
  file(READ ${SOURCE}/tests/mpi/${source} text)
  string(REGEX REPLACE "\noutput: [^\n]*" "\noutput: {directory: out, frames: 4, history_every: 10, format: exodus, exodus_file: run.e}" text "${text}")
  string(REPLACE "end_time: 4.0e-5" "end_time: 1.5e-5" text "${text}")
  file(WRITE ${WORK}/${name}.yaml "${text}")
endfunction()

# run(label deck ranks): the run's Exodus file at ${WORK}/${label}/run.e.
function(run label deck ranks)
  set(out ${WORK}/${label})
  if(ranks EQUAL 0)
    set(command ${SERIAL} run ${WORK}/${deck}.yaml -q -o ${out} --threads 1)
  else()
    set(command ${MPIEXEC} --oversubscribe -n ${ranks} ${HORIZON} run ${WORK}/${deck}.yaml -q -o ${out} --threads 1)
  endif()
  execute_process(COMMAND ${command} RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${label}: exit ${rc}\n${log}")
  endif()
  if(NOT EXISTS ${out}/run.e)
    message(FATAL_ERROR "${label}: no ${out}/run.e")
  endif()
endfunction()

# same(label reference): run.e of the two runs the same bytes.
function(same label serial)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/${label}/run.e ${WORK}/${serial}/run.e
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${label}: run.e differs from the serial program's")
  endif()
  message(STATUS "${label}: run.e the same bytes as ${serial}")
endfunction()

deck(bar bar_local.yaml)
run(bar_serial bar 0)
run(bar_2 bar 2)
run(bar_3 bar 3)
same(bar_2 bar_serial)
same(bar_3 bar_serial)

# The distributed Newton's sums run in another order than the serial program's (its
# displacements agree to 1e-8 there: static.cmake); on 1 and 2 MPI ranks they are the
# same bits, and so is the file.
deck(static static.yaml)
run(static_1 static 1)
run(static_2 static 2)
same(static_2 static_1)
