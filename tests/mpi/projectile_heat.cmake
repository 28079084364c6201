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
restart_on_three(heat ${WORK}/heat.yaml)
file(REMOVE_RECURSE ${WORK})
