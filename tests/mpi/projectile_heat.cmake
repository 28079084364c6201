# Rigid projectiles and heat conduction split over ranks (docs/design.md "Running on
# several ranks"), each with the same bytes at any rank count (tests/mpi/same_bytes.cmake:
# history.csv, state_crc32 and the summary's energy, damage and loads, between the MPI
# runs on 1, 2, 3 and 4 ranks; state_crc32 equal to the serial program's):
#  - tests/mpi/projectile.yaml: a free rigid sphere into a cylinder that cracks (the
#    contact force on the body a grid sum in both programs, every rank advancing the same
#    body). It must break bonds and slow the sphere; its 2-rank checkpoint restarted on 3
#    ranks gives the uninterrupted run's history.csv and state_crc32 (the body's state
#    replicated in the checkpoint).
#  - tests/mpi/heat.yaml: a quenched plate with explicit heat conduction (each rank
#    advances its owned temperatures and receives its ghosts'), thermal strain and a
#    temperature-dependent critical stretch, every kind of thermal boundary. It must
#    cool, crack and close its heat balance; its 2-rank checkpoint restarted on 3 ranks
#    likewise (the temperatures and thermal strains gathered from their owners).
#    The same deck with the backward-Euler heat step (a distributed conjugate gradient,
#    thermal/heat.cpp) on 1-4 ranks, equal to the serial program (state_crc32 and
#    temperature_crc32).
#  - the heat deck as heat conduction alone (solver.type heat), forward Euler on 3 ranks,
#    backward Euler on 2 and 4 (the CG's bits on 1-4 ranks are the coupled deck's):
#    thermal.temperature_crc32 of every MPI run equal to the serial program's, history.csv
#    the same bytes between MPI runs, local particles.
# Both decks hold local particles on 4 ranks (summary.json particles_local; the heat
# deck's ranks at most 60 % of the plate each).
# cmake -DHORIZON=... -DSERIAL=... -DMPIEXEC=... -DSOURCE=... -DWORK=... -P projectile_heat.cmake
include(${CMAKE_CURRENT_LIST_DIR}/same_bytes.cmake)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

# The projectile, with a checkpoint every 200 steps.
file(READ ${SOURCE}/tests/mpi/projectile.yaml text)
string(REPLACE "damage_measure: volume}" "damage_measure: volume, checkpoint: {every: 200}}" text "${text}")
file(WRITE ${WORK}/projectile.yaml "${text}")
same_bytes(projectile ${WORK}/projectile.yaml 1x1 2x1 3x1 4x1)
string(JSON broken GET "${projectile_summary}" damage broken_bonds)
string(JSON v0 GET "${projectile_summary}" projectiles ball initial_speed)
string(JSON v1 GET "${projectile_summary}" projectiles ball final_speed)
if(broken LESS 100 OR NOT v1 LESS v0)
  message(FATAL_ERROR "the projectile deck must break bonds (${broken}) and slow the sphere (${v0} to ${v1} m/s)")
endif()
message(STATUS "projectile: ${broken} broken bonds, the sphere from ${v0} to ${v1} m/s")

# local_on_four(label limit_percent): the 4-rank run of `label` held local particles, each
# rank at most limit_percent of them (100: only that some rank holds fewer than all).
function(local_on_four label limit)
  file(READ ${WORK}/${label}_4x1/summary.json summary)
  string(JSON local GET "${summary}" particles_local)
  string(JSON total GET "${summary}" particles)
  if(NOT local)
    message(FATAL_ERROR "${label}: 4 ranks did not hold local particles (particles_local ${local})")
  endif()
  set(shares "")
  set(fewest ${total})
  foreach(k RANGE 3)
    string(JSON held GET "${summary}" halo ${k} particles_held)
    math(EXPR percent "100 * ${held} / ${total}")
    string(APPEND shares " ${held}")
    if(percent GREATER limit)
      message(FATAL_ERROR "${label}: rank ${k} holds ${held} of ${total} particles (${percent} %), more than ${limit} %")
    endif()
    if(held LESS fewest)
      set(fewest ${held})
    endif()
  endforeach()
  if(NOT fewest LESS total)
    message(FATAL_ERROR "${label}: every one of 4 ranks holds all ${total} particles")
  endif()
  message(STATUS "${label}: local particles on 4 ranks, held of ${total}:${shares}")
endfunction()
local_on_four(projectile 100)
restart_on_three(projectile ${WORK}/projectile.yaml)

# The heat deck, with a checkpoint every 100 steps.
file(READ ${SOURCE}/tests/mpi/heat.yaml text)
string(REPLACE "history_every: 20}" "history_every: 20, checkpoint: {every: 100}}" text "${text}")
file(WRITE ${WORK}/heat.yaml "${text}")
same_bytes(heat ${WORK}/heat.yaml 1x1 2x1 3x1 4x1)
string(JSON broken GET "${heat_summary}" damage broken_bonds)
string(JSON tmin GET "${heat_summary}" thermal temperature_min)
string(JSON balance GET "${heat_summary}" thermal heat_balance_error)
if(broken LESS 10 OR NOT tmin LESS 593 OR balance GREATER 1e-9 OR balance LESS -1e-9)
  message(FATAL_ERROR "the heat deck must crack (${broken} broken bonds), cool (lowest ${tmin} K) and close its "
                      "heat balance (${balance})")
endif()
message(STATUS "heat: ${broken} broken bonds, lowest temperature ${tmin} K, heat balance ${balance}")
local_on_four(heat 60)
restart_on_three(heat ${WORK}/heat.yaml)

# The heat deck with the backward-Euler heat step.
file(READ ${SOURCE}/tests/mpi/heat.yaml text)
string(REPLACE "time_scale: 5000" "time_scale: 5000\n  integration: implicit" text "${text}")
file(WRITE ${WORK}/heat_implicit.yaml "${text}")
same_bytes(heat_implicit ${WORK}/heat_implicit.yaml 1x1 2x1 3x1 4x1)
file(READ ${WORK}/heat_implicit_serial/summary.json serial_summary)
string(JSON serial_t GET "${serial_summary}" thermal temperature_crc32)
string(JSON t GET "${heat_implicit_summary}" thermal temperature_crc32)
string(JSON broken GET "${heat_implicit_summary}" damage broken_bonds)
string(JSON balance GET "${heat_implicit_summary}" thermal heat_balance_error)
if(NOT t EQUAL serial_t OR broken LESS 10 OR balance GREATER 1e-9 OR balance LESS -1e-9)
  message(FATAL_ERROR "the implicit heat deck: temperature_crc32 ${t} (serial ${serial_t}), ${broken} broken bonds, "
                      "heat balance ${balance}")
endif()
message(STATUS "heat_implicit: temperature_crc32 ${t} = serial, ${broken} broken bonds, heat balance ${balance}")

# Heat conduction alone (solver.type heat, its own driver), forward and backward Euler:
# the serial program's temperatures at every rank count, and the same history.csv.
# heat_alone(label deck ranks...): the serial program, then the MPI program on each count.
function(heat_alone label deck)
  set(reference "")
  foreach(run serial ${ARGN})
    set(out ${WORK}/${label}_${run})
    if(run STREQUAL "serial")
      set(command ${SERIAL} run ${deck} -q -o ${out} --threads 1)
    else()
      set(command ${MPIEXEC} --oversubscribe -n ${run} ${HORIZON} run ${deck} -q -o ${out} --threads 1)
    endif()
    execute_process(COMMAND ${command} RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${label}, ${run}: exit ${rc}\n${log}")
    endif()
    file(READ ${out}/summary.json summary)
    file(READ ${out}/history.csv history)
    string(JSON t GET "${summary}" thermal temperature_crc32)
    string(JSON balance GET "${summary}" thermal heat_balance_error)
    if(balance GREATER 1e-9 OR balance LESS -1e-9)
      message(FATAL_ERROR "${label}, ${run}: heat balance ${balance}")
    endif()
    if(run STREQUAL "serial")
      set(serial_t ${t})
      continue()
    endif()
    string(JSON ranks GET "${summary}" ranks)
    if(NOT t EQUAL serial_t OR NOT ranks EQUAL run)
      message(FATAL_ERROR "${label}: ${run} ranks (summary: ${ranks}) end in temperature_crc32 ${t}, the serial "
                          "program in ${serial_t}")
    endif()
    if(run GREATER 1)  # local particles: each rank some of the plate
      string(JSON local GET "${summary}" particles_local)
      string(JSON total GET "${summary}" particles)
      string(JSON held GET "${summary}" particles_held 0)
      if(NOT local OR NOT held LESS total)
        message(FATAL_ERROR "${label}, ${run} ranks: particles_local ${local}, rank 0 holds ${held} of ${total}")
      endif()
    endif()
    if(reference STREQUAL "")
      set(reference "${history}")
    elseif(NOT history STREQUAL reference)
      message(FATAL_ERROR "${label}: history.csv on ${run} ranks differs from the first MPI run's (${out})")
    endif()
  endforeach()
  message(STATUS "${label}: temperature_crc32 ${t} serial and the MPI program on ${ARGN} ranks, heat balance ${balance}")
  set(${label}_summary "${summary}" PARENT_SCOPE)
endfunction()
file(READ ${SOURCE}/tests/mpi/heat.yaml text)
string(REGEX REPLACE "solver:[^\n]*" "solver: {type: heat, end_time: 0.2}" text "${text}")
string(REPLACE "expansion: 7.5e-6, " "" text "${text}")
string(REPLACE "  time_scale: 5000\n" "" text "${text}")
file(WRITE ${WORK}/heat_alone.yaml "${text}")
heat_alone(heat_alone ${WORK}/heat_alone.yaml 3)
string(REPLACE "initial_temperature: 593" "initial_temperature: 593\n  integration: implicit" text "${text}")
string(REPLACE "end_time: 0.2}" "end_time: 0.2, time_step: 0.01}" text "${text}")
file(WRITE ${WORK}/heat_alone_implicit.yaml "${text}")
heat_alone(heat_alone_implicit ${WORK}/heat_alone_implicit.yaml 2 4)
string(JSON iterations GET "${heat_alone_implicit_summary}" thermal cg_iterations_last_step)
if(iterations LESS 2)
  message(FATAL_ERROR "heat_alone_implicit: ${iterations} conjugate-gradient iterations in the last step")
endif()
# Steady solves (thermal.integration: steady, one per step of 0.05 s): the same bits at
# every rank count, and the boundaries' flows in balance (no heat is stored).
string(REPLACE "integration: implicit" "integration: steady" text "${text}")
string(REPLACE "time_step: 0.01}" "time_step: 0.05}" text "${text}")
file(WRITE ${WORK}/heat_alone_steady.yaml "${text}")
heat_alone(heat_alone_steady ${WORK}/heat_alone_steady.yaml 2 4)
file(REMOVE_RECURSE ${WORK})
