# Static and implicit solves split over MPI ranks (docs/design.md "Static and implicit
# solves on several ranks"), each deck on several ranks and with the serial program:
#   - tests/mpi/static.yaml: 3-D LPS block, 2,000 particles, Newton with the matrix-free
#     CG on distributed vectors;
#   - tests/mpi/static_bar.yaml: 1-D PMB bar in tension, the same solver, against the
#     analytic strain and tip displacement;
#   - the bar with ADR, and under implicit dynamics (Newmark); the bar on 2 and 3 ranks,
#     its variants on 1 and 3;
#   - a bond_pair plate by ADR on 1 and 3 ranks (the whole system on every rank, the
#     model's pass split): the serial program's field bit for bit.
# On more than one rank each rank holds only its bond rows (local rows: fewer bonds than
# the whole system, summary.json bonds_held).
# Required: the same history.csv, state_crc32 and displacement field on every rank count,
# bit for bit; that field within 1e-8 (Newton, Newmark) or 1e-6 (ADR, tolerance 1e-6) of
# the serial program's (tests/mpi/static_check.py). And clear errors on 2 ranks for an
# assembled tangent (linear_solver cholesky), naming matrix_free instead.
# cmake -DHORIZON=horizon-mpi -DSERIAL=horizon -DMPIEXEC=... -DPYTHON=... -DSOURCE=... -DWORK=... -P static.cmake
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
if(NOT PYTHON)
  set(PYTHON python3)
endif()

# Runs `deck` serially and on each rank count of `counts`; fails unless history.csv and state_crc32 are
# the same on all rank counts, then runs static_check.py `mode` `tolerance` on the frames.
# A sixth argument `whole`: the deck keeps the whole system on every rank (structures), so
# the local-rows check is skipped.
function(check_deck tag deck mode tolerance counts)
  execute_process(COMMAND ${SERIAL} run ${deck} -q -o ${WORK}/${tag}_serial --threads 1
                  RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${tag}, serial program: exit ${rc}\n${log}")
  endif()
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
    # Local rows (parallel/decomposition.hpp): on more than one rank each rank holds fewer
    # bonds than the whole system, and together at least all of them.
    if(ranks GREATER 1 AND NOT "${ARGV5}" STREQUAL "whole")
      string(JSON total GET "${summary}" bonds)
      set(sum 0)
      set(shares "")
      math(EXPR last "${ranks} - 1")
      foreach(k RANGE ${last})
        string(JSON held GET "${summary}" bonds_held ${k})
        if(NOT held LESS total)
          message(FATAL_ERROR "${tag} on ${ranks} ranks: rank ${k} holds ${held} of the ${total} bonds (local rows expected)")
        endif()
        math(EXPR sum "${sum} + ${held}")
        string(APPEND shares " ${held}")
      endforeach()
      if(sum LESS total)
        message(FATAL_ERROR "${tag} on ${ranks} ranks: the ranks hold ${sum} bonds together, fewer than the ${total} of the system")
      endif()
      message(STATUS "${tag} on ${ranks} ranks: bonds held${shares} of ${total}")
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
  execute_process(COMMAND ${PYTHON} ${SOURCE}/tests/mpi/static_check.py ${mode} ${tolerance}
                          ${WORK}/${tag}_serial/frames/frame_00001.vtu ${frames}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
  message(STATUS "${tag}:\n${log}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${tag}: static_check.py failed (exit ${rc})")
  endif()
endfunction()

check_deck(block ${SOURCE}/tests/mpi/static.yaml field 1e-8 "1;2;3")
# The block with the whole system on every rank (HORIZON_MPI_WHOLE_SYSTEM=1, as before
# local rows): the same history.csv and state_crc32 as with local rows.
execute_process(COMMAND ${CMAKE_COMMAND} -E env HORIZON_MPI_WHOLE_SYSTEM=1 ${MPIEXEC} --oversubscribe -n 2 ${HORIZON} run
                        ${SOURCE}/tests/mpi/static.yaml -q -o ${WORK}/block_whole --threads 1
                RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "block, whole system on 2 ranks: exit ${rc}\n${log}")
endif()
file(READ ${WORK}/block_whole/summary.json whole_summary)
file(READ ${WORK}/block_n2/summary.json local_summary)
string(JSON whole_crc GET "${whole_summary}" state_crc32)
string(JSON local_crc GET "${local_summary}" state_crc32)
string(JSON whole_held GET "${whole_summary}" bonds_held 0)
string(JSON total GET "${whole_summary}" bonds)
file(READ ${WORK}/block_whole/history.csv whole_history)
file(READ ${WORK}/block_n2/history.csv local_history)
if(NOT whole_crc EQUAL local_crc OR NOT whole_history STREQUAL local_history OR NOT whole_held EQUAL total)
  message(FATAL_ERROR "block on 2 ranks: the whole system (state_crc32 ${whole_crc}, rank 0 holds ${whole_held} of "
                      "${total} bonds) differs from local rows (${local_crc}) or does not hold every bond")
endif()
message(STATUS "block on 2 ranks, whole system on every rank: state_crc32 ${whole_crc} as with local rows")
check_deck(bar ${SOURCE}/tests/mpi/static_bar.yaml bar 1e-8 "2;3")
file(READ ${SOURCE}/tests/mpi/static_bar.yaml text)
string(REPLACE "method: newton, linear_solver: matrix_free, tolerance: 1.0e-12" "method: adr, tolerance: 1.0e-6" adr "${text}")
file(WRITE ${WORK}/bar_adr.yaml "${adr}")
check_deck(bar_adr ${WORK}/bar_adr.yaml bar_adr 1e-6 "1;3")
# Implicit dynamics (Newmark, Newton with the matrix-free CG on the shifted tangent):
# the bar under the suddenly applied load, 10 steps of 2 us, frame at the end.
string(REPLACE "type: static, method: newton, linear_solver: matrix_free, tolerance: 1.0e-12"
               "type: implicit_dynamic, time_step: 2.0e-6, end_time: 2.0e-5, linear_solver: matrix_free, tolerance: 1.0e-10"
               newmark "${text}")
string(REPLACE "frames: 1}" "frames: 1, history_every: 1}" newmark "${newmark}")
file(WRITE ${WORK}/bar_newmark.yaml "${newmark}")
check_deck(bar_newmark ${WORK}/bar_newmark.yaml field 1e-8 "1;3")

# A structure (model bond_pair, a plate of examples/plate_navier.yaml at 0.05 m spacing,
# 21 x 21 nodes, simply supported on four edges, uniform pressure) solved by ADR on ranks:
# the model's split force pass, its tangent's owned rows gathered for the fictitious mass
# (solver/adr.cpp). The damping is fixed from the lowest eigenvalue, so no sum is split
# and the field equals the serial program's bit for bit (tolerance 0).
file(READ ${SOURCE}/examples/plate_navier.yaml plate)
string(REPLACE "spacing: 0.0125" "spacing: 0.05" plate_adr "${plate}")
string(REPLACE "method: newton, tangent: analytic, linear_solver: cholesky, tolerance: 1.0e-10"
               "method: adr, tolerance: 1.0e-8" plate_adr "${plate_adr}")
if(NOT plate_adr MATCHES "spacing: 0.05" OR NOT plate_adr MATCHES "method: adr")
  message(FATAL_ERROR "examples/plate_navier.yaml changed: its spacing or solver line is no longer the one this test edits")
endif()
file(WRITE ${WORK}/plate_adr.yaml "${plate_adr}")
check_deck(plate_adr ${WORK}/plate_adr.yaml field 0 "1;3" whole)

# What is not split: a clear error naming what to use instead (an assembled tangent;
# Newmark with linear_solver cg gets the same message).
string(REPLACE "linear_solver: matrix_free" "linear_solver: cholesky" cholesky "${text}")
file(WRITE ${WORK}/cholesky.yaml "${cholesky}")
execute_process(COMMAND ${MPIEXEC} --oversubscribe -n 2 ${HORIZON} run ${WORK}/cholesky.yaml -q -o ${WORK}/cholesky
                RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
set(expected "solver.linear_solver cholesky assembles the whole tangent on one rank; on several ranks use linear_solver: matrix_free")
if(rc EQUAL 0 OR NOT log MATCHES "cannot run on 2 MPI ranks yet" OR NOT log MATCHES "${expected}")
  message(FATAL_ERROR "cholesky on 2 ranks: expected the error '${expected}', got exit ${rc}\n${log}")
endif()
message(STATUS "cholesky on 2 ranks refused as expected")
# A structure solved statically by Newton (examples/plate_navier.yaml, model bond_pair,
# cholesky): its tangent is not the unified form's, so only ADR splits it; the error says so.
execute_process(COMMAND ${MPIEXEC} --oversubscribe -n 2 ${HORIZON} run ${SOURCE}/examples/plate_navier.yaml -q
                        -o ${WORK}/plate RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(rc EQUAL 0 OR NOT log MATCHES "cannot run on 2 MPI ranks yet: static and implicit solves are split over ranks for the unified models only")
  message(FATAL_ERROR "a static structure on 2 ranks: expected the unified-models error, got exit ${rc}\n${log}")
endif()
message(STATUS "a static structure on 2 ranks refused as expected")
