# Each rank holds only the bond rows it computes (parallel/decomposition.hpp, local rows),
# with the serial program's result:
#  - tests/mpi/impact.yaml without the compression factor (bond-based: a rank computes,
#    and holds, its own particles' rows alone) on 2 ranks: each rank holds less than 60 %
#    of the serial program's bonds and together exactly all of them;
#  - the same deck with HORIZON_MPI_WHOLE_SYSTEM=1 (every rank builds the whole system,
#    as before local rows): every rank holds every bond;
#  - impact.yaml itself (alpha: the neighbours' rows are computed and held too) on 2
#    ranks: each rank holds fewer bonds than the whole system;
#  - the bond-based deck with two precracks (one keeps its bonds as broken): the count
#    of cut bonds the run prints equals the serial program's.
# Every run ends in the serial program's state_crc32.
# cmake -DHORIZON=... -DSERIAL=... -DMPIEXEC=... -DSOURCE=... -DWORK=... -P local_bonds.cmake
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
file(READ ${SOURCE}/tests/mpi/impact.yaml impact)
string(REPLACE "critical_stretch: 0.0005, alpha: 0.25, breaks: after_force" "critical_stretch: 0.0005" bond_based
               "${impact}")
if(bond_based STREQUAL impact)
  message(FATAL_ERROR "tests/mpi/impact.yaml changed: its damage line is no longer the one this test edits")
endif()
file(WRITE ${WORK}/bond_based.yaml "${bond_based}")

# run(label deck ranks [ENV...]): runs it; sets ${label}_summary in the caller.
function(run label deck ranks)
  set(out ${WORK}/${label})
  if(ranks EQUAL 0)
    set(command ${SERIAL} run ${deck} -q -o ${out} --threads 1)
  else()
    set(command ${CMAKE_COMMAND} -E env ${ARGN} ${MPIEXEC} --oversubscribe -n ${ranks} ${HORIZON} run ${deck} -q -o
                ${out} --threads 1)
  endif()
  execute_process(COMMAND ${command} RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${label}: exit ${rc}\n${log}")
  endif()
  file(READ ${out}/summary.json summary)
  set(${label}_summary "${summary}" PARENT_SCOPE)
endfunction()

# check(label serial_label limit_percent): same state_crc32 as the serial run; each rank
# holds at most limit_percent of the bonds; together at least all of them (exactly all
# when exact is set).
function(check label serial limit exact)
  string(JSON crc GET "${${label}_summary}" state_crc32)
  string(JSON serial_crc GET "${${serial}_summary}" state_crc32)
  string(JSON total GET "${${serial}_summary}" bonds)
  string(JSON reported GET "${${label}_summary}" bonds)
  if(NOT crc EQUAL serial_crc)
    message(FATAL_ERROR "${label}: state_crc32 ${crc}, the serial program ${serial_crc}")
  endif()
  if(NOT reported EQUAL total)
    message(FATAL_ERROR "${label}: summary.json counts ${reported} bonds, the serial program ${total}")
  endif()
  set(sum 0)
  set(shares "")
  foreach(k 0 1)
    string(JSON held GET "${${label}_summary}" halo ${k} bonds_held)
    math(EXPR percent "100 * ${held} / ${total}")
    math(EXPR sum "${sum} + ${held}")
    string(APPEND shares " ${held} (${percent} %)")
    if(held GREATER 0 AND percent GREATER limit)
      message(FATAL_ERROR "${label}: rank ${k} holds ${held} of the ${total} bonds (${percent} %), more than ${limit} %")
    endif()
  endforeach()
  if(sum LESS total OR (exact AND NOT sum EQUAL total))
    message(FATAL_ERROR "${label}: the ranks hold ${sum} bonds together, the whole system has ${total}")
  endif()
  message(STATUS "${label}: state_crc32 ${crc} = serial; bonds held per rank of ${total}:${shares}")
endfunction()

run(bond_based_serial ${WORK}/bond_based.yaml 0)
run(bond_based_2 ${WORK}/bond_based.yaml 2)
check(bond_based_2 bond_based_serial 59 TRUE)
run(bond_based_whole_2 ${WORK}/bond_based.yaml 2 HORIZON_MPI_WHOLE_SYSTEM=1)
check(bond_based_whole_2 bond_based_serial 100 FALSE)
string(JSON held GET "${bond_based_whole_2_summary}" halo 1 bonds_held)
string(JSON total GET "${bond_based_serial_summary}" bonds)
if(NOT held EQUAL total)
  message(FATAL_ERROR "HORIZON_MPI_WHOLE_SYSTEM=1: rank 1 holds ${held} bonds, not the whole system's ${total}")
endif()
run(alpha_serial ${SOURCE}/tests/mpi/impact.yaml 0)
run(alpha_2 ${SOURCE}/tests/mpi/impact.yaml 2)
check(alpha_2 alpha_serial 99 FALSE)

# Precracks on local rows: one keeps its bonds as broken, one removes them. The count of
# cut bonds (printed by the run) and the final state equal the serial program's.
string(CONCAT cracked "${bond_based}" "precracks:\n"
       "  - {polygon: [[0.0005, -0.006, 0], [0.0005, 0.001, 0], [0.0005, 0.001, 0.006], [0.0005, -0.006, 0.006]], "
       "bonds: broken}\n"
       "  - {polygon: [[-0.0005, -0.006, -0.006], [-0.0005, 0.001, -0.006], [-0.0005, 0.001, 0], [-0.0005, -0.006, 0]]}\n")
file(WRITE ${WORK}/cracked.yaml "${cracked}")
set(cut_lines "")
foreach(ranks 0 2)
  if(ranks EQUAL 0)
    set(command ${SERIAL} run ${WORK}/cracked.yaml -o ${WORK}/cracked_${ranks} --threads 1)
  else()
    set(command ${MPIEXEC} --oversubscribe -n ${ranks} ${HORIZON} run ${WORK}/cracked.yaml -o ${WORK}/cracked_${ranks}
                --threads 1)
  endif()
  execute_process(COMMAND ${command} RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "cracked, ${ranks} ranks: exit ${rc}\n${log}")
  endif()
  string(REGEX MATCH "bonds +[0-9]+ directed \\([0-9.]+ per particle\\), [0-9]+ cut by precracks" line "${log}")
  string(REGEX MATCH "[0-9]+ cut" cut "${line}")
  if(cut STREQUAL "" OR cut STREQUAL "0 cut")
    message(FATAL_ERROR "cracked, ${ranks} ranks: no bonds cut by the precracks in its report:\n${log}")
  endif()
  file(READ ${WORK}/cracked_${ranks}/summary.json summary)
  string(JSON crc GET "${summary}" state_crc32)
  list(APPEND cut_lines "${line} / state_crc32 ${crc}")
endforeach()
list(GET cut_lines 0 serial_line)
list(GET cut_lines 1 split_line)
if(NOT serial_line STREQUAL split_line)
  message(FATAL_ERROR "precracks on 2 ranks: '${split_line}', the serial program '${serial_line}'")
endif()
message(STATUS "precracks: ${split_line} = serial")
