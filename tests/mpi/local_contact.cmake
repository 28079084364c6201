# Local particles with short-range contact and checkpoints (parallel/decomposition.hpp:
# each rank holds only the particles it reads; the contact partners it does not hold come
# as contact ghosts outside its system):
#  - tests/mpi/bar_contact.yaml (two PMB bars 4 mm apart, no bond between them, thrown
#    at each other: contact across the gap, bonds break) on 1, 2, 3 and 4 ranks:
#    state_crc32 equal to the serial program's; on 2 to 4 ranks local particles; on 4
#    ranks each rank holds at most 50 % of the particles with its contact ghosts (the
#    most it held), the ranks own every particle once, contact ghosts were held and
#    chosen again during the run; history.csv on 4 ranks the same bytes as with
#    HORIZON_MPI_LOCAL_PARTICLES=0 (every particle on every rank);
#  - a checkpoint at step 200 written on 3 ranks with local particles: the same bytes as
#    the checkpoint of HORIZON_MPI_LOCAL_PARTICLES=0 (every record gathered from the
#    owners by global id); writing it changes nothing (state_crc32 and history.csv of the
#    run without one; rank 0 took it from the owners in windows of a few hundred ids);
#    restarted on 2 and 4 ranks with local particles (each rank reads its particles' and
#    rows' entries; every rank holds fewer than all), it ends in the uninterrupted run's
#    history.csv and state_crc32;
#  - rank 0 unable to open the checkpoint file: every rank stops with its error.
# cmake -DHORIZON=... -DSERIAL=... -DMPIEXEC=... -DSOURCE=... -DWORK=... -P local_contact.cmake
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
set(deck ${SOURCE}/tests/mpi/bar_contact.yaml)

# run(label deck ranks [ENV... --] [OPTIONS...]): runs it; sets ${label}_summary and
# ${label}_history. Arguments before "--" are environment settings, after it options.
function(run label deck ranks)
  set(env "")
  set(options "")
  set(target env)
  foreach(a IN LISTS ARGN)
    if(a STREQUAL "--")
      set(target options)
    else()
      list(APPEND ${target} ${a})
    endif()
  endforeach()
  set(out ${WORK}/${label})
  if(ranks EQUAL 0)
    set(command ${SERIAL} run ${deck} -q -o ${out} --threads 1 ${options})
  else()
    set(command ${CMAKE_COMMAND} -E env ${env} ${MPIEXEC} --oversubscribe -n ${ranks} ${HORIZON} run ${deck} -q -o
                ${out} --threads 1 ${options})
  endif()
  execute_process(COMMAND ${command} RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${label}: exit ${rc}\n${log}")
  endif()
  file(READ ${out}/summary.json summary)
  file(READ ${out}/history.csv history)
  set(${label}_summary "${summary}" PARENT_SCOPE)
  set(${label}_history "${history}" PARENT_SCOPE)
endfunction()

function(same_crc label reference)
  string(JSON crc GET "${${label}_summary}" state_crc32)
  string(JSON expected GET "${${reference}_summary}" state_crc32)
  if(NOT crc EQUAL expected)
    message(FATAL_ERROR "${label}: state_crc32 ${crc}, ${reference} ${expected}")
  endif()
endfunction()

function(same_history label reference)
  if(NOT ${label}_history STREQUAL ${reference}_history)
    file(WRITE ${WORK}/${label}_history.csv "${${label}_history}")
    file(WRITE ${WORK}/${reference}_history.csv "${${reference}_history}")
    message(FATAL_ERROR "${label}: history.csv differs from ${reference}'s (both in ${WORK})")
  endif()
endfunction()

run(serial ${deck} 0)
string(JSON total GET "${serial_summary}" particles)
string(JSON broken GET "${serial_summary}" damage broken_bonds)
if(broken LESS 100)
  message(FATAL_ERROR "the halves must meet hard enough to break bonds: ${broken} broken")
endif()
foreach(ranks 1 2 3 4)
  run(local_${ranks} ${deck} ${ranks})
  same_crc(local_${ranks} serial)
  string(JSON local GET "${local_${ranks}_summary}" particles_local)
  if(ranks GREATER 1 AND NOT local)
    message(FATAL_ERROR "${ranks} ranks: the deck with contact does not hold local particles")
  endif()
  message(STATUS "${ranks} ranks: state_crc32 = serial")
endforeach()

# 4 ranks: what each holds, and that contact ghosts were used and chosen again.
set(owned_sum 0)
set(ghosts_sum 0)
set(shares "")
foreach(k RANGE 3)
  string(JSON held GET "${local_4_summary}" halo ${k} particles_held)
  string(JSON ghosts GET "${local_4_summary}" halo ${k} contact_ghosts_most)
  string(JSON owned GET "${local_4_summary}" halo ${k} particles)
  string(JSON rebuilds GET "${local_4_summary}" halo ${k} ghost_rebuilds)
  math(EXPR percent "100 * (${held} + ${ghosts}) / ${total}")
  math(EXPR owned_sum "${owned_sum} + ${owned}")
  math(EXPR ghosts_sum "${ghosts_sum} + ${ghosts}")
  string(APPEND shares " ${held}+${ghosts} (${percent} %)")
  if(percent GREATER 50)
    message(FATAL_ERROR "4 ranks: rank ${k} holds ${held} particles and up to ${ghosts} contact ghosts of ${total} (${percent} %)")
  endif()
  if(rebuilds LESS 2)
    message(FATAL_ERROR "4 ranks: rank ${k} never chose its ghosts again (${rebuilds}); the test must cover it")
  endif()
endforeach()
if(NOT owned_sum EQUAL total)
  message(FATAL_ERROR "4 ranks: the ranks own ${owned_sum} particles together, the whole system has ${total}")
endif()
if(ghosts_sum EQUAL 0)
  message(FATAL_ERROR "4 ranks: no rank held a contact ghost; the test must cover them")
endif()
message(STATUS "4 ranks: particles held + contact ghosts (most) per rank of ${total}:${shares}")
run(whole_4 ${deck} 4 HORIZON_MPI_LOCAL_PARTICLES=0)
same_history(local_4 whole_4)

# Checkpoints with local particles.
file(READ ${deck} text)
string(REPLACE "damage_measure: volume}" "damage_measure: volume, checkpoint: {every: 200}}" text "${text}")
file(WRITE ${WORK}/checkpoint.yaml "${text}")
# Written in windows of a few hundred global ids (HORIZON_CHECKPOINT_CHUNK: rank 0 takes
# each record from the owners window by window, parallel/checkpoint_stream.hpp).
run(checkpoint_3 ${WORK}/checkpoint.yaml 3 HORIZON_CHECKPOINT_CHUNK=4096)
string(JSON local GET "${checkpoint_3_summary}" particles_local)
if(NOT local)
  message(FATAL_ERROR "a deck with checkpoints does not hold local particles")
endif()
same_crc(checkpoint_3 serial)
run(reference_3 ${deck} 3)
same_history(checkpoint_3 reference_3)
run(checkpoint_whole_3 ${WORK}/checkpoint.yaml 3 HORIZON_MPI_LOCAL_PARTICLES=0)
file(SHA256 ${WORK}/checkpoint_3/checkpoint.hzc local_sum)
file(SHA256 ${WORK}/checkpoint_whole_3/checkpoint.hzc whole_sum)
if(NOT local_sum STREQUAL whole_sum)
  message(FATAL_ERROR "the checkpoint of local particles differs from HORIZON_MPI_LOCAL_PARTICLES=0's")
endif()
foreach(ranks 2 4)
  file(COPY ${WORK}/checkpoint_3/ DESTINATION ${WORK}/restart_${ranks})
  # 2 ranks: the restart's row offsets and list places summed in windows of 512 ids.
  set(env "")
  if(ranks EQUAL 2)
    set(env HORIZON_CHECKPOINT_CHUNK=4096)
  endif()
  run(restart_${ranks} ${WORK}/checkpoint.yaml ${ranks} ${env} -- --restart ${WORK}/restart_${ranks}/checkpoint.hzc)
  same_crc(restart_${ranks} checkpoint_3)
  same_history(restart_${ranks} checkpoint_3)
  # The restart holds local particles: each rank its own and those its rows read.
  string(JSON local GET "${restart_${ranks}_summary}" particles_local)
  if(NOT local)
    message(FATAL_ERROR "the restart on ${ranks} ranks does not hold local particles")
  endif()
  set(held_list "")
  math(EXPR last "${ranks} - 1")
  foreach(k RANGE ${last})
    string(JSON held GET "${restart_${ranks}_summary}" halo ${k} particles_held)
    if(NOT held LESS total)
      message(FATAL_ERROR "the restart on ${ranks} ranks: rank ${k} holds ${held} particles of ${total}")
    endif()
    string(APPEND held_list " ${held}")
  endforeach()
  message(STATUS "checkpoint of 3 ranks restarted on ${ranks} (particles held per rank of ${total}:${held_list}): identical")
endforeach()

# Rank 0 cannot open the checkpoint's temporary file (a directory of that name): every
# rank stops with an error naming it (rank 0 still takes its part in the streamed
# writing), none hangs.
file(MAKE_DIRECTORY ${WORK}/unwritable/checkpoint.hzc.tmp)
execute_process(COMMAND ${MPIEXEC} --oversubscribe -n 3 ${HORIZON} run ${WORK}/checkpoint.yaml -q -o ${WORK}/unwritable
                        --threads 1
                RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log TIMEOUT 120)
if(rc EQUAL 0 OR NOT log MATCHES "cannot open '[^']*checkpoint.hzc.tmp' for writing")
  message(FATAL_ERROR "a checkpoint rank 0 cannot write: exit ${rc}, expected an error naming the file:\n${log}")
endif()
message(STATUS "a checkpoint rank 0 cannot write stops the run on every rank (exit ${rc})")
file(REMOVE_RECURSE ${WORK})
